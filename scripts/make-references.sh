#!/usr/bin/env bash
# Regenerates the reference images references/<scene>.exr and their records
# references/<scene>.json (settings, commands, residual error estimated from
# two independent half renders). Default: every scene in scenes/, 128x128,
# 8192 spp, seed 1000; see scripts/make-references.sh --help.
exec "$(dirname "${BASH_SOURCE[0]}")/run-python.sh" gmon_sweep.references "$@"
