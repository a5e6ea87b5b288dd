#!/usr/bin/env bash
# The pinned comparison: osteon as of commit 76bc24c (the extractor's figures of 2026-11-22),
# built beside the current tree, and both timed against VTK's FlyingEdges on the same grids,
# interleaved run by run (bench/extract_interleaved.sh), so that a regression shows:
#   bench/pinned_build.sh [-n RUNS] [-c CPU] [-v VOLUMES] [SCRATCH]
# SCRATCH (default /tmp/osteon-pinned) holds a git worktree of the pinned commit and its
# Release build (ccache when installed; a second run reuses both). The current build is
# build/ of this tree, which must have osteon and osteon_bench_extract_peer built (VTK 9).
# PINNED=<commit> pins another commit.
set -euo pipefail

pinned="${PINNED:-76bc24c}"
args=()
while [[ "${1:-}" == -* ]]; do
  args+=("$1" "$2")
  shift 2
done
scratch="${1:-/tmp/osteon-pinned}"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
tree="$scratch/osteon-$pinned"

mkdir -p "$scratch"
if [[ ! -d "$tree" ]]; then
  git -C "$root" worktree add --detach "$tree" "$pinned" >/dev/null
fi
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
if [[ ! -f "$tree/build/build.ninja" ]]; then
  # Tests and benchmarks off: only the command is compared. Warnings are not errors: an old
  # tree meets newer compilers' warnings.
  cmake -S "$tree" -B "$tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DOSTEON_BUILD_TESTS=OFF -DOSTEON_BUILD_BENCH=OFF -DOSTEON_WERROR=OFF "${launcher[@]}" >/dev/null
fi
CCACHE_BASEDIR="$tree" CCACHE_NOHASHDIR=1 cmake --build "$tree/build" --target osteon -- -j"$(nproc)" >/dev/null
echo "pinned: $pinned ($(git -C "$tree" log -1 --format='%h %cs %s' | cut -c1-80))"
echo "current: $(git -C "$root" log -1 --format='%h %cs %s' | cut -c1-80)"
exec "$here/extract_interleaved.sh" "${args[@]}" "$root/build/cli/osteon" "$tree/build/cli/osteon"
