#!/usr/bin/env bash
# Formats every tracked C++ file (*.cpp, *.h under git) in place with .clang-format.
#   scripts/format.sh           format in place
#   scripts/format.sh --check   change nothing; list the files that are not formatted and exit 1
#                               if there is any (clang-format --dry-run --Werror)
# clang-format 14 (Debian 12's clang-format package; ./run.sh installs it): other versions
# format some constructs differently, so the version is checked.
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT="${CLANG_FORMAT:-clang-format}"
case "${1:-}" in
  "") check=0 ;;
  --check) check=1 ;;
  -h|--help) sed -n 2,7p "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "format.sh: unknown option '$1' (--check | --help)" >&2; exit 2 ;;
esac
command -v "$CLANG_FORMAT" >/dev/null || { echo "format.sh: $CLANG_FORMAT not found (apt-get install clang-format)" >&2; exit 2; }
version=$("$CLANG_FORMAT" --version | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
[ "$version" = 14 ] || { echo "format.sh: clang-format 14 wanted, found '$("$CLANG_FORMAT" --version)'" >&2; exit 2; }
mapfile -t files < <(git ls-files -- '*.cpp' '*.h')
if [ "$check" = 0 ]; then
  "$CLANG_FORMAT" -i --style=file "${files[@]}"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$CLANG_FORMAT" --style=file --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "format.sh: ${#bad[@]} of ${#files[@]} files are not formatted (scripts/format.sh fixes them):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "format.sh: all ${#files[@]} C++ files formatted"
