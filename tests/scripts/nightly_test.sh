#!/usr/bin/env bash
# scripts/nightly over two nights of a quick validation (the built-in bone at 2.4 mm): the
# history gets one row per case and night, each night's report.html its trend plots; the first
# night's Hausdorff distance is then halved (report and history), so the second night must
# exit 1 naming that case, and its plot shows the step. Bad input: exit 2, nothing appended.
#   nightly_test.sh OSTEON SOURCE_DIR WORK_DIR
set -euo pipefail
osteon=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
root="$work/nights" history="$work/nights/history.csv"
fail() { echo "FAIL: $1"; exit 1; }
nightly() { "$src/scripts/nightly" --osteon "$osteon" --out-root "$root" --quick --voxel-sizes 2.4 "$@"; }
rows() { tail -n +2 "$history" | wc -l; }
nights() { tail -n +2 "$history" | cut -d, -f1 | sort -u | wc -l; }

# Night 1: PASS, 4 rows, plots in the report.
nightly >"$work/night1.out" 2>&1 || { cat "$work/night1.out"; fail "night 1 exited $?"; }
night1=$(realpath "$root/latest")
[[ "$(head -n 1 "$history")" == date,commit,model,voxel_size_mm,method,mode,crack_percent,border_edges,self_intersections,hausdorff_mm,max_force_n,jitter_n,case_s,mesh_ms,run_s ]] ||
  fail "history header: $(head -n 1 "$history")"
[[ $(rows) -eq 4 && $(nights) -eq 1 ]] || fail "after night 1: $(rows) rows, $(nights) nights"
grep -q ',default,2.4,crackfree,static,0,0,0,0\.' "$history" || fail "no crack-free static row with 0 cracks: $(cat "$history")"
[[ -s "$night1/trends/1_default.png" ]] || fail "night 1 drew no trend plot"
grep -q "Trends over 1 night(s).*src='trends/1_default.png'" "$night1/report.html" || fail "night 1's report.html has no trends"

# The first night made better than it was: its Hausdorff distance for the static crack-free case halved.
static='.cases |= map(if .method == "crackfree" and .mode == "static" then .hausdorff_mm /= 2 else . end)'
jq "$static" "$night1/report.json" >"$work/r.json" && mv "$work/r.json" "$night1/report.json"
awk -F, -v OFS=, 'NR > 1 && $5 == "crackfree" && $6 == "static" { $10 = $10 / 2 } { print }' "$history" >"$work/h.csv"
mv "$work/h.csv" "$history"
halved=$(awk -F, '$5 == "crackfree" && $6 == "static" { print $10 }' "$history")

rc=0
nightly >"$work/night2.out" 2>&1 || rc=$?
cat "$work/night2.out"
[[ $rc -eq 1 ]] || fail "night 2 exited $rc, not 1, on a regression"
grep -q '^nightly: regression: default|2.4|crackfree|static: hausdorff_mm ' "$work/night2.out" ||
  fail "night 2 did not name the regressed case"
night2=$(realpath "$root/latest")
[[ "$night2" != "$night1" ]] || fail "latest still links to night 1"
[[ "$(jq -r .compared_with "$night2/report.json")" == "$night1/report.json" ]] || fail "night 2 was not compared with night 1"
[[ $(rows) -eq 8 && $(nights) -eq 2 ]] || fail "after night 2: $(rows) rows, $(nights) nights"
# The plot's data: two nights, the step from the halved distance to today's.
data="$night2/trends/data/1_2.4_static"
[[ $(wc -l <"$data") -eq 2 ]] || fail "the static series has $(wc -l <"$data") points, not 2"
[[ "$(awk 'NR == 1 { print $3 }' "$data")" == "$halved" ]] || fail "night 1's point is not the halved distance"
awk 'NR == 1 { a = $3 } NR == 2 { exit !($3 > 1.9 * a) }' "$data" || fail "no step in the Hausdorff series: $(cat "$data")"
[[ -s "$night2/trends/1_default.png" ]] || fail "night 2 drew no trend plot"
grep -q "Trends over 2 night(s)" "$night2/report.html" || fail "night 2's report.html has no trends"

# Bad input: exit 2, one line, the history untouched.
refuse() {
  local want=$1; shift
  local rc=0 err
  err=$("$src/scripts/nightly" "$@" 2>&1 >/dev/null) || rc=$?
  [[ $rc -eq 2 ]] || fail "nightly $*: exit $rc, not 2"
  grep -qF -- "$want" <<<"$err" || fail "nightly $*: '$err' does not say '$want'"
}
before=$(md5sum <"$history")
refuse "unknown option '--night'" --out-root "$root" --night x
refuse "--shards is an option of --slurm" --out-root "$root" --shards 2
refuse "--osteon $work/none: not an executable" --out-root "$root" --osteon "$work/none"
echo "date,model" >"$work/other.csv"
refuse "not a nightly history" --osteon "$osteon" --out-root "$root" --history "$work/other.csv"
refuse "$work/none.stl" --osteon "$osteon" --out-root "$root" --models "$work/none.stl" --quick
[[ "$(md5sum <"$history")" == "$before" ]] || fail "bad input changed the history"
echo "nightly: ok"
