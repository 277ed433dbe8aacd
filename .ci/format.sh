#!/usr/bin/env bash
# Checks that every C++ source tracked by git is formatted by the project's .clang-format
# (clang-format 14, Debian's; installed by third_party/install-deps.sh). Fix with:
#   git ls-files '*.cpp' '*.hpp' | xargs clang-format-14 -i
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
clang-format-14 --dry-run -Werror "${files[@]}"
echo "format: ${#files[@]} files formatted as .clang-format says"
