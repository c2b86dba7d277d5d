//! What the CLI tests share: running the built `vouch` binary and reading its exit code.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `vouch ARGS` in the test's working directory.
pub fn vouch(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vouch")).args(args).output().expect("the vouch binary runs")
}

/// Runs `vouch ARGS` from the repository root, where the bundled examples' relative paths hold.
pub fn vouch_at_root(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vouch"))
        .args(args)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .expect("the vouch binary runs")
}

/// The exit code (a test fails if the process was killed by a signal).
pub fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed")
}
