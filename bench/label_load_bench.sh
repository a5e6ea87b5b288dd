#!/usr/bin/env bash
# Loading a 256^3 label map (or CT) against extracting its surface: `osteon mesh LABELS.nrrd --smooth 0
# --json` reports the load (`setup_ms.load`: read, meaning, the grid with its cortical shell)
# and the extraction alone (`time_ms.extract`). Three uint8 0/255 label maps at 0.3 mm (a shell
# of 7 voxels): a sphere filling the box, the same sphere with three drilled tunnels, and the
# shared humerus voxelized (its longest side 254 voxels) in the middle of the box; and beside
# them a uint8 scalar volume (the sphere, more than 64 values: read with --iso 120, its density
# by distance as a label map's) and a 256^3 int16 CT (air, a body, two long bones: cortical by
# HU, not by distance). Each build
# given runs each volume RUNS times (default 5), the builds interleaved run by run; the table
# shows each build's median load and extraction, and the median of the ratio (load / extract)
# taken run by run, each from one process.
#   bench/label_load_bench.sh [RUNS] BUILD_DIR [BUILD_DIR...]   e.g. bench/label_load_bench.sh 5 before build
# The humerus comes from OSTEON_SHARED_DATA_DIR (default ../shared/data beside the repository);
# without it that row is skipped. Run it with `nice` on a shared machine.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
runs="${1:-5}"
shift || true
builds=("$@")
((${#builds[@]})) || builds=("$here/build")
for b in "${builds[@]}"; do
  [[ -x "$b/cli/osteon" ]] || { echo "$0: build $b/cli/osteon first" >&2; exit 2; }
done
data="${OSTEON_SHARED_DATA_DIR:-$here/../shared/data}"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# The volumes, row by row as spans (a pure-Python voxel loop would take a minute).
write_labels() {
  python3 - "$@" <<'PY'
import math, sys
kind, out = sys.argv[1], sys.argv[2]
n = 256
rows = []
def span(row, centre, radius2, value):
    if radius2 <= 0:
        return
    h = math.sqrt(radius2)
    lo, hi = max(0, math.floor(centre - h) + 1), min(n, math.ceil(centre + h))
    if lo < hi:
        row[lo:hi] = value * (hi - lo)
if kind == "humerus":  # an osteon grid (fill 0..255) into the middle of the box, 0/255
    src = open(sys.argv[3], "rb").read()
    cut = src.index(b"\n\n") + 2
    sizes = [int(v) for v in next(l for l in src[:cut].decode().split("\n")
                                  if l.startswith("sizes:")).split()[1:]]
    if max(sizes) > n:
        sys.exit(f"humerus grid {sizes} larger than {n}^3")
    voxels = src[cut:].translate(bytes(0 if v < 128 else 255 for v in range(256)))
    shift = [(n - s) // 2 for s in sizes]
    for z in range(n):
        for y in range(n):
            zz, yy = z - shift[2], y - shift[1]
            row = bytes(n)
            if 0 <= zz < sizes[2] and 0 <= yy < sizes[1]:
                o = (zz * sizes[1] + yy) * sizes[0]
                row = bytes(shift[0]) + voxels[o:o + sizes[0]] + bytes(n - shift[0] - sizes[0])
            rows.append(row)
elif kind == "scalar":  # uint8, more values than labels: the sphere 150-249, outside 0-49
    c, r = n / 2 - 0.5, 0.5 * (n - 3)
    for z in range(n):
        for y in range(n):
            row = bytearray([z % 50]) * n
            span(row, c, r * r - (y - c) ** 2 - (z - c) ** 2, bytes([150 + y % 100]))
            rows.append(bytes(row))
elif kind == "ct":  # int16 HU: air, a body of soft tissue, two long bones (shell, marrow)
    from array import array
    c = n / 2 - 0.5
    for z in range(n):
        for y in range(n):
            row = array("h", [-1000]) * n
            dy = y - c
            span(row, c, (0.45 * n) ** 2 - (dy / 0.75) ** 2, array("h", [40]))
            for cx in (c - 0.25 * n, c + 0.25 * n):
                span(row, cx, (0.1 * n) ** 2 - dy * dy, array("h", [1400]))
                span(row, cx, (0.065 * n) ** 2 - dy * dy, array("h", [200]))
            rows.append(row.tobytes())
else:  # a sphere filling the box; drilled: three tunnels of radius n/12, off centre by n/8
    c, r, t, off = n / 2 - 0.5, 0.5 * (n - 3), n / 12.0, n / 8.0
    for z in range(n):
        for y in range(n):
            row = bytearray(n)
            dy, dz = y - c, z - c
            span(row, c, r * r - dy * dy - dz * dz, b"\xff")
            if kind == "drilled":
                if (dy - off) ** 2 + dz * dz < t * t:  # the tunnel along x
                    row = bytearray(n)
                span(row, c, t * t - (dz - off) ** 2, b"\0")  # along y
                span(row, c + off, t * t - dy * dy, b"\0")  # along z
            rows.append(bytes(row))
header = (f"NRRD0004\ntype: {'int16' if kind == 'ct' else 'uint8'}\ndimension: 3\n"
          "space: left-posterior-superior\nendian: little\n"
          f"sizes: {n} {n} {n}\nspace directions: (0.3,0,0) (0,0.3,0) (0,0,0.3)\n"
          "kinds: domain domain domain\nencoding: raw\nspace origin: (0,0,0)\n\n")
open(out, "wb").write(header.encode() + b"".join(rows))
PY
}

osteon="${builds[-1]}/cli/osteon"
volumes=(sphere drilled)
write_labels sphere "$scratch/sphere.nrrd"
write_labels drilled "$scratch/drilled.nrrd"
if [[ -f "$data/humerus_R_opensim_myosuite.stl" ]]; then
  # The bone's longest side (321 mm) over 254 voxels.
  "$osteon" voxelize "$data/humerus_R_opensim_myosuite.stl" --units m --voxel-size 1.27 \
    --out "$scratch/humerus_grid.nrrd" >/dev/null
  write_labels humerus "$scratch/humerus.nrrd" "$scratch/humerus_grid.nrrd"
  volumes+=(humerus)
fi
write_labels scalar "$scratch/scalar.nrrd"
write_labels ct "$scratch/ct.nrrd"
volumes+=(scalar ct)

echo "volume load bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p' | head -1), nproc $(nproc), median of $runs runs, builds interleaved"
for v in "${volumes[@]}"; do
  for ((k = 1; k <= runs; ++k)); do
    for ((b = 0; b < ${#builds[@]}; ++b)); do
      iso=()
      [[ $v == scalar ]] && iso=(--iso 120)  # a scalar volume is read only with an iso value
      "${builds[b]}/cli/osteon" mesh "$scratch/$v.nrrd" "${iso[@]}" --smooth 0 --json \
        >"$scratch/$v.$b.$k.json"
    done
  done
done

python3 - "$scratch" "$runs" "${builds[@]}" -- "${volumes[@]}" <<'PY'
import json, statistics, sys
args = sys.argv[3:]
builds, volumes = args[:args.index("--")], args[args.index("--") + 1:]
scratch, runs = sys.argv[1], int(sys.argv[2])
print("| volume | triangles | build | load ms | extract ms | load / extract, run by run |")
print("|---|---:|---|---:|---:|---:|")
for v in volumes:
    for b, name in enumerate(builds):
        js = [json.load(open(f"{scratch}/{v}.{b}.{k}.json")) for k in range(1, runs + 1)]
        load = statistics.median(j["setup_ms"]["load"] for j in js)
        extract = statistics.median(j["time_ms"]["extract"] for j in js)
        lo = min(j["setup_ms"]["load"] for j in js)
        hi = max(j["setup_ms"]["load"] for j in js)
        # The ratio run by run (load and extraction of one process, one moment), its median.
        ratios = sorted(j["setup_ms"]["load"] / j["time_ms"]["extract"] for j in js)
        ratio = statistics.median(ratios)
        print(f"| {v} | {js[0]['triangles']:,} | {name} | {load:.0f} ({lo:.0f}-{hi:.0f}) | "
              f"{extract:.1f} | {ratio:.1f} ({ratios[0]:.1f}-{ratios[-1]:.1f}) |")
PY
