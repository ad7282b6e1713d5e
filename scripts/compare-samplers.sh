#!/usr/bin/env bash
# gmonrt's samplers against one another on one scene (bench/compare_samplers.py):
# the variance of the mean, var / stderr^2 (1: honest standard errors), MoN's
# and G-MoN's MSE and the time of a render, over --seeds renders of each
# sampler, after building gmonrt and setting up build/venv when needed.
#   scripts/compare-samplers.sh ../shared/scenes/cornell-box/cornell-box.pbrt --resolution 64x64 --spp 64 --seeds 4
# Every option: scripts/compare-samplers.sh --help.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exec "$root/scripts/run-python.sh" "$root/bench/compare_samplers.py" "$@"
