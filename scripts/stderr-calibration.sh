#!/usr/bin/env bash
# Measures how well gmonrt's per-pixel standard errors (--stderr) cover the
# error against the references: a markdown table per estimator of coverage at
# 1.96 stderr, median |error| / stderr and NaN stderr, for cornell-glass and
# cornell-diffuse at 64, 256 and 1024 spp (--quick: 32 and 64).
# Every option: scripts/stderr-calibration.sh --help.
exec "$(dirname "${BASH_SOURCE[0]}")/run-python.sh" gmon_sweep.calibration "$@"
