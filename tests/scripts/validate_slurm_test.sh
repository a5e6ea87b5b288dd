#!/usr/bin/env bash
# A 4-shard quick validation through a one-node Slurm cluster on this machine
# (scripts/slurm-local), merged, against the same validation run unsharded: same verdict, same
# cases, same per-case results. The built-in bone at four voxel sizes: four case groups (a
# model at a voxel size, the unit a shard takes), so every shard has one. Exit 77 (skipped, with the reason) where Slurm cannot start here
# or the osteon given cannot shard.
#   validate_slurm_test.sh OSTEON SOURCE_DIR WORK_DIR
set -euo pipefail
osteon=$1 src=$2 work=$3
skip() { echo "SKIPPED: $1"; exit 77; }

rm -rf "$work"
mkdir -p "$work"
cluster="$work/cluster"
# The cluster goes down whatever happens; a daemon left running fails the test.
cleanup() {
  local rc=$?
  if ! "$src/scripts/slurm-local" stop "$cluster"; then
    echo "FAIL: stopping the cluster left a daemon running"
    [[ $rc -ne 0 && $rc -ne 77 ]] || rc=1
  fi
  exit "$rc"
}
trap cleanup EXIT

"$osteon" validate --help | grep -q -- '--shard' || skip "$osteon validate has no --shard"
if ! "$src/scripts/slurm-local" start "$cluster" 2>"$work/start.err"; then
  skip "Slurm cannot start here: $(cat "$work/start.err")"
fi
export SLURM_CONF="$cluster/slurm.conf"

run=(--quick --voxel-sizes 1.8,2.1,2.4,2.7)
started=$(date +%s)
rc=0
"$src/scripts/validate-slurm" --shards 4 "${run[@]}" --out-dir "$work/run" --osteon "$osteon" --time 10 \
  --cpus-per-task 1 --wait >"$work/submit.out" 2>&1 || rc=$?
cat "$work/submit.out"
echo "through Slurm: $(($(date +%s) - started)) s, exit $rc"
grep -qE '^shards: job [0-9]+, array 0-3 ' "$work/submit.out" || { echo "FAIL: no shard job id printed"; exit 1; }
grep -qE '^merge: job [0-9]+, ' "$work/submit.out" || { echo "FAIL: no merge job id printed"; exit 1; }
grep -qF "report: $work/run/merged/report.html" "$work/submit.out" || { echo "FAIL: report path not printed"; exit 1; }
for k in 0 1 2 3; do
  [[ -f "$work/run/shard-$k/report.json" ]] || { echo "FAIL: shard $k wrote no report"; cat "$work/run/logs/shard-$k.out"; exit 1; }
  [[ "$(jq -r '.shard | type' "$work/run/shard-$k/report.json")" == object ]] ||
    { echo "FAIL: shard $k's report has no \"shard\" object"; exit 1; }
  [[ "$(jq '.cases | length' "$work/run/shard-$k/report.json")" -eq 4 ]] ||
    { echo "FAIL: shard $k ran $(jq '.cases | length' "$work/run/shard-$k/report.json") cases, not one group of 4"; exit 1; }
done
[[ -f "$work/run/merged/report.json" && -f "$work/run/merged/report.html" ]] ||
  { echo "FAIL: no merged report"; cat "$work/run/logs/merge.out"; exit 1; }

started=$(date +%s)
urc=0
"$osteon" validate "${run[@]}" --out-dir "$work/unsharded" >"$work/unsharded.out" 2>&1 || urc=$?
echo "unsharded: $(($(date +%s) - started)) s, exit $urc"
[[ $rc -eq $urc ]] || { echo "FAIL: validate-slurm --wait exited $rc, the unsharded run $urc"; exit 1; }

# Same verdict and the same cases with the same results (the deterministic fields).
summary='[.schema, .verdict, (.cases | length),
          (.cases | map({model, voxel_size_mm, method, mode, pass, border_edges, non_manifold,
                         self_intersections, crack_percent, collision_misses})
                  | sort_by(.model, .voxel_size_mm, .method, .mode))]'
jq -S "$summary" "$work/run/merged/report.json" >"$work/merged.summary"
jq -S "$summary" "$work/unsharded/report.json" >"$work/unsharded.summary"
if ! diff -u "$work/unsharded.summary" "$work/merged.summary"; then
  echo "FAIL: the merged report differs from the unsharded run (above: - unsharded, + merged)"
  exit 1
fi
[[ "$(jq '.cases | length' "$work/run/merged/report.json")" -eq 16 ]] || { echo "FAIL: not 16 cases"; exit 1; }
echo "merged: $(jq -r .verdict "$work/run/merged/report.json"), 16 cases, as unsharded"
