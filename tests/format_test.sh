#!/usr/bin/env bash
# Every C++ file of the tree is as clang-format 14 (Debian 12's) writes it with .clang-format; the files that are
# not are named, with the command that formats them. Another clang-format version formats differently: the test
# then skips, saying so. A self-test shows a misformatted file is caught.
# Usage: tests/format_test.sh SOURCE_DIR
set -uo pipefail
root="${1:?usage: format_test.sh SOURCE_DIR}"
cd "$root" || exit 2
cf="$(command -v clang-format-14 || command -v clang-format || true)"
if [ -z "$cf" ]; then
  echo "SKIP: clang-format not installed (bash scripts/setup.sh installs it)"
  exit 77
fi
major="$("$cf" --version | grep -o 'version [0-9]*' | grep -o '[0-9]*')"
if [ "$major" != "14" ]; then
  echo "SKIP: $cf is version $major; the tree is formatted by clang-format 14 (Debian 12), which formats differently"
  exit 77
fi
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
cp .clang-format "$scratch/"
printf 'int  f( int a ){return a;}\n' > "$scratch/planted.cpp"
if "$cf" --dry-run -Werror "$scratch/planted.cpp" >/dev/null 2>&1; then
  echo "FAIL: the self-test's misformatted file passed"
  exit 1
fi
if [ -d .git ] || git rev-parse --git-dir >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.h')
else
  mapfile -t files < <(find . -path ./build -prune -o \( -name '*.cpp' -o -name '*.h' \) -print | sed 's#^\./##')
fi
bad=()
for f in "${files[@]}"; do
  "$cf" --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "FAIL: ${#bad[@]} of ${#files[@]} files are not clang-format 14's: ${bad[*]}"
  echo "  format them: $cf -i ${bad[*]}"
  exit 1
fi
echo "all ${#files[@]} C++ files as clang-format $major writes them"
