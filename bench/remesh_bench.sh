#!/usr/bin/env bash
# Remeshes while drilling in real time: the surface updates' p50 / p99 / max (the programs' own
# `remesh_ms`, read from their JSON files) for `drill --threaded` (its visual thread) and the
# viewer (its render loop, under Xvfb), portal-5 on the built-in humerus and the shared real
# one (metres), at 0.54 and 0.3 mm, levels 0 and 2. One build, or two interleaved run by run
# (an earlier build beside this one). The flush after the loops stop and the final extraction
# for surface.ply are not remeshes while drilling.
#   bench/remesh_bench.sh RUNS FRAMES BUILD [BUILD2]   e.g. bench/remesh_bench.sh 3 900 build
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
[[ $# -ge 3 ]] || { echo "usage: $0 RUNS FRAMES BUILD [BUILD2]" >&2; exit 2; }
runs="$1"
frames="$2"
shift 2
builds=("$@")
for b in "${builds[@]}"; do
  [[ -x "$b/cli/osteon" ]] || { echo "$0: no $b/cli/osteon" >&2; exit 2; }
done
data="${OSTEON_SHARED_DATA_DIR:-$here/../shared/data}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
xvfb=0
command -v xvfb-run >/dev/null && xvfb=1

bones=("humerus (built-in)|default|mm")
[[ -f "$data/humerus_R_opensim_myosuite.stl" ]] &&
  bones+=("humerus (OpenSim)|$data/humerus_R_opensim_myosuite.stl|m")

echo "remesh bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), load $(cut -d' ' -f1 /proc/loadavg)"
echo "| bone | voxel mm | levels | program | build | runs | remesh p50 ms | remesh p99 ms | remesh max ms (worst run) |"
echo "|---|---:|---:|---|---|---:|---:|---:|---:|"
row() {  # name vs levels program build files...
  python3 - "$@" <<'PY'
import json, sys
name, vs, levels, program, build = sys.argv[1:6]
r = [json.load(open(f))["remesh_ms"] for f in sys.argv[6:]]
med = lambda xs: sorted(xs)[len(xs) // 2]
print(f"| {name} | {vs} | {levels} | {program} | {build} | {len(r)} | {med([x['p50'] for x in r]):.2f} | "
      f"{med([x['p99'] for x in r]):.2f} | {max(x['max'] for x in r):.2f} |")
PY
}
for b in "${bones[@]}"; do
  IFS='|' read -r name mesh units <<<"$b"
  for vs in 0.54 0.3; do
    for levels in 0 2; do
      for ((k = 1; k <= runs; ++k)); do
        for i in "${!builds[@]}"; do
          "${builds[$i]}/cli/osteon" drill "$mesh" --units "$units" --voxel-size "$vs" --levels "$levels" \
            --path portal-5 --threaded --json --out-dir "$scratch/d" >"$scratch/t$i-$k.json"
          if ((xvfb)) && [[ -x "${builds[$i]}/viewer/osteon-viewer" ]]; then
            xvfb-run -a -s '-screen 0 1280x800x24' "${builds[$i]}/viewer/osteon-viewer" "$mesh" \
              --units "$units" --voxel-size "$vs" --levels "$levels" --path portal-5 \
              --frames "$frames" --json >"$scratch/v$i-$k.json" 2>/dev/null
          fi
        done
      done
      for i in "${!builds[@]}"; do
        row "$name" "$vs" "$levels" "drill --threaded" "${builds[$i]}" "$scratch"/t$i-*.json
        [[ -f "$scratch/v$i-1.json" ]] && row "$name" "$vs" "$levels" "viewer" "${builds[$i]}" "$scratch"/v$i-*.json
      done
      rm -f "$scratch"/*.json
    done
  done
done
