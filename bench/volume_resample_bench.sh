#!/usr/bin/env bash
# Loading and meshing a 512 x 512 x 350 int16 bone phantom CT (bench/ct_phantom.h) as
# `osteon mesh CT.nrrd` does, one process per run (`osteon_bench_volume measure`: load, mesh,
# CPU time, peak RSS over that span, to JSON): at 0.7 x 0.7 x 1 mm (aniso), 0.98 x 0.98 x 2 mm
# (thick), 0.7 x 0.7 x 1 mm tilted 15 degrees (oblique), all resampled onto cubes at the finest
# spacing, 0.7 mm cubes (iso, placed exactly) beside them, and aniso's bone as a uint8 label
# map (labels, resampled partial-volume; KINDS="aniso iso" runs some only). Each build given
# runs each volume RUNS times (default 5), the builds interleaved run by run; the table shows
# each build's median (range in brackets).
#   bench/volume_resample_bench.sh [RUNS] BUILD_DIR [BUILD_DIR...]
# The phantoms take 1.2 GB in a scratch folder under TMPDIR. Run it with `nice` on a shared
# machine.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
runs="${1:-5}"
shift || true
builds=("$@")
((${#builds[@]})) || builds=("$here/build")
for b in "${builds[@]}"; do
  [[ -x "$b/bench/osteon_bench_volume" ]] || {
    echo "$0: build $b/bench/osteon_bench_volume first" >&2
    exit 2
  }
done
kinds=(${KINDS:-aniso thick oblique iso labels})

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for k in "${kinds[@]}"; do
  "${builds[-1]}/bench/osteon_bench_volume" write "$k" "$scratch/$k.nrrd"
done

echo "volume resample bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), median of $runs runs, builds interleaved"
for k in "${kinds[@]}"; do
  for ((r = 1; r <= runs; ++r)); do
    for ((b = 0; b < ${#builds[@]}; ++b)); do
      "${builds[b]}/bench/osteon_bench_volume" measure "$scratch/$k.nrrd" "$scratch/$k.$b.$r.json"
    done
  done
done

python3 - "$scratch" "$runs" "${builds[@]}" -- "${kinds[@]}" <<'PY'
import json, statistics, sys
args = sys.argv[3:]
builds, kinds = args[:args.index("--")], args[args.index("--") + 1:]
scratch, runs = sys.argv[1], int(sys.argv[2])
print("| CT | build | load ms | mesh ms | load + mesh ms | CPU ms | peak RSS MB | peak / raw | triangles |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
for k in kinds:
    for b, name in enumerate(builds):
        js = [json.load(open(f"{scratch}/{k}.{b}.{r}.json")) for r in range(1, runs + 1)]
        med = lambda key: statistics.median(j[key] for j in js)
        lo, hi = min(j["total_ms"] for j in js), max(j["total_ms"] for j in js)
        print(f"| {k} | {name} | {med('load_ms'):.0f} | {med('mesh_ms'):.0f} | "
              f"{med('total_ms'):.0f} ({lo:.0f}-{hi:.0f}) | {med('cpu_ms'):.0f} | "
              f"{med('peak_mb'):.0f} | {med('peak_mb') / js[0]['raw_mb']:.2f} | "
              f"{js[0]['triangles']:,} |")
PY
