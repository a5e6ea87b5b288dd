#!/usr/bin/env bash
# The viewer while drilling, under Xvfb (Mesa llvmpipe, no GPU): 1.2 mm with 2 levels on the
# built-in humerus, portal-5 played at 1 kHz, RUNS runs of FRAMES frames. Per run: frame p99,
# upload p99, the haptic and collision loops' overrun share, and right after it the machine's
# no-work floor for as long (the same two 1 kHz loops doing nothing beside a thread streaming
# memory, osteon_bench_drilling --floor-only).
#   bench/viewer_bench.sh [BUILD_DIR] [RUNS] [FRAMES]
set -euo pipefail
build="${1:-build}"
runs="${2:-3}"
frames="${3:-600}"
viewer="$build/viewer/osteon-viewer"
floorbench="$build/bench/osteon_bench_drilling"
[[ -x "$viewer" && -x "$floorbench" ]] || { echo "$0: build $viewer and $floorbench first" >&2; exit 2; }
command -v xvfb-run >/dev/null || { echo "$0: needs xvfb-run (scripts/setup installs xvfb)" >&2; exit 2; }

echo "viewer bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), nproc $(nproc)"
echo "| run | frames | frame p50 ms | frame p99 ms | upload p99 ms | remesh p99 ms | haptic overruns | collision overruns | floor haptic | floor collision |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for ((k = 1; k <= runs; ++k)); do
  start=$EPOCHREALTIME
  xvfb-run -a -s '-screen 0 1280x800x24' "$viewer" default --voxel-size 1.2 --levels 2 --path portal-5 \
    --frames "$frames" --json > "$scratch/run.json"
  seconds=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
  read -r _ fp0 fo0 fp1 fo1 _ < <("$floorbench" --floor-only "$seconds")
  python3 - "$scratch/run.json" "$k" "$fp0" "$fo0" "$fp1" "$fo1" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); k = sys.argv[2]
fp0, fo0, fp1, fo1 = map(int, sys.argv[3:7])
share = lambda o, s: f"{o} of {s} ({100.0 * o / max(s, 1):.3f} %)"
print(f"| {k} | {j['frames']} | {j['frame_ms']['p50']:.1f} | {j['frame_ms']['p99']:.1f} | {j['upload_ms']['p99']:.3f} | "
      f"{j['remesh_ms']['p99']:.3f} | {share(j['haptic']['overruns'], j['haptic']['steps'])} | "
      f"{share(j['collision']['overruns'], j['collision']['steps'])} | {share(fo0, fp0)} | {share(fo1, fp1)} |")
PY
done
