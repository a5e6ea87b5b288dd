#!/usr/bin/env bash
# Set-up, from the file to the first step: for each bone and voxel size, the stages
# `osteon drill --levels 0 --json` reports in `setup_ms` (load, voxelize, density, hierarchy,
# surface, path, total; first_step and surface_ready: from the start to the first haptic step
# and to the full surface, extracted beside the first steps), the peak RSS when ready to step and at exit, the voxels with bone, and
# how the stages grow with the voxel count from one size to the next:
# exponent = log(time ratio) / log(voxel ratio), so 1 is linear in voxels.
#   bench/setup_bench.sh [BUILD_DIR] [SIZES] [RUNS]   e.g. bench/setup_bench.sh build "1.2 0.54 0.3 0.25" 3
# The built-in humerus (`default`) and the shared real humerus (metres) drill portal-5; the
# fibula (mm) and femur (metres) have no humeral head, so they drill a two-row CSV path in the
# air (--allow-empty): the same set-up, then a 10-step run that meets no bone. Real bones come
# from OSTEON_SHARED_DATA_DIR (default ../shared/data beside the repository); absent ones are
# skipped. Each case runs RUNS times (default 3) and the run with the median total is shown;
# run it with `nice` on a shared machine.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
sizes="${2:-1.2 0.54 0.3 0.25}"
runs="${3:-3}"
osteon="$build/cli/osteon"
[[ -x "$osteon" ]] || { echo "$0: build $osteon first" >&2; exit 2; }
data="${OSTEON_SHARED_DATA_DIR:-$here/../shared/data}"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
printf 't,x,y,z,drill_on\n0,1e5,1e5,1e5,1\n0.01,1e5,1e5,1e5,1\n' >"$scratch/air.csv"

# name|mesh argument|units|path
cases=("humerus (built-in)|default|mm|portal-5")
[[ -f "$data/humerus_R_opensim_myosuite.stl" ]] &&
  cases+=("humerus (OpenSim)|$data/humerus_R_opensim_myosuite.stl|m|portal-5")
[[ -f "$data/fibula_L_vhm_denver.stl" ]] &&
  cases+=("fibula (VHM)|$data/fibula_L_vhm_denver.stl|mm|$scratch/air.csv")
[[ -f "$data/femur_R_opensim_myosuite.stl" ]] &&
  cases+=("femur (OpenSim)|$data/femur_R_opensim_myosuite.stl|m|$scratch/air.csv")

echo "set-up bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), median of $runs runs"
: >"$scratch/rows"
for c in "${cases[@]}"; do
  IFS='|' read -r name mesh units path <<<"$c"
  for vs in $sizes; do
    ok=1
    rm -f "$scratch"/one*.json
    for ((k = 1; k <= runs; ++k)); do
      rm -rf "$scratch/run"
      if ! "$osteon" drill "$mesh" --units "$units" --voxel-size "$vs" --levels 0 --path "$path" --allow-empty \
        --json --out-dir "$scratch/run" >"$scratch/one$k.json" 2>"$scratch/err"; then
        echo "$name at $vs mm: $(head -1 "$scratch/err")" >&2
        ok=0
        break
      fi
    done
    ((ok)) || continue
    python3 - "$name" "$vs" "$scratch"/one*.json >>"$scratch/rows" <<'PY'
import json, sys
runs = sorted((json.load(open(f)) for f in sys.argv[3:]), key=lambda j: j["setup_ms"]["total"])
j = runs[(len(runs) - 1) // 2]; s = j["setup_ms"]  # the run with the median total
print("|".join([sys.argv[1], sys.argv[2], str(j["voxels"])] +
               [f"{s[k]:.1f}" for k in ("load", "voxelize", "density", "hierarchy", "surface", "path", "total", "first_step", "surface_ready")] +
               [f"{j['setup_peak_rss_mb']:.0f}", f"{j['peak_rss_mb']:.0f}"]))
PY
  done
done

python3 - "$scratch/rows" <<'PY'
import math, sys
rows = [line.rstrip("\n").split("|") for line in open(sys.argv[1]) if line.strip()]
stages = ["load", "voxelize", "density", "hierarchy", "surface", "path", "total", "first_step", "surface_ready"]
grown = ["voxelize", "density", "hierarchy", "surface", "total"]
print("| bone | voxel mm | voxels | " + " | ".join(f"{s} ms" for s in stages) +
      " | RSS ready MB | peak RSS MB | " + " | ".join(f"exp {s}" for s in grown) + " |")
print("|---|---:|---:|" + "---:|" * (len(stages) + 2 + len(grown)))
previous = {}
for r in rows:
    name, vs, voxels = r[0], r[1], int(r[2])
    ms = dict(zip(stages, map(float, r[3:12])))
    exps = []
    p = previous.get(name)
    for s in grown:
        # Exponent of growth against the previous size of the same bone (1 = linear in voxels).
        if p and p[0] > 0 and voxels != p[0] and p[1][s] > 0 and ms[s] > 0:
            exps.append(f"{math.log(ms[s] / p[1][s]) / math.log(voxels / p[0]):.2f}")
        else:
            exps.append("")
    previous[name] = (voxels, ms)
    print(f"| {name} | {vs} | {voxels:,} | " + " | ".join(f"{ms[s]:.0f}" for s in stages) +
          f" | {r[12]} | {r[13]} | " + " | ".join(exps) + " |")
PY
