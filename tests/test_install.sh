#!/bin/sh
# tests/test_install.sh — the installed mosaic package, used as a program outside this build would.
#
# Takes: STEP BUILD_DIR SOURCE_DIR WORK_DIR CONFIG VERSION CMAKE GENERATOR MAKE_PROGRAM CXX
# CXX_FLAGS (tests/CMakeLists.txt passes its own build's values, so the examples are built with
# the same generator, compiler and flags, sanitizers included). Gives: exit 0 if STEP passes.
#   install   `cmake --install BUILD_DIR --prefix WORK_DIR/prefix`, and checks what it put there
#   cmake     configures the installed examples (share/mosaic/examples, a copy of engine/examples)
#             with find_package(mosaic CONFIG) from that prefix only,
#             builds every example with warnings as errors, runs them, and checks their images
#   pkgconfig builds the installed examples/hello_triangle with `pkg-config --cflags --libs mosaic`
#   headers   compiles <mosaic/mosaic.hpp> from the installed include folder with warnings as
#             errors, and checks that no xsimd or oneTBB header or name reaches it
# The steps after `install` need it to have run (a ctest fixture).
set -eu

# CXX_FLAGS may be empty, and ctest drops an empty last argument.
[ $# -eq 10 ] || [ $# -eq 11 ] || { echo "usage: $0 STEP BUILD SOURCE WORK CONFIG VERSION CMAKE GENERATOR MAKE CXX FLAGS" >&2; exit 2; }
step=$1 build=$2 source=$3 work=$4 config=$5 version=$6 cmake=$7 generator=$8 make_program=$9
shift 9
cxx=$1 cxx_flags=${2:-}
prefix=$work/prefix
# The examples must compile as cleanly as the library: the same warnings as mosaic_flags.
warnings="-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Werror"

fail() {
  echo "test_install ($step): $*" >&2
  exit 1
}

# Runs a command with its output in a log, shown only if it fails.
quiet() {
  log=$work/last-$step.log
  if ! "$@" >"$log" 2>&1; then
    cat "$log" >&2
    fail "command failed: $*"
  fi
}

# hello_triangle's image, decoded from PPM: 256×256, background (24, 24, 32), triangle corners
# at (±0.8, -0.8) and (0, 0.8) in NDC. Its area is 0.5 · 204.8 · 204.8 = 20971.5 px², 32.0% of
# the image; 4x MSAA also tints the ~660 pixels its 663 px of edges cross, about half of them
# outside it (+0.5%). So 30% to 35% of the pixels differ from the background, and each corner's
# pure primary appears near that corner.
check_hello_ppm() {
  file=$1
  [ -s "$file" ] || fail "$file was not written"
  header_bytes=$(printf 'P6\n256 256\n255\n' | wc -c)
  [ "$(head -c "$header_bytes" "$file" | od -An -c | tr -d ' \n')" = 'P6\n256256\n255\n' ] ||
    fail "$file: not a 256x256 binary PPM"
  counts=$(od -An -v -tu1 -j "$header_bytes" "$file" | awk '
    { for (i = 1; i <= NF; ++i) { c[n % 3] = $i; ++n
        if (n % 3 == 0) {
          ++total
          if (c[0] != 24 || c[1] != 24 || c[2] != 32) ++lit
          if (c[0] > 200 && c[1] < 40 && c[2] < 40) ++red
          if (c[1] > 200 && c[0] < 40 && c[2] < 40) ++green
          if (c[2] > 200 && c[0] < 40 && c[1] < 40) ++blue } } }
    END { printf "%d %d %d %d %d", total, lit, red, green, blue }')
  set -- $counts
  [ "$1" -eq 65536 ] || fail "$file: $1 pixels, expected 65536"
  # 30% and 35% of 65536 pixels.
  [ "$2" -ge 19661 ] && [ "$2" -le 22938 ] ||
    fail "$file: $2 of 65536 pixels differ from the background, expected 30% to 35%"
  [ "$3" -gt 0 ] && [ "$4" -gt 0 ] && [ "$5" -gt 0 ] ||
    fail "$file: missing a pure corner colour (red $3, green $4, blue $5 pixels)"
}

# A PNG file: the signature, an IHDR of the expected size, and more than MIN_BYTES. stb writes a
# flat 256×256 image in 2.8 KiB and a flat 160×90 one in 0.7 KiB (measured); the examples' images
# are 9.8 KiB (hello_triangle), 14 KiB (scene_stats, 320×180), 6 KiB (orbit, 160×90), 1.3 KiB
# (city_occlusion, 160×90, large flat walls), 55 KiB and 8.5 KiB (textured, 320×180, trilinear
# and nearest), so the thresholds of 4 KiB, 2 KiB and 1000 bytes tell an image with content from
# a flat one.
check_png() {
  file=$1 width=$2 height=$3 min_bytes=$4
  [ -s "$file" ] || fail "$file was not written"
  [ "$(od -An -tu1 -N 8 "$file" | tr -s ' ' | sed 's/^ //; s/ $//')" = '137 80 78 71 13 10 26 10' ] ||
    fail "$file: no PNG signature"
  # IHDR width and height: big-endian 32-bit at offsets 16 and 20.
  size=$(od -An -tu1 -j 16 -N 8 "$file" |
    awk '{ printf "%d %d", (($1 * 256 + $2) * 256 + $3) * 256 + $4, (($5 * 256 + $6) * 256 + $7) * 256 + $8 }')
  [ "$size" = "$width $height" ] || fail "$file: PNG is $size, expected $width $height"
  bytes=$(wc -c <"$file")
  [ "$bytes" -gt "$min_bytes" ] || fail "$file: only $bytes bytes, looks empty"
}

case $step in
install)
  rm -rf "$work"
  mkdir -p "$work"
  quiet "$cmake" --install "$build" --config "$config" --prefix "$prefix"
  for f in include/mosaic/mosaic.hpp bin/mosaic share/mosaic/examples/CMakeLists.txt \
    share/mosaic/examples/hello_triangle/main.cpp; do
    [ -e "$prefix/$f" ] || fail "$prefix/$f was not installed"
  done
  for f in libmosaic.a mosaicConfig.cmake mosaicConfigVersion.cmake mosaicTargets.cmake mosaic.pc; do
    [ -n "$(find "$prefix" -name "$f")" ] || fail "$f was not installed under $prefix"
  done
  # Only the public API is installed: no internal header of engine/src.
  extra=$(find "$prefix/include" -type f ! -path "$prefix/include/mosaic/*.hpp")
  [ -z "$extra" ] || fail "unexpected files in the installed include folder: $extra"
  quiet "$prefix/bin/mosaic" scenes
  ;;

cmake)
  rm -rf "$work/examples"
  quiet "$cmake" -S "$prefix/share/mosaic/examples" -B "$work/examples" -G "$generator" \
    -DCMAKE_MAKE_PROGRAM="$make_program" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_BUILD_TYPE="$config" -DCMAKE_CXX_FLAGS="$cxx_flags $warnings" \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  # The package found must be the installed one, not this build tree.
  found=$(sed -n 's/^mosaic_DIR:PATH=//p' "$work/examples/CMakeCache.txt")
  case $found in
  "$prefix"/*) ;;
  *) fail "find_package(mosaic) found '$found', not the package under $prefix" ;;
  esac
  quiet "$cmake" --build "$work/examples" --config "$config" -j 2
  bin=$work/examples
  quiet "$bin/hello_triangle/hello_triangle" "$work/hello_cmake.png"
  check_png "$work/hello_cmake.png" 256 256 4096
  quiet "$bin/hello_triangle/hello_triangle" "$work/hello_cmake.ppm"
  check_hello_ppm "$work/hello_cmake.ppm"
  quiet "$bin/scene_stats/scene_stats" default --size 320 180 --frames 2 --out "$work/stats.png"
  grep -q '^scene default: 320x180' "$work/last-$step.log" || fail "scene_stats printed no stats"
  check_png "$work/stats.png" 320 180 4096
  rm -rf "$work/orbit"
  quiet "$bin/orbit/orbit" --frames 3 --size 160 90 --samples 4 --out-dir "$work/orbit"
  for f in 0 1 2; do check_png "$work/orbit/frame_000$f.png" 160 90 2048; done
  [ ! -e "$work/orbit/frame_0003.png" ] || fail "orbit wrote more frames than asked for"
  quiet "$bin/orbit/orbit" "$source/tests/data/cube.obj" --frames 2 --size 160 90 --no-images
  grep -q 'orbit: .*cube.obj, 12 triangles' "$work/last-$step.log" || fail "orbit did not load cube.obj"
  # The occlusion workflow at one size and one sample for both passes, where the queries'
  # guarantee makes the visible-only frame the very image of the full one.
  quiet "$bin/city_occlusion/city_occlusion" --blocks 6 --objects 500 --occluder-size 160 90 \
    --size 160 90 --samples 1 --repeat 1 --out "$work/city.png"
  grep -q '^queries: 500 boxes in .* hidden' "$work/last-$step.log" || fail "city_occlusion ran no queries"
  grep -q '^pixels that differ: 0 of 14400$' "$work/last-$step.log" ||
    fail "city_occlusion: culling hidden objects changed the image: $(grep differ "$work/last-$step.log")"
  check_png "$work/city.png" 160 90 1000
  # Textures and a discarding shader: mipmapped and point-sampled floors must differ.
  quiet "$bin/textured/textured" "$work/textured.png"
  grep -q '^textured: wrote .* 4 triangles drawn' "$work/last-$step.log" || fail "textured drew no quads"
  check_png "$work/textured.png" 320 180 4096
  quiet "$bin/textured/textured" --filter nearest "$work/textured_nearest.png"
  check_png "$work/textured_nearest.png" 320 180 4096
  ! cmp -s "$work/textured.png" "$work/textured_nearest.png" || fail "textured: --filter changed nothing"
  # The version file: the examples asked for 0.1 and got it; the next minor version must be
  # refused (before 1.0 a minor release may break the API).
  next=$(echo "$version" | awk -F. '{ printf "%d.%d", $1, $2 + 1 }')
  rm -rf "$work/version_check"
  mkdir -p "$work/version_check"
  printf '%s\n' 'cmake_minimum_required(VERSION 3.25)' 'project(version_check LANGUAGES CXX)' \
    "find_package(mosaic $next CONFIG REQUIRED)" >"$work/version_check/CMakeLists.txt"
  if "$cmake" -S "$work/version_check" -B "$work/version_check/build" -G "$generator" \
    -DCMAKE_MAKE_PROGRAM="$make_program" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_PREFIX_PATH="$prefix" >"$work/version_check.log" 2>&1; then
    fail "find_package(mosaic $next) accepted the installed version $version"
  fi
  grep -q "requested version \"$next\"" "$work/version_check.log" ||
    fail "find_package(mosaic $next) failed for another reason: $(cat "$work/version_check.log")"
  ;;

pkgconfig)
  pc=$(find "$prefix" -name mosaic.pc)
  PKG_CONFIG_PATH=$(dirname "$pc")${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
  export PKG_CONFIG_PATH
  [ "$(pkg-config --modversion mosaic)" = "$version" ] ||
    fail "pkg-config reports version $(pkg-config --modversion mosaic), expected $version"
  # The .pc file is relocatable: its include folder is the installed one.
  case $(pkg-config --variable=includedir mosaic) in
  "$(dirname "$pc")"/*) ;;
  *) fail "mosaic.pc points outside its install: $(pkg-config --variable=includedir mosaic)" ;;
  esac
  mkdir -p "$work/pkgconfig"
  # shellcheck disable=SC2046  # the flags are meant to be split into words
  quiet "$cxx" -std=c++20 $cxx_flags $warnings $(pkg-config --cflags mosaic) \
    "$prefix/share/mosaic/examples/hello_triangle/main.cpp" -o "$work/pkgconfig/hello_triangle" \
    $(pkg-config --libs mosaic)
  quiet "$work/pkgconfig/hello_triangle" "$work/hello_pkgconfig.png"
  check_png "$work/hello_pkgconfig.png" 256 256 4096
  quiet "$work/pkgconfig/hello_triangle" "$work/hello_pkgconfig.ppm"
  check_hello_ppm "$work/hello_pkgconfig.ppm"
  ;;

headers)
  mkdir -p "$work/headers"
  tu=$work/headers/public_api.cpp
  printf '%s\n' '#include <mosaic/mosaic.hpp>' \
    'int main() { return mosaic::RenderTarget(1, 1).width() - 1; }' >"$tu"
  # -I, not -isystem: a warning in a public header fails, as it would in a user's -Werror build.
  quiet "$cxx" -std=c++20 $warnings -I"$prefix/include" -fsyntax-only "$tu"
  # Every header the public API pulls in: none may belong to xsimd or oneTBB.
  quiet "$cxx" -std=c++20 -I"$prefix/include" -M "$tu"
  leaked=$(tr ' \\' '\n\n' <"$work/last-$step.log" | grep -E '/(xsimd|tbb|oneapi)/' | sort -u | head -n 5 || true)
  [ -z "$leaked" ] || fail "the public headers include xsimd or oneTBB: $leaked"
  # Nor may they name those libraries (a forward declaration needs no include).
  named=$(grep -nwE '(xsimd|tbb|oneapi)' "$prefix"/include/mosaic/*.hpp || true)
  [ -z "$named" ] || fail "the public headers name xsimd or oneTBB: $named"
  ;;

*)
  fail "unknown step"
  ;;
esac
