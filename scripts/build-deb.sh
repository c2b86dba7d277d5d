#!/usr/bin/env bash
# Builds the Debian package of vouch (target/debian/vouch_*.deb) with cargo-deb: the binary, one
# man page per command, shell completions and the guard's systemd unit.
# Needs cargo-deb (`cargo install cargo-deb --locked`); installs it when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v cargo-deb >/dev/null 2>&1 || cargo install cargo-deb --locked --quiet
cargo build --release -p vouch-cli
assets=target/assets
rm -rf "$assets" && mkdir -p "$assets/man" "$assets/completions"
./target/release/vouch man -o "$assets/man"
gzip -9n "$assets"/man/*.1
./target/release/vouch completions bash > "$assets/completions/vouch.bash"
./target/release/vouch completions zsh > "$assets/completions/_vouch"
./target/release/vouch completions fish > "$assets/completions/vouch.fish"
cargo deb -p vouch-cli --no-build --quiet
ls target/debian/*.deb
