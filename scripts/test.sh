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
# The Python package `vouch`: built by maturin (from PyPI) into the venv, tested with pytest
# (its tests compare with the `vouch` binary the line above built).
if [ -x .venv/bin/python ]; then
  .venv/bin/pip install -q --disable-pip-version-check ./crates/vouch-py
  .venv/bin/python -m pytest -q crates/vouch-py/tests
elif [ "${VOUCH_REQUIRE_PEERS:-}" = 1 ]; then
  echo "the Python package tests need .venv (run scripts/install-peers.sh)" >&2
  exit 1
fi
