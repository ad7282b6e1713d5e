#!/usr/bin/env bash
# gmonrt against upstream pbrt-v4 on the shared scenes (bench/compare_pbrt.py):
# image mean, per-pixel variance (whole image, 4x4 regions, lit surfaces), time
# and efficiency at 64 spp, seeds 1 and 2, after building gmonrt and setting up
# build/venv when needed.
#   scripts/compare-pbrt.sh --scenes cornell-box,veach-mis --csv build/compare-pbrt.csv
# Every option: scripts/compare-pbrt.sh --help.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exec "$root/scripts/run-python.sh" "$root/bench/compare_pbrt.py" "$@"
