#!/bin/sh
# compare-tile-sizes.sh — which screen tile size gives the best modelled 16-core frame.
#
# Takes: optional scene names (default: every built-in scene and corner); the environment may
# set MOSAIC_TILE_SIZES (default "16 32 64 128"), MOSAIC_JOBS (build jobs, default 2) and
# MOSAIC_SCALING_ARGS (more mosaic-scaling options, e.g. "--frames 11 --samples 1,4,16").
# Gives: the Release build of mosaic-scaling in build/release, each size's tables and JSON per
# scene in build/release/tile-sizes/<scene>-<N>.{md,json}, and on stdout the table of modelled
# 16-core times per tile size with the real 1- and 2-thread times.
# The tile size is a renderer option (mosaic-scaling --tile-size), so one build serves every
# size. Runs go scene by scene through every size, so that a change in the machine's load
# between scenes does not favour one size.
set -eu

root=$(cd "$(dirname "$0")/../.." && pwd)
sizes=${MOSAIC_TILE_SIZES:-"16 32 64 128"}
jobs=${MOSAIC_JOBS:-2}
if [ "$#" -gt 0 ]; then
  scenes="$*"
else
  scenes="default random-small random-large slivers star fan corner"
fi

build="$root/build/release"
(cd "$root" && cmake --preset release >/dev/null)
cmake --build "$build" -j "$jobs" --target mosaic_scaling >&2
out="$build/tile-sizes"
mkdir -p "$out"

jsons=""
for scene in $scenes; do
  for n in $sizes; do
    echo "== $scene, tile size $n" >&2
    # shellcheck disable=SC2086 # MOSAIC_SCALING_ARGS is a list of options
    "$build/mosaic-scaling" --scenes "$scene" --tile-size "$n" --json "$out/$scene-$n.json" \
      ${MOSAIC_SCALING_ARGS:-} >"$out/$scene-$n.md" 2>/dev/null
    jsons="$jsons $out/$scene-$n.json"
  done
done

# shellcheck disable=SC2086 # one argument per JSON file
"$build/mosaic-scaling" --compare $jsons --compare-cores 16
