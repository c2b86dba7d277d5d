//! Test-only helpers shared by every crate of the workspace.
//!
//! Tests that need reference data (`../shared`, beside the repository) or a real peer (a C
//! compiler, the Python venv with pymavlink/MAVProxy/MAVSDK) ask for it here. When it is missing
//! they get `None` and a `skipping: …` message on stderr — unless the environment says the
//! dependency is required (`VOUCH_REQUIRE_SHARED=1`, `VOUCH_REQUIRE_PEERS=1`, both set by CI), in
//! which case the test fails with the same message. A green run in CI therefore never hides a
//! skipped golden comparison.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Which kind of dependency a test asked for; selects the variable that makes it mandatory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// Reference data under `../shared` (`VOUCH_REQUIRE_SHARED`).
    Shared,
    /// A real peer program: compiler, interpreter, relay (`VOUCH_REQUIRE_PEERS`).
    Peer,
}

impl Need {
    fn variable(self) -> &'static str {
        match self {
            Need::Shared => "VOUCH_REQUIRE_SHARED",
            Need::Peer => "VOUCH_REQUIRE_PEERS",
        }
    }

    /// Whether the environment makes a missing dependency of this kind a failure.
    pub fn required(self) -> bool {
        std::env::var(self.variable()).is_ok_and(|v| v == "1")
    }
}

/// Reports a missing dependency: `None` with a skip message, or a panic when it is required.
pub fn missing<T>(need: Need, what: &str) -> Option<T> {
    if need.required() {
        panic!("{what} is required here ({}=1) but missing", need.variable());
    }
    eprintln!("skipping: {what}");
    None
}

/// The repository's root directory (two levels above any crate's manifest directory).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `../shared/<rel>` beside the repository, if it holds `marker` (a file that proves the data is
/// complete), else a skip (or a failure under `VOUCH_REQUIRE_SHARED=1`).
pub fn shared(rel: &str, marker: &str) -> Option<PathBuf> {
    let dir = repo_root().join("../shared").join(rel);
    if dir.join(marker).exists() {
        Some(dir)
    } else {
        missing(Need::Shared, &format!("{} not found", dir.join(marker).display()))
    }
}

/// The C compiler (`$CC` or `cc`) if it runs, else a skip (or a failure under
/// `VOUCH_REQUIRE_PEERS=1`).
pub fn c_compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    match Command::new(&cc).arg("--version").output() {
        Ok(o) if o.status.success() => Some(cc),
        _ => missing(Need::Peer, &format!("no C compiler ({cc}) can be run")),
    }
}

/// The Python interpreter of the peer venv (`$VOUCH_PYTHON`, set by `scripts/test.sh`) if it can
/// import every module in `modules`, else a skip (or a failure under `VOUCH_REQUIRE_PEERS=1`).
pub fn python_with(modules: &[&str]) -> Option<String> {
    let Ok(py) = std::env::var("VOUCH_PYTHON") else {
        return missing(
            Need::Peer,
            "VOUCH_PYTHON is not set (run scripts/install-peers.sh, then scripts/test.sh)",
        );
    };
    for m in modules {
        let ok = Command::new(&py)
            .args(["-c", &format!("import {m}")])
            .output()
            .is_ok_and(|o| o.status.success());
        if !ok {
            return missing(Need::Peer, &format!("{py} cannot import {m}"));
        }
    }
    Some(py)
}

/// A program on `PATH` (e.g. `socat`) if it can be started, else a skip (or a failure under
/// `VOUCH_REQUIRE_PEERS=1`).
pub fn program(name: &str, version_arg: &str) -> Option<PathBuf> {
    match Command::new(name).arg(version_arg).output() {
        Ok(_) => Some(PathBuf::from(name)),
        Err(e) => missing(Need::Peer, &format!("{name} cannot be run ({e})")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_marker_is_a_skip_or_a_failure_as_the_environment_says() {
        let result = std::panic::catch_unwind(|| shared("fpl", "no-such-marker-file"));
        if Need::Shared.required() {
            assert!(result.is_err(), "a required dependency must fail the test");
        } else {
            assert!(matches!(result, Ok(None)));
        }
    }
}
