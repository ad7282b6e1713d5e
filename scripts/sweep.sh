#!/usr/bin/env bash
# Convergence sweep of one scene against its reference: CSV and plots of
# error against spp and time for mean, MoN and G-MoN, in build/sweep/<scene>/.
#   scripts/sweep.sh scenes/cornell-glass.pbrt --max-spp 1024 --sets 5,21
# Every option: scripts/sweep.sh --help.
exec "$(dirname "${BASH_SOURCE[0]}")/run-python.sh" gmon_sweep.sweep "$@"
