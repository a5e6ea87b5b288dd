#!/bin/sh
# `osteon mesh SERIES --out x.ply --json` on DICOM series, two builds interleaved run by run:
# wall time, CPU time (user + system, the child's too), the load's share (setup_ms.load), peak RSS (GNU time, the largest of osteon and its
# reading child). Phantoms from build/bench/osteon_bench_dicom_phantom FOLDER SYNTAX.
#   bench/dicom_load_bench.sh RUNS BEFORE_DIR AFTER_DIR SERIES...
# BEFORE_DIR and AFTER_DIR each hold an osteon and its libosteon_dicom.so.
set -eu
runs=$1 before=$2 after=$3
shift 3
out=$(mktemp -d)
printf 'series\tbuild\trun\twall_s\tcpu_s\tload_ms\tpeak_rss_mb\n'
for series in "$@"; do
  for run in $(seq 1 "$runs"); do
    for build in before after; do
      dir=$before
      [ "$build" = after ] && dir=$after
      OSTEON_DICOM_PLUGIN="$dir/libosteon_dicom.so" /usr/bin/time -v -o "$out/time" \
        "$dir/osteon" mesh "$series" --out "$out/x.ply" --json >"$out/json"
      wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$out/time" |
        awk -F: '{ print ($1 * 60) + $2 }')
      cpu=$(sed -n 's/.*\(User\|System\) time (seconds): //p' "$out/time" | awk '{ s += $1 } END { print s }')
      rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$out/time")
      load=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["setup_ms"]["load"])' \
        "$out/json")
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(basename "$series")" "$build" "$run" "$wall" "$cpu" \
        "$load" "$((rss / 1024))"
    done
  done
done
rm -rf "$out"
