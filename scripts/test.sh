#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, sets up the
# Python environment, runs every test.
# Under CI=true a missing OpenCL device fails the tests instead of skipping.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh"
# The Python tests (metrics, the sweep) run in build/venv.
"$root/scripts/python-env.sh" >/dev/null
# PoCL shows no device at all without a writable cache directory.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$root/build/pocl-cache}"
mkdir -p "$POCL_CACHE_DIR"
cd "$root/build"
ctest --output-on-failure
