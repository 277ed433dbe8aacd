#!/bin/sh
# compare-tile-sizes.sh — which screen tile size gives the best modelled 16-core frame.
#
# Takes: optional scene names (default: every built-in scene and corner); the environment may
# set MOSAIC_TILE_SIZES (default "16 32 64 128"), MOSAIC_JOBS (build jobs, default 2) and
# MOSAIC_SCALING_ARGS (more mosaic-scaling options, e.g. "--frames 11").
# Gives: one Release build per tile size in build/scaling-<N> (tests off, only mosaic-scaling),
# each build's tables and JSON per scene in build/scaling-<N>/scaling-<scene>.{md,json}, and on
# stdout the table of modelled 16-core times per tile size with the real 1- and 2-thread times.
# The tile size is a compile-time constant (MOSAIC_TILE_SIZE), hence one build per size. Runs
# go scene by scene through every size, so that a change in the machine's load between scenes
# does not favour one size.
set -eu

root=$(cd "$(dirname "$0")/../.." && pwd)
sizes=${MOSAIC_TILE_SIZES:-"16 32 64 128"}
jobs=${MOSAIC_JOBS:-2}
if [ "$#" -gt 0 ]; then
  scenes="$*"
else
  scenes="default random-small random-large slivers star fan corner"
fi

for n in $sizes; do
  dir="$root/build/scaling-$n"
  echo "== building tile size $n in $dir" >&2
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOSAIC_BUILD_TESTS=OFF \
    -DMOSAIC_TILE_SIZE="$n" >/dev/null
  cmake --build "$dir" -j "$jobs" --target mosaic_scaling >&2
done

jsons=""
for scene in $scenes; do
  for n in $sizes; do
    dir="$root/build/scaling-$n"
    echo "== $scene, tile size $n" >&2
    # shellcheck disable=SC2086 # MOSAIC_SCALING_ARGS is a list of options
    "$dir/mosaic-scaling" --scenes "$scene" --json "$dir/scaling-$scene.json" \
      ${MOSAIC_SCALING_ARGS:-} >"$dir/scaling-$scene.md" 2>/dev/null
    jsons="$jsons $dir/scaling-$scene.json"
  done
done

first=$(echo "$sizes" | cut -d' ' -f1)
# shellcheck disable=SC2086 # one argument per JSON file
"$root/build/scaling-$first/mosaic-scaling" --compare $jsons --compare-cores 16
