#!/usr/bin/env bash
# Regenerates docs/results.md and docs/results/ (plots, CSVs): sweeps of every
# scene with a reference in references/, for M in 5,11,21,25 up to 1024 spp.
# Every option: scripts/results.sh --help.
exec "$(dirname "${BASH_SOURCE[0]}")/run-python.sh" gmon_sweep.results "$@"
