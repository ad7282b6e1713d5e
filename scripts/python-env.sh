#!/usr/bin/env bash
# Creates or updates the Python virtual environment build/venv with the pinned
# packages of scripts/python-requirements.txt, from PyPI. Idempotent: does
# nothing when the environment already matches the requirements file.
# Prints the environment's python on stdout.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/build/venv"
requirements="$root/scripts/python-requirements.txt"
stamp="$venv/requirements.installed"

"$root/scripts/install-deps.sh" # python3 and python3-venv among them
if [ ! -f "$stamp" ] || ! cmp -s "$requirements" "$stamp"; then
  echo "Setting up $venv from $requirements" >&2
  [ -x "$venv/bin/python" ] || python3 -m venv "$venv" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements" >&2
  cp "$requirements" "$stamp"
fi
echo "$venv/bin/python"
