#!/usr/bin/env bash
# Start-up cost of the `osteon` command, side by side for two (or more) binaries:
#   bench/startup_bench.sh [-n RUNS] BINARY [BINARY...]
# e.g. bench/startup_bench.sh -n 21 /tmp/osteon-before build/cli/osteon
#
# For `osteon --help` and `osteon info default` it prints, per binary, the shared libraries
# the dynamic loader initialised (LD_DEBUG=libs), and the median over RUNS runs of the wall
# time (bash's EPOCHREALTIME around /usr/bin/time, so it includes time's own fork and exec,
# about 1 ms) and of the peak resident set size (/usr/bin/time %M). One warm-up run per
# command comes first, so the page cache is warm for every binary alike.
set -euo pipefail

runs=11
if [[ "${1:-}" == "-n" ]]; then
  runs="$2"
  shift 2
fi
if [[ $# -lt 1 ]]; then
  echo "usage: $0 [-n RUNS] BINARY [BINARY...]" >&2
  exit 2
fi
if [[ ! -x /usr/bin/time ]]; then
  echo "$0: needs /usr/bin/time (apt-get install time)" >&2
  exit 2
fi

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

median() {  # the median of the numbers on stdin
  sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

# Libraries the loader initialised for one run of the command (the program itself excluded).
libraries() {
  local log="$scratch/ld"
  rm -f "$log".*
  LD_DEBUG=libs LD_DEBUG_OUTPUT="$log" "$@" >/dev/null 2>&1 || true
  cat "$log".* | grep -c "calling init:" || true
}

printf '%-40s %-14s %6s %10s %12s\n' binary command libs "wall ms" "max RSS MB"
for binary in "$@"; do
  for command in "--help" "info default"; do
    read -r -a args <<<"$command"
    "$binary" "${args[@]}" >/dev/null 2>&1 || true  # warm-up
    : >"$scratch/wall"
    : >"$scratch/rss"
    for ((i = 0; i < runs; ++i)); do
      start=$EPOCHREALTIME
      /usr/bin/time -f '%M' -o "$scratch/one" "$binary" "${args[@]}" >/dev/null 2>&1
      end=$EPOCHREALTIME
      awk -v s="$start" -v e="$end" 'BEGIN { printf "%.1f\n", (e - s) * 1000 }' >>"$scratch/wall"
      awk '{ printf "%.1f\n", $1 / 1024 }' "$scratch/one" >>"$scratch/rss"
    done
    printf '%-40s %-14s %6s %10s %12s\n' "$binary" "$command" "$(libraries "$binary" "${args[@]}")" \
      "$(median <"$scratch/wall")" "$(median <"$scratch/rss")"
  done
done
echo "($runs runs each; medians; $(nproc) CPUs: $(lscpu | sed -n 's/^Model name: *//p' | head -1))"
