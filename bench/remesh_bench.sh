#!/usr/bin/env bash
# Remeshes while drilling: the surface updates' p50 / p99 / max (the programs' own `remesh_ms`,
# read from their JSON files) for `drill` (deterministic: after every step), `drill --threaded`
# (the visual thread) and the viewer (its render loop, under Xvfb), portal-5 on the built-in
# humerus and the shared real one (metres), at 0.54 and 0.3 mm. The last flush after the loops
# stop, and the final extraction for surface.ply, are not remeshes while drilling.
#   bench/remesh_bench.sh [BUILD_DIR] [RUNS] [FRAMES]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
runs="${2:-3}"
frames="${3:-900}"
osteon="$build/cli/osteon"
viewer="$build/viewer/osteon-viewer"
[[ -x "$osteon" ]] || { echo "$0: build $osteon first" >&2; exit 2; }
data="${OSTEON_SHARED_DATA_DIR:-$here/../shared/data}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

bones=("humerus (built-in)|default|mm")
[[ -f "$data/humerus_R_opensim_myosuite.stl" ]] &&
  bones+=("humerus (OpenSim)|$data/humerus_R_opensim_myosuite.stl|m")

echo "remesh bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), load $(cut -d' ' -f1 /proc/loadavg)"
echo "| bone | voxel mm | levels | program | runs | remesh p50 ms | remesh p99 ms | remesh max ms (worst run) | first step ms | surface ready ms |"
echo "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|"
row() {  # name vs levels program files...
  python3 - "$@" <<'PY'
import json, sys
name, vs, levels, program = sys.argv[1:5]
runs = [json.load(open(f)) for f in sys.argv[5:]]
r = [j["remesh_ms"] for j in runs]
med = lambda xs: sorted(xs)[len(xs) // 2]
s = [j.get("setup_ms", {}) for j in runs]
fs = med([x.get("first_step", 0.0) for x in s]); sr = med([x.get("surface_ready", 0.0) for x in s])
print(f"| {name} | {vs} | {levels} | {program} | {len(runs)} | {med([x['p50'] for x in r]):.2f} | "
      f"{med([x['p99'] for x in r]):.2f} | {max(x['max'] for x in r):.2f} | "
      f"{fs:.0f} | {sr:.0f} |".replace("| 0 | 0 |", "| - | - |"))
PY
}
for b in "${bones[@]}"; do
  IFS='|' read -r name mesh units <<<"$b"
  for vs in 0.54 0.3; do
    for levels in 0 2; do
      for mode in deterministic threaded; do
        flag=""; [[ $mode == threaded ]] && flag="--threaded"
        files=()
        for ((k = 1; k <= runs; ++k)); do
          "$osteon" drill "$mesh" --units "$units" --voxel-size "$vs" --levels "$levels" \
            --path portal-5 $flag --json --out-dir "$scratch/d" >"$scratch/$mode$k.json"
          files+=("$scratch/$mode$k.json")
        done
        row "$name" "$vs" "$levels" "drill $flag" "${files[@]}"
      done
      if [[ -x "$viewer" ]] && command -v xvfb-run >/dev/null; then
        files=()
        for ((k = 1; k <= runs; ++k)); do
          xvfb-run -a -s '-screen 0 1280x800x24' "$viewer" "$mesh" --units "$units" --voxel-size "$vs" \
            --levels "$levels" --path portal-5 --frames "$frames" --json >"$scratch/v$k.json" 2>/dev/null
          files+=("$scratch/v$k.json")
        done
        row "$name" "$vs" "$levels" "viewer" "${files[@]}"
      fi
    done
  done
done
