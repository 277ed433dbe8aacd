#!/bin/sh
# bench/instructions/per-stage.sh — where a frame's instructions go: per triangle, per stage.
#
# Takes: a scene and `mosaic render` options (default: random-small --msaa 4); environment ISA,
# a `mosaic render --isa` value (default avx2; sse4.1 also runs: valgrind cannot run AVX-512).
# Gives: the table of per_stage.py on stdout.
# Builds the profile preset (Release flags with -g; the CLI only, in build/profile) and renders
# the frame once on one thread under callgrind: about a minute for 100k small triangles.
# Instruction counts repeat to within 0.05 % from run to run, so two versions of a kernel compare
# here where wall-clock times on a shared machine do not.
set -eu

root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
for tool in valgrind callgrind_annotate addr2line python3; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "per-stage.sh: $tool is missing; third_party/install-deps.sh installs it" >&2
    exit 1
  fi
done
cmake --preset profile >/dev/null
cmake --build --preset profile >/dev/null
bin="$root/build/profile/engine/mosaic"

[ $# -gt 0 ] || set -- random-small --msaa 4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file="$work/callgrind.out" \
  "$bin" render "$@" --isa "${ISA:-avx2}" --threads 1 --no-out --stats \
  >"$work/render.out" 2>"$work/valgrind.log"; then
  echo "per-stage.sh: mosaic render $* --isa ${ISA:-avx2} failed:" >&2
  grep -v '^==' "$work/valgrind.log" >&2  # the CLI's own messages, without valgrind's
  exit 1
fi
echo "mosaic render $* --isa ${ISA:-avx2} --threads 1 under callgrind:"
python3 "$root/bench/instructions/per_stage.py" "$work/callgrind.out" "$bin" \
  "$(tail -n 1 "$work/render.out")"
