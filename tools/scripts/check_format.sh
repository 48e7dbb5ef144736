#!/usr/bin/env bash
# clang-format (the repository's .clang-format) over every tracked C++ source and header; a file
# that formatting would change fails the check. Usage: tools/scripts/check_format.sh [--fix]
#   --fix: format the files in place instead.
set -euo pipefail
cd "$(dirname "$0")/../.."
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.hpp' '*.cc')
if [[ "${1:-}" == "--fix" ]]; then
  printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -n 50 clang-format -i
  echo "check_format: formatted ${#files[@]} files"
  exit 0
fi
if printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -n 50 clang-format --dry-run -Werror; then
  echo "check_format: ${#files[@]} files clean"
else
  echo "check_format: files above need tools/scripts/check_format.sh --fix" >&2
  exit 1
fi
