#!/bin/sh
# bench/run-benchmarks.sh — runs mosaic's benchmark suite and prints the README tables.
#
# Takes: an optional build directory (default build/release, the release preset's), in which
# the targets mosaic_bench and mosaic_bench_table are built; environment REPS (repetitions,
# default 7: the tables show medians), FILTER (a --benchmark_filter regex, default all) and
# OUT (the JSON file, default <build>/bench/bench-results.json).
# Gives: Google Benchmark's console table on stderr, the JSON in OUT, and the markdown tables on
# stdout. About 3 minutes on an idle 2-core machine with REPS=7, plus about 40 s for the three
# 1 M-triangle knot scenes.
# The repetitions of all cases are interleaved in random order, so that a burst of load from
# other work on the machine spreads over many cases instead of spoiling every repetition of one.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build/release"}
reps=${REPS:-7}
out=${OUT:-"$build/bench/bench-results.json"}
bench="$build/bench/mosaic-bench"
table="$build/bench/mosaic-bench-table"

for exe in "$bench" "$table"; do
  if [ ! -x "$exe" ]; then
    echo "run-benchmarks.sh: $exe is missing; build it first:" >&2
    echo "  cmake --preset release && cmake --build --preset release --target mosaic_bench mosaic_bench_table" >&2
    exit 1
  fi
done

"$bench" --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_enable_random_interleaving=true \
  --benchmark_out="$out" --benchmark_out_format=json \
  ${FILTER:+"--benchmark_filter=$FILTER"} >&2
"$table" "$out"
