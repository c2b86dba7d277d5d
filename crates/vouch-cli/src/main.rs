//! `vouch`: one binary, three families of doer/checker pairs.
//!
//! This file only dispatches; each family's subcommands live in their own module
//! (`fpl.rs`, `mav.rs`, `navfn.rs`) and call into the family's library crate.
//!
//! Exit codes shared by all families: 0 success, 1 input rejected (plan/map/protocol error),
//! 2 usage or I/O error, 3 violations found (checkers).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod fpl;
mod mav;
mod navfn;

#[derive(Parser)]
#[command(
    name = "vouch",
    version,
    about = "Pair every doer with a checker: flight plans, MAVLink, NavFn"
)]
struct Cli {
    #[command(subcommand)]
    family: Family,
}

#[derive(Subcommand)]
enum Family {
    /// Paparazzi flight plans: parse, compile to flight_plan.h, simulate, validate
    #[command(subcommand)]
    Fpl(fpl::FplCmd),
    /// MAVLink: protocol checking of recordings and a guarding proxy
    #[command(subcommand)]
    Mav(mav::MavCmd),
    /// ROS 2 nav2 NavFn planner, bit-exact, with checked plans and a verification campaign
    #[command(subcommand)]
    Navfn(navfn::NavfnCmd),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version on stdout with exit 0; real usage errors exit 2.
            let _ = e.print();
            return if e.use_stderr() { ExitCode::from(2) } else { ExitCode::SUCCESS };
        }
    };
    match cli.family {
        Family::Fpl(cmd) => fpl::run(cmd),
        Family::Mav(cmd) => mav::run(cmd),
        Family::Navfn(cmd) => navfn::run(cmd),
    }
}
