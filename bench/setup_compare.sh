#!/usr/bin/env bash
# Set-up of two builds side by side, interleaved run by run on the same machine: `osteon drill
# BONE --voxel-size VS --levels 0 --path P --json` [--threaded], each build's own figures read
# from its JSON: the first step (`setup_ms.first_step`; a build without it steps once its whole
# set-up is done, `setup_ms.total`), the full surface (`surface_ready`; else the total), the
# peak RSS when ready and at exit. Medians of RUNS (ranges beside). Remeshes while drilling:
# bench/remesh_bench.sh (a deterministic run outpaces the clock, so its surface may catch up
# only at the end).
#   bench/setup_compare.sh EARLIER_BUILD BUILD [RUNS] [SIZES] [--threaded]
# Bones: the shared femur (the stand-in for a CT-sized humerus) and humerus, metres, from
# OSTEON_SHARED_DATA_DIR (default ../shared/data); the femur drills a path in the air.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
[[ $# -ge 2 ]] || { echo "usage: $0 EARLIER_BUILD BUILD [RUNS] [SIZES] [--threaded]" >&2; exit 2; }
builds=("$1" "$2")
runs="${3:-3}"
sizes="${4:-0.54 0.3}"
flag="${5:-}"
for b in "${builds[@]}"; do
  [[ -x "$b/cli/osteon" ]] || { echo "$0: no $b/cli/osteon" >&2; exit 2; }
done
data="${OSTEON_SHARED_DATA_DIR:-$here/../shared/data}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
printf 't,x,y,z,drill_on\n0,1e5,1e5,1e5,1\n0.01,1e5,1e5,1e5,1\n' >"$scratch/air.csv"
cases=()
[[ -f "$data/femur_R_opensim_myosuite.stl" ]] && cases+=("femur (OpenSim)|$data/femur_R_opensim_myosuite.stl|$scratch/air.csv")
[[ -f "$data/humerus_R_opensim_myosuite.stl" ]] && cases+=("humerus (OpenSim)|$data/humerus_R_opensim_myosuite.stl|portal-5")

echo "set-up compare, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), load $(cut -d' ' -f1 /proc/loadavg), $runs runs interleaved ${flag}"
echo "| bone | voxel mm | build | first step ms | full surface ms | RSS ready MB | peak RSS MB |"
echo "|---|---:|---|---:|---:|---:|---:|"
for c in "${cases[@]}"; do
  IFS='|' read -r name mesh path <<<"$c"
  for vs in $sizes; do
    for ((k = 1; k <= runs; ++k)); do
      for i in 0 1; do
        rm -rf "$scratch/out"
        "${builds[$i]}/cli/osteon" drill "$mesh" --units m --voxel-size "$vs" --levels 0 --path "$path" \
          --allow-empty $flag --json --out-dir "$scratch/out" >"$scratch/b$i-$k.json" 2>/dev/null
      done
    done
    for i in 0 1; do
      python3 - "$name" "$vs" "${builds[$i]}" "$scratch"/b$i-*.json <<'PY'
import json, sys
name, vs, build = sys.argv[1:4]
js = [json.load(open(f)) for f in sys.argv[4:]]
def col(values, fmt="{:.0f}"):
    v = sorted(values)
    return f"{fmt.format(v[len(v) // 2])} ({fmt.format(v[0])}-{fmt.format(v[-1])})"
s = [j["setup_ms"] for j in js]
first = [x.get("first_step") or x["total"] for x in s]
ready = [x.get("surface_ready") or x["total"] for x in s]
print(f"| {name} | {vs} | {build} | {col(first)} | {col(ready)} | "
      f"{col([j['setup_peak_rss_mb'] for j in js])} | {col([j['peak_rss_mb'] for j in js])} |")
PY
    done
  done
done
