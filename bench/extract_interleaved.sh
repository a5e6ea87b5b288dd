#!/usr/bin/env bash
# `osteon mesh`'s own extraction time (time_ms.extract, --smooth 0) against VTK's
# vtkFlyingEdges3D on the same grid, one fresh process per run, both pinned to one core,
# interleaved run by run so both see the same machine from minute to minute:
#   bench/extract_interleaved.sh [-n RUNS] [-c CPU] [-v VOLUMES] OSTEON [OSTEON...]
# e.g. bench/extract_interleaved.sh -n 21 build/cli/osteon /tmp/osteon-76bc24c/build/cli/osteon
#
# The volumes are the benchmark's (osteon_bench_surface's extract/...): a drilled sphere and
# the built-in humerus at 64^3, 128^3 and 256^3, written as osteon grids (GRID.nrrd) by
# build/bench/osteon_bench_extract_peer, which also runs FlyingEdges (one thread, iso 127.5 of
# the grid's uint8 fill steps, no normals). Per volume it prints the median of each binary's
# extraction and of FlyingEdges', and the median of the per-run ratios osteon / FlyingEdges
# (the goal: at most 1/3). PEER names the peer program (default: beside this script's build).
set -euo pipefail

runs=11
cpu=0
volumes="sphere_64 sphere_128 sphere_256 humerus_64 humerus_128 humerus_256"
while [[ "${1:-}" == -* ]]; do
  case "$1" in
    -n) runs="$2" ;;
    -c) cpu="$2" ;;
    -v) volumes="$2" ;;
    *) echo "usage: $0 [-n RUNS] [-c CPU] [-v VOLUMES] OSTEON [OSTEON...]" >&2; exit 2 ;;
  esac
  shift 2
done
if [[ $# -lt 1 ]]; then
  echo "usage: $0 [-n RUNS] [-c CPU] [-v VOLUMES] OSTEON [OSTEON...]" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
peer="${PEER:-$here/../build/bench/osteon_bench_extract_peer}"
if [[ ! -x "$peer" ]]; then
  echo "$0: $peer: not built (needs VTK 9: libvtk9-dev; cmake --build build -t osteon_bench_extract_peer)" >&2
  exit 2
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
"$peer" write "$scratch" >/dev/null

median() {  # the median of the numbers on stdin
  sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
field() {  # field "$json" NAME: a number from a JSON object printed on one or more lines
  python3 -c 'import json, sys; j = json.loads(sys.argv[1])
for k in sys.argv[2].split("."): j = j[k]
print(j)' "$1" "$2"
}

printf '%-12s' volume
for ((b = 1; b <= $#; ++b)); do printf ' %12s %8s' "osteon$b ms" "/ FE"; done
printf ' %12s %10s\n' "FE ms" triangles
for volume in $volumes; do
  grid="$scratch/$volume.nrrd"
  : >"$scratch/fe"
  for ((b = 1; b <= $#; ++b)); do : >"$scratch/os$b"; : >"$scratch/ratio$b"; done
  for ((i = 0; i < runs; ++i)); do
    fe="$(field "$(taskset -c "$cpu" "$peer" flyingedges "$grid")" extract_ms)"
    echo "$fe" >>"$scratch/fe"
    b=0
    for binary in "$@"; do
      b=$((b + 1))
      json="$(taskset -c "$cpu" "$binary" mesh "$grid" --smooth 0 --json)"
      ms="$(field "$json" time_ms.extract)"
      triangles="$(field "$json" triangles)"
      echo "$ms" >>"$scratch/os$b"
      awk -v a="$ms" -v f="$fe" 'BEGIN { printf "%.4f\n", a / f }' >>"$scratch/ratio$b"
    done
  done
  printf '%-12s' "$volume"
  for ((b = 1; b <= $#; ++b)); do
    printf ' %12.3f %8.3f' "$(median <"$scratch/os$b")" "$(median <"$scratch/ratio$b")"
  done
  printf ' %12.3f %10s\n' "$(median <"$scratch/fe")" "$triangles"
done
echo "($runs runs each, interleaved, medians; taskset -c $cpu; $(lscpu | sed -n 's/^Model name: *//p' | head -1); $(date -u '+%Y-%m-%d %H:%M UTC'))"
for ((b = 1; b <= $#; ++b)); do echo "osteon$b: ${!b}"; done
