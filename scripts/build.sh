#!/usr/bin/env bash
# Installs what is missing, then configures and builds into build/.
# Extra arguments go to CMake's configure step.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGMON_WERROR=ON "$@" >/dev/null
cmake --build "$root/build" -j "$(nproc)"
