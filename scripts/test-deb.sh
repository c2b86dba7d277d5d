#!/usr/bin/env bash
# Builds the .deb, installs it with dpkg on this machine, runs commands from the installed path,
# then removes it again. Needs root (as on CI) and dpkg.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build-deb.sh
deb=$(ls -t target/debian/vouch_*.deb | head -1)
dpkg -i "$deb"
trap 'dpkg -r vouch >/dev/null' EXIT
fail() { echo "deb test: $*" >&2; exit 1; }
[ -x /usr/bin/vouch ] || fail "/usr/bin/vouch missing"
/usr/bin/vouch --version | grep -q '^vouch ' || fail "vouch --version"
out=$(mktemp -d)
/usr/bin/vouch fpl compile examples/fpl/demo.xml -o "$out/flight_plan.h"
grep -q 'auto_nav' "$out/flight_plan.h" || fail "compiled header lacks auto_nav"
for page in vouch vouch-fpl-compile vouch-mav-guard vouch-navfn-plan; do
  [ -f "/usr/share/man/man1/$page.1.gz" ] || fail "man page $page missing"
done
if command -v man >/dev/null 2>&1; then man -w vouch >/dev/null || fail "man -w vouch"; fi
[ -f /usr/share/bash-completion/completions/vouch ] || fail "bash completion missing"
bash -n /usr/share/bash-completion/completions/vouch || fail "bash completion syntax"
[ -f /usr/share/zsh/vendor-completions/_vouch ] || fail "zsh completion missing"
[ -f /usr/share/fish/vendor_completions.d/vouch.fish ] || fail "fish completion missing"
[ -f /lib/systemd/system/vouch-guard.service ] || fail "systemd unit missing"
grep -q '^ExecStart=/usr/bin/vouch mav guard -c /etc/vouch/guard.conf' /lib/systemd/system/vouch-guard.service \
  || fail "systemd unit does not start the guard with its configuration"
/usr/bin/vouch mav guard -c /etc/vouch/guard.conf --check >/dev/null \
  || fail "the installed guard configuration is not accepted"
rm -rf "$out"
echo "deb test: $deb installed, commands ran from /usr/bin, man pages, completions and unit in place"
