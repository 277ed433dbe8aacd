#!/usr/bin/env bash
# Installs every build, test and benchmark dependency of mosaic from Debian 12 packages.
# Idempotent: packages already present are skipped, so running it again costs a few seconds.
# Nothing is vendored and nothing is downloaded at build time; this script is the only install step.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libtbb-dev            # oneTBB: task arena and parallel loops
  libxsimd-dev          # xsimd: portable SIMD batches for the tile kernels
  libglm-dev            # GLM: vectors and matrices in the public API
  libbenchmark-dev      # Google Benchmark: bench/
  libgtest-dev          # GoogleTest: tests/
  libstb-dev            # stb_image_write: PNG output
  libcli11-dev          # CLI11: command-line parsing
  nlohmann-json3-dev    # nlohmann/json: --stats and report JSON
  libegl-dev            # EGL headers: the llvmpipe peer (bench/peers/llvmpipe) runs surfaceless
  libegl-mesa0          # Mesa's EGL vendor library: EGL_MESA_platform_surfaceless
  libgl1-mesa-dri       # Mesa's gallium drivers, llvmpipe among them
  libgl-dev             # OpenGL headers (GL/glcorearb.h) and libOpenGL
  libfftw3-dev          # FFTW: spectra and aliasing energy in `mosaic report`
  libgmp-dev            # GMP rationals: exact triangle-pixel areas, the ground truth of `mosaic report`
  clang-14              # .ci/fuzz.sh: libFuzzer needs clang (GCC has no -fsanitize=fuzzer)
  clang-format-14       # .ci/format.sh: the sources follow .clang-format
  libclang-rt-14-dev    # clang's runtime libraries: libFuzzer, ASan and UBSan for clang-14
  valgrind              # bench/instructions: instructions per stage (callgrind)
  python3               # bench/instructions/per_stage.py, bench/obj/grid_obj.py
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
