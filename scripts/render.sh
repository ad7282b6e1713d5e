#!/usr/bin/env bash
# The README's render command: installs what is missing, builds, and renders
# the default scene to render.exr and render.png in the current directory.
# Arguments are passed to gmonrt (see gmonrt --help).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh"
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$root/build/pocl-cache}"
mkdir -p "$POCL_CACHE_DIR"
exec "$root/build/gmonrt" "$@"
