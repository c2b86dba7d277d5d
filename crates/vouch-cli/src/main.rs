//! The `vouch` binary: everything is in the library (`vouch_cli::run`).

fn main() -> std::process::ExitCode {
    vouch_cli::run()
}
