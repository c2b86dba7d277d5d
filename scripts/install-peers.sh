#!/usr/bin/env bash
# Installs the real peers the tests talk to: a Python venv with pymavlink, MAVProxy and MAVSDK,
# rosbags and mcap-ros2-support (all from PyPI), Dask distributed (the engine of the navfn
# campaign's distributed test), socat (Debian) for the do-nothing relay of the guard benchmark, and
# for `vouch fpl validate --target cortex-m4|cortex-m7` the ARM cross compiler with its C library
# and the emulator (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v socat >/dev/null 2>&1; then
  (apt-get update -qq && apt-get install -y -qq socat) >/dev/null 2>&1 || echo "socat not installed (benchmark relay will be skipped)"
fi
if ! command -v arm-none-eabi-gcc >/dev/null 2>&1 || ! command -v qemu-system-arm >/dev/null 2>&1 \
  || [ ! -d /usr/lib/arm-none-eabi/newlib ]; then
  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm) >/dev/null 2>&1 \
    || echo "ARM cross compiler or QEMU not installed (the fpl --target cortex-m tests will be skipped)"
fi
if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
.venv/bin/pip install -q --disable-pip-version-check pymavlink==2.4.50 MAVProxy==1.8.75 mavsdk==4.1.0
# navfn: the ROS ecosystem's bag writers (rosbags; mcap + mcap-ros2-support with their
# compressors), numpy and pytest for the Python package `vouch`, maturin to build it
.venv/bin/pip install -q --disable-pip-version-check rosbags==0.11.9 mcap==1.6.0 \
  mcap-ros2-support==0.6.0 zstandard==0.25.0 lz4==4.4.5 numpy==2.3.5 pytest==9.2.0 maturin==1.16.0
.venv/bin/pip install -q --disable-pip-version-check dask==2026.8.0 distributed==2026.8.0
