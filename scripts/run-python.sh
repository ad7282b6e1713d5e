#!/usr/bin/env bash
# Runs a module of scripts/gmon_sweep, or a Python file (bench/*.py), with
# the scripts' Python environment, after building gmonrt and setting up
# build/venv when needed:
#   scripts/run-python.sh gmon_sweep.sweep ARGS...
#   scripts/run-python.sh bench/compare_pbrt.py ARGS...
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
python="$("$root/scripts/python-env.sh")"
# PoCL shows no device at all without a writable cache directory.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$root/build/pocl-cache}"
mkdir -p "$POCL_CACHE_DIR"
module="$1"
shift
case "$module" in
*.py) exec "$python" "$module" "$@" ;;
*) PYTHONPATH="$root/scripts" exec "$python" -m "$module" "$@" ;;
esac
