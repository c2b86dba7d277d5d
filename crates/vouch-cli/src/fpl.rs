//! `vouch fpl …` subcommands (owned by the fpl family).

use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum FplCmd {
    /// Print what this family can do so far
    Info,
}

pub fn run(cmd: FplCmd) -> ExitCode {
    match cmd {
        FplCmd::Info => {
            println!("vouch fpl: not implemented yet");
            ExitCode::SUCCESS
        }
    }
}
