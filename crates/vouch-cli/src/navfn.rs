//! `vouch navfn …` subcommands (owned by the navfn family).

use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum NavfnCmd {
    /// Print what this family can do so far
    Info,
}

pub fn run(cmd: NavfnCmd) -> ExitCode {
    match cmd {
        NavfnCmd::Info => {
            println!("vouch navfn: not implemented yet");
            ExitCode::SUCCESS
        }
    }
}
