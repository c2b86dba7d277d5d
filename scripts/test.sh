#!/usr/bin/env bash
# The whole test suite: Rust unit/integration/property/snapshot tests of every crate, including
# the tests that talk to real peers (cc for generated C, pymavlink/MAVProxy/MAVSDK for the guard).
# Peers that are missing make their tests skip with a message; `.ci/run` installs them first.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -x .venv/bin/python ]; then
  export VOUCH_PYTHON="$PWD/.venv/bin/python"
  export PATH="$PWD/.venv/bin:$PATH"
fi
cargo test --workspace --release "$@"
