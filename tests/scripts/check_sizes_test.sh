#!/usr/bin/env bash
# scripts/check-sizes: a file over the limit, a function over it, a table excused by its
# comment, a known breach in the baseline, and a baseline line that is stale.
set -euo pipefail
root=$1
tool="$root/scripts/check-sizes"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "check_sizes_test: $*" >&2; exit 1; }

# A function of 101 lines (its signature, 99 body lines, its closing brace) and one of 100.
{
  echo 'int longOne(int x) {'
  for i in $(seq 99); do echo "  x += $i;"; done
  echo '}'
  echo 'int shortOne(int x) {'
  for i in $(seq 98); do echo "  x += $i;"; done
  echo '}'
  echo 'int table() {  // table'
  for i in $(seq 150); do echo "  // row $i"; done
  echo '}'
} > "$dir/a.cpp"
out=$("$tool" "$dir/a.cpp" 2>&1) && fail "a 101-line function passed"
grep -q "function of 101 lines" <<<"$out" || fail "no breach named: $out"
grep -q "shortOne\|table" <<<"$out" && fail "a function within the limit, or a table, was named: $out"

# A file of 501 lines.
for i in $(seq 501); do echo "// line $i"; done > "$dir/b.h"
out=$("$tool" "$dir/b.h" 2>&1) && fail "a 501-line file passed"
grep -q "501 lines (at most 500)" <<<"$out" || fail "no file breach named: $out"

# Known breaches pass; a new one does not; an entry no longer over the limit is stale.
cd "$dir"
echo "a.cpp: function longOne" > known.txt
"$tool" --baseline known.txt a.cpp >/dev/null || fail "a known breach failed"
out=$("$tool" --baseline /dev/null a.cpp 2>&1) && fail "an unknown breach passed"
printf 'a.cpp: function longOne\na.cpp: function shortOne\n' > stale.txt
out=$("$tool" --baseline stale.txt a.cpp 2>&1) && fail "a stale baseline line passed"
grep -q "a.cpp: function shortOne: no longer over the limit" <<<"$out" || fail "stale line not named: $out"
echo "check_sizes_test: ok"
