#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, only those missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config clang clang-format
  libclang-rt-dev llvm
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers clinfo
  libopenexr-dev libpng-dev libcglm-dev libcmocka-dev zlib1g-dev
  python3 python3-venv
  libstb-dev libnanovdb-dev libblosc-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "Installing: ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
# Wait for another install's package lock (up to 10 minutes) instead of
# failing.
lock_wait=(-o DPkg::Lock::Timeout=600)
$sudo apt-get "${lock_wait[@]}" update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get "${lock_wait[@]}" install -y -qq --no-install-recommends "${missing[@]}" >&2
