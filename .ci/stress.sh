#!/bin/sh
# .ci/stress.sh — runs `mosaic stress` with a fixed seed for about a minute.
#
# Takes: the environment MOSAIC_STRESS_MINUTES (default 1), MOSAIC_STRESS_SEED (default 2026),
# MOSAIC_STRESS_BUILD (a configured build directory; default build/ci when the CI has configured
# it, else build/stress, configured here as a Release build) and MOSAIC_JOBS (default 2).
# Gives: exit status 0 when every frame passed; 1 otherwise, with the reduced failing .tris
# files in <build>/stress-failures/ (replay one with the `mosaic render` line at its top).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
minutes=${MOSAIC_STRESS_MINUTES:-1}
seed=${MOSAIC_STRESS_SEED:-2026}
jobs=${MOSAIC_JOBS:-2}

start=$(date +%s)
if [ -n "${MOSAIC_STRESS_BUILD:-}" ]; then
  build=$MOSAIC_STRESS_BUILD
elif [ -f "$root/build/ci/build.ninja" ]; then
  build=$root/build/ci  # the CI's own Release build: only mosaic_cli may need linking
else
  build=$root/build/stress
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOSAIC_BUILD_TESTS=OFF \
    -DMOSAIC_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" -j "$jobs" --target mosaic_cli
built=$(date +%s)
mkdir -p "$build/stress-failures"
status=0
"$build/engine/mosaic" stress --seed "$seed" --minutes "$minutes" --threads 2 \
  --out-dir "$build/stress-failures" || status=$?
end=$(date +%s)
echo "stress.sh: build $((built - start)) s, stress $((end - built)) s"
exit $status
