#!/usr/bin/env bash
# scripts/check-format: a tree as .clang-format writes it passes, a file that differs fails and
# is named, and --fix rewrites it so that the check passes again.
set -euo pipefail
root=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "check_format_test: $*" >&2; exit 1; }

mkdir -p "$dir/scripts" "$dir/core/src"
cp "$root/scripts/check-format" "$dir/scripts/"
cp "$root/.clang-format" "$dir/"
printf 'int add(int a, int b) {\n  return a + b;\n}\n' > "$dir/core/src/good.cpp"
"$dir/scripts/check-format" >/dev/null || fail "a formatted file failed"

printf 'int  mul(int a,int b){return a*b;}\n' > "$dir/core/src/bad.cpp"
out=$("$dir/scripts/check-format" 2>&1) && fail "a file that differs passed"
grep -q "not clang-formatted: core/src/bad.cpp" <<<"$out" || fail "the file was not named: $out"
grep -q "good.cpp" <<<"$out" && fail "a formatted file was named: $out"

"$dir/scripts/check-format" --fix
"$dir/scripts/check-format" >/dev/null || fail "--fix left the file unformatted"
echo "check_format_test: ok"
