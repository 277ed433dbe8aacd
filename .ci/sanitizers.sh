#!/bin/sh
# .ci/sanitizers.sh — the test suite under AddressSanitizer + UndefinedBehaviorSanitizer, and the
# multithreaded tests under ThreadSanitizer, with the CMakePresets.json presets asan-ubsan
# (build/asan) and tsan (build/tsan).
#
# The asan-ubsan preset compiles at -O1 -g1 (line tables, all a sanitizer report needs): the tile
# kernel files are large template instantiations, and at -O2 -g one took more than 7 minutes to
# compile under the sanitizers, at -O1 -g 8.5 minutes, at -O1 -g1 under 3.
#
# Takes: the environment MOSAIC_JOBS (default 2). Gives: exit status 0 when both runs pass; the
# first failing step's status otherwise (its sanitizer report is in the ctest output).
#
# ThreadSanitizer and oneTBB (investigated; see .ci/tsan.supp): Debian's libtbb is not built with
# -fsanitize=thread, so TSan cannot see the happens-before edges of task spawn, stealing and
# join, which live in libtbb's atomics. The result is hundreds of false reports whose stacks are
# mosaic code (front-end counters read after the join, tile data handed from the binning phase to
# the raster phase) and oneTBB header templates compiled into mosaic (blocked_range, start_for).
# A suppression cannot tell them from real races: TSan matches every frame, and every mosaic task
# runs below libtbb frames. So the TSan step runs only with MOSAIC_TSAN=1, for a libtbb that is
# TSan-instrumented (or once frame.cpp annotates its fork/join points with __tsan_release /
# __tsan_acquire); with Debian's libtbb it reports (e.g. 689 reports for test_hard_depth, and
# 9 minutes instead of 0.2 s) and fails.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
jobs=${MOSAIC_JOBS:-2}

# The multithreaded tests: every test that renders with more than one worker thread or compares
# thread counts (the fast path against the reference, z-fighting across 1/2/7 threads, the
# stress tool, the hard cases on every SIMD path).
tsan_targets="test_fast_path test_hard_depth test_hard_watertight test_hard_nonfinite test_stress mosaic_cli"
tsan_tests='^(FastPath|HardDepth|HardWatertight|HardNonFinite|Stress[A-Za-z]*)\.'

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

if [ "${MOSAIC_TSAN:-0}" != 1 ]; then
  echo "sanitizers.sh: tsan skipped (set MOSAIC_TSAN=1; Debian's libtbb is not TSan-instrumented)"
  echo "sanitizers.sh: total $((asan_done - start)) s"
  exit 0
fi
cmake --preset tsan >/dev/null
# shellcheck disable=SC2086 # the target list is meant to split
cmake --build --preset tsan -j "$jobs" --target $tsan_targets
tbuilt=$(date +%s)
TSAN_OPTIONS="suppressions=$root/.ci/tsan.supp halt_on_error=1 second_deadlock_stack=1" \
  ctest --test-dir build/tsan -j "$jobs" --output-on-failure --timeout 900 -R "$tsan_tests"
end=$(date +%s)
echo "sanitizers.sh: tsan build $((tbuilt - asan_done)) s, tests $((end - tbuilt)) s; total $((end - start)) s"
