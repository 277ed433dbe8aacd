#!/bin/sh
# .ci/sanitizers.sh — the test suite under AddressSanitizer + UndefinedBehaviorSanitizer, and the
# multithreaded tests under ThreadSanitizer, with the CMakePresets.json presets asan-ubsan
# (build/asan) and tsan (build/tsan).
#
# The asan-ubsan preset compiles at -O1 -g1 (line tables, all a sanitizer report needs): the tile
# kernel files are large template instantiations, and at -O2 -g one took more than 7 minutes to
# compile under the sanitizers, at -O1 -g 8.5 minutes, at -O1 -g1 under 3.
#
# Gives: exit status 0 when both runs pass; the first failing step's status otherwise (its
# sanitizer report is in the ctest output).
#
# ThreadSanitizer and oneTBB: Debian's libtbb is not built with -fsanitize=thread, so TSan cannot
# see the happens-before edges of task spawn, stealing and join, which live in libtbb's atomics.
# Without help it reports hundreds of false races (689 for test_hard_depth alone). Two pieces
# make it exact on mosaic's own code:
# - every parallel stage states its fork and join edges (engine/src/parallel/stage_edges.hpp:
#   __tsan_release before the stage and at each task's end, __tsan_acquire at each task's start
#   and after the join), compiled into TSan builds only;
# - .ci/tsan.supp ignores what libtbb itself calls and races whose innermost frame is oneTBB's,
#   never a pattern that could match a mosaic frame (see the file).
# The proof that nothing of mosaic's is hidden is a test: tests/tsan/seeded_race.cpp races in a
# shader on the tile workers, and TsanSeededRace.IsReported passes only if TSan reports it.
# The tsan preset builds the AVX2 path only (MOSAIC_SIMD_ISAS): the threading code is shared by
# every ISA, and the kernels are most of the compile time.
#
# Takes: the environment MOSAIC_JOBS (default 2) and MOSAIC_TSAN (default 1; 0 skips TSan).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
jobs=${MOSAIC_JOBS:-2}

# The multithreaded tests: every test that renders with more than one worker thread or compares
# thread counts (the fast path against the reference, z-fighting across 1/2/7 threads, shaders,
# occlusion queries, the stress tool, the soak, a renderer entered from two threads, the hard
# cases, the vertex stage's blocks), and the seeded race.
tsan_targets="test_fast_path test_hard_depth test_hard_watertight test_hard_nonfinite test_stress
  test_shaders test_shader_features test_texture test_occlusion test_soak test_api_errors
  test_vertex_stage tsan_seeded_race mosaic_cli"
tsan_tests='^(FastPath|HardDepth|HardWatertight|HardNonFinite|Stress[A-Za-z]*|Shader[A-Za-z]*|Textur[A-Za-z]*|Occlusion[A-Za-z]*|Soak|ApiErrors|VertexStage|TsanSeededRace)\.'

start=$(date +%s)
cmake --preset asan-ubsan >/dev/null
cmake --build --preset asan-ubsan -j "$jobs"
built=$(date +%s)
# detect_leaks: leaks fail the run; halt_on_error: the first UB report fails its test.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan -j "$jobs" --output-on-failure --timeout 900
asan_done=$(date +%s)
echo "sanitizers.sh: asan-ubsan build $((built - start)) s, tests $((asan_done - built)) s"

if [ "${MOSAIC_TSAN:-1}" != 1 ]; then
  echo "sanitizers.sh: tsan skipped (MOSAIC_TSAN=0)"
  echo "sanitizers.sh: total $((asan_done - start)) s"
  exit 0
fi
cmake --preset tsan >/dev/null
# shellcheck disable=SC2086 # the target list is meant to split
cmake --build --preset tsan -j "$jobs" --target $tsan_targets
tbuilt=$(date +%s)
# history_size=7, the longest history: TSan then restores the stack of an old access (oneTBB's
# atomics on the caller's stack, in a stage long before) so that .ci/tsan.supp can match it.
TSAN_OPTIONS="suppressions=$root/.ci/tsan.supp halt_on_error=1 second_deadlock_stack=1 history_size=7" \
  ctest --test-dir build/tsan -j "$jobs" --output-on-failure --timeout 900 -R "$tsan_tests"
end=$(date +%s)
echo "sanitizers.sh: tsan build $((tbuilt - asan_done)) s, tests $((end - tbuilt)) s; total $((end - start)) s"
