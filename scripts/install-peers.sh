#!/usr/bin/env bash
# Installs the real peers the tests talk to: a Python venv with pymavlink, MAVProxy and MAVSDK
# (all from PyPI), Dask distributed (the engine of the navfn campaign's distributed test), and
# socat (Debian) for the do-nothing relay of the guard benchmark.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v socat >/dev/null 2>&1; then
  (apt-get update -qq && apt-get install -y -qq socat) >/dev/null 2>&1 || echo "socat not installed (benchmark relay will be skipped)"
fi
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
.venv/bin/pip install -q --disable-pip-version-check pymavlink==2.4.50 MAVProxy==1.8.75 mavsdk==4.1.0
.venv/bin/pip install -q --disable-pip-version-check dask==2026.8.0 distributed==2026.8.0
