#!/usr/bin/env bash
# gmonrt against upstream pbrt-v4 on the shared scenes (bench/compare_pbrt.py):
# image mean, per-pixel variance (whole image, 4x4 regions, lit surfaces), time
# and efficiency at 64 spp, seeds 1 and 2, after building gmonrt and setting up
# build/venv when needed.
#   scripts/compare-pbrt.sh --scenes cornell-box,veach-mis --csv build/compare-pbrt.csv
# Every option: scripts/compare-pbrt.sh --help.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
python="$("$root/scripts/python-env.sh")"
# PoCL shows no device at all without a writable cache directory.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$root/build/pocl-cache}"
mkdir -p "$POCL_CACHE_DIR"
exec "$python" "$root/bench/compare_pbrt.py" "$@"
