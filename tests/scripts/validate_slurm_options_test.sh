#!/usr/bin/env bash
# scripts/validate-slurm without a cluster: the sbatch commands it would run (--dry-run), and
# one-line refusals (exit 2) of bad options; scripts/slurm-local's usage.
#   validate_slurm_options_test.sh SOURCE_DIR OSTEON WORK_DIR
set -euo pipefail
src=$1 osteon=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
vs="$src/scripts/validate-slurm"
fail() { echo "FAIL: $1"; exit 1; }

out=$("$vs" --shards 4 --quick --models default --voxel-sizes 1.2,0.9 --partition batch --time 1:30:00 \
  --cpus-per-task 8 --out-dir "$work/run" --osteon "$osteon" --compare "$src/README.md" --dry-run)
echo "$out"
shard_line=$(grep '^sbatch .*--array=' <<<"$out") || fail "no array submission"
merge_line=$(grep '^sbatch .*--dependency=' <<<"$out") || fail "no merge submission"
for want in --array=0-3 --exclusive --nodes=1 --partition=batch --time=1:30:00 --cpus-per-task=8 \
  "--output=$work/run/logs/shard-%a.out" "$work/run/slurm/shard.sh"; do
  grep -qF -- "$want" <<<"$shard_line" || fail "shard submission lacks $want"
done
for want in --dependency=afterok:JOBID --kill-on-invalid-dep=yes --partition=batch --time=1:30:00 \
  "$work/run/slurm/merge.sh"; do
  grep -qF -- "$want" <<<"$merge_line" || fail "merge submission lacks $want"
done
grep -qF -- "validate --quick --models default --voxel-sizes 1.2,0.9 --shard \"\$k/4\" --out-dir $work/run/shard-\"\$k\"" <<<"$out" ||
  fail "the shard script does not run one shard per array index"
grep -qF -- "validate --merge $work/run/shard-0 $work/run/shard-1 $work/run/shard-2 $work/run/shard-3 --out-dir $work/run/merged --compare $src/README.md" <<<"$out" ||
  fail "the merge script does not merge the four shards"
grep -qxF "report: $work/run/merged/report.html" <<<"$out" || fail "no report path"
[[ ! -e "$work/run" ]] || fail "--dry-run created $work/run"

# Bad options: exit 2, one line naming the option.
refuse() {
  local want=$1; shift
  local rc=0 err
  err=$("$vs" "$@" 2>&1 >/dev/null) || rc=$?
  [[ $rc -eq 2 ]] || fail "validate-slurm $*: exit $rc, not 2"
  [[ $(wc -l <<<"$err") -eq 1 ]] || fail "validate-slurm $*: more than one line: $err"
  grep -qF -- "$want" <<<"$err" || fail "validate-slurm $*: '$err' does not say '$want'"
}
refuse "--shards N is required" --out-dir "$work/x" --dry-run
refuse "--shards 0" --shards 0 --out-dir "$work/x" --dry-run
refuse "--shards x" --shards x --out-dir "$work/x" --dry-run
refuse "--out-dir DIR is required" --shards 2 --dry-run
refuse "--time 2h" --shards 2 --out-dir "$work/x" --time 2h --dry-run
refuse "--cpus-per-task 0" --shards 2 --out-dir "$work/x" --cpus-per-task 0 --dry-run
refuse "--cpus-per-task needs a value" --shards 2 --out-dir "$work/x" --cpus-per-task
refuse "--partition a b" --shards 2 --out-dir "$work/x" --partition "a b" --dry-run
refuse "unknown option '--nodes'" --shards 2 --out-dir "$work/x" --nodes 3
refuse "--osteon $work/none" --shards 2 --out-dir "$work/x" --osteon "$work/none" --dry-run
refuse "--compare $work/none.json" --shards 2 --out-dir "$work/x" --compare "$work/none.json" --dry-run
mkdir -p "$work/used/shard-0"
refuse "already holds a run" --shards 2 --out-dir "$work/used" --osteon "$osteon" --dry-run

rc=0
"$src/scripts/slurm-local" restart "$work/c" 2>/dev/null || rc=$?
[[ $rc -eq 2 ]] || fail "slurm-local restart: exit $rc, not 2"
echo "validate-slurm options: ok"
