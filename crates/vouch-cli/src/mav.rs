//! `vouch mav …` subcommands (owned by the mav family).

use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum MavCmd {
    /// Print what this family can do so far
    Info,
}

pub fn run(cmd: MavCmd) -> ExitCode {
    match cmd {
        MavCmd::Info => {
            println!("vouch mav: not implemented yet");
            ExitCode::SUCCESS
        }
    }
}
