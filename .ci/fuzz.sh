#!/bin/sh
# .ci/fuzz.sh — builds the libFuzzer targets (tests/fuzz) with clang-14 under AddressSanitizer and
# UndefinedBehaviorSanitizer, then runs each for a bounded time on its kept corpus.
#
# Takes: the environment MOSAIC_FUZZ_SECONDS (per fuzzer, default 60), MOSAIC_FUZZ_BUILD (build
# directory, default build/fuzz), MOSAIC_JOBS (default 2) and MOSAIC_FUZZ_GROW (default 0).
# Gives: exit status 0 when no fuzzer found anything; otherwise 1, with the crashing input saved
# as <build>/<fuzzer>-crash-* (turn it into a regression test, and add it to
# tests/fuzz/corpus/<fuzzer>/).
# By default the kept corpus is read, never written: new inputs go to a scratch directory that is
# removed. The long campaign, MOSAIC_FUZZ_GROW=1 MOSAIC_FUZZ_SECONDS=480 .ci/fuzz.sh, instead
# merges (-merge=1) the kept corpus and what the run found into a fresh, minimal corpus and puts
# it in tests/fuzz/corpus/<fuzzer>/, ready to commit.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${MOSAIC_FUZZ_BUILD:-$root/build/fuzz}
seconds=${MOSAIC_FUZZ_SECONDS:-60}
jobs=${MOSAIC_JOBS:-2}
grow=${MOSAIC_FUZZ_GROW:-0}

# Longest input per fuzzer: fuzz_pipeline reads an 8-byte header, up to 8192 vertices of 16 bytes
# and 8160 index bytes; without it libFuzzer stays near the kept corpus's largest file. The parser
# fuzzer keeps libFuzzer's default.
max_len() { [ "$1" = fuzz_pipeline ] && echo "-max_len=$((8 + 8192 * 16 + 8160))"; }

start=$(date +%s)
# The fuzz preset (CMakePresets.json): clang-14, ASan + UBSan + libFuzzer instrumentation.
cmake --preset fuzz -B "$build" >/dev/null
cmake --build "$build" -j "$jobs" --target fuzz_scene_parsers fuzz_pipeline
echo "fuzz.sh: build took $(($(date +%s) - start)) s"

status=0
for fuzzer in fuzz_scene_parsers fuzz_pipeline; do
  scratch=$(mktemp -d)
  t0=$(date +%s)
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: a leak or a blow-up is a finding.
  # shellcheck disable=SC2046 # max_len prints one word or none
  if ! "$build/tests/fuzz/$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      $(max_len "$fuzzer") -print_final_stats=1 -artifact_prefix="$build/$fuzzer-" \
      "$scratch" "$root/tests/fuzz/corpus/$fuzzer" 2>"$build/$fuzzer.log"; then
    tail -n 40 "$build/$fuzzer.log"
    echo "fuzz.sh: $fuzzer FAILED; the input is in $build/$fuzzer-*"
    status=1
  fi
  grep -E "^stat::number_of_executed_units|^stat::new_units_added" "$build/$fuzzer.log" | tr '\n' ' '
  echo "fuzz.sh: $fuzzer ran $(($(date +%s) - t0)) s"
  if [ "$grow" = 1 ] && [ "$status" = 0 ]; then
    merged=$(mktemp -d)
    # shellcheck disable=SC2046
    "$build/tests/fuzz/$fuzzer" -merge=1 $(max_len "$fuzzer") "$merged" \
      "$root/tests/fuzz/corpus/$fuzzer" "$scratch" 2>"$build/$fuzzer-merge.log"
    rm -rf "$root/tests/fuzz/corpus/$fuzzer"
    mv "$merged" "$root/tests/fuzz/corpus/$fuzzer"
    echo "fuzz.sh: $fuzzer corpus merged: $(ls "$root/tests/fuzz/corpus/$fuzzer" | wc -l) inputs"
  fi
  rm -rf "$scratch"
done
echo "fuzz.sh: total $(($(date +%s) - start)) s"
exit $status
