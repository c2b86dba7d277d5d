//! `vouch`: one binary, three families of doer/checker pairs.
//!
//! This library is the whole command line (the binary only calls [`run`]); it is a library so
//! that tests, completions and man pages see the same clap command tree. Each family's
//! subcommands live in their own module (`fpl`, `mav`, `navfn`) and call into the family's
//! library crate.
//!
//! The command contract (exit codes, pipe-safe output, diagnostics printed once) is in
//! `contract.rs`.

// The command line is the one place that prints (through `contract.rs` and `diagnostics.rs`)
// and exits (in `main.rs`); it still never unwraps or panics on its own.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::dbg_macro,
        clippy::todo,
        clippy::unimplemented
    )
)]

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[macro_use]
mod help;
pub mod contract;
mod diagnostics;
mod fpl;
mod mav;
mod navfn;
pub mod safe_text;
mod tooling;

use contract::{CmdResult, Ctx, Exit, Failure, MessageFormat, Out, Severity, Verbosity};

/// The whole command line.
#[derive(Parser)]
#[command(
    name = "vouch",
    version,
    about = "Pair every doer with a checker: flight plans, MAVLink, NavFn",
    after_help = after_help!([
        "vouch fpl compile examples/fpl/demo.xml -o flight_plan.h",
        "vouch mav lint",
        "vouch navfn plan examples/navfn/warehouse.yaml --start 1,1 --goal 8.5,6.5",
        "vouch fpl compile -h          # every command has its own page"
    ])
)]
pub struct Cli {
    /// How errors and warnings are printed on stderr
    ///
    /// human: boxes with the source excerpt; short: `file:line:col: error[CODE]: message`
    /// lines, for editors and CI; json: one JSON object per line.
    #[arg(
        long,
        global = true,
        value_enum,
        value_name = "FORMAT",
        default_value_t = MessageFormat::Human,
        help_heading = "Global options"
    )]
    message_format: MessageFormat,
    /// Print errors only (no warnings, summaries or progress)
    #[arg(short, long, global = true, conflicts_with = "verbose", help_heading = "Global options")]
    quiet: bool,
    /// Print more detail (progress, per-item notes)
    #[arg(short, long, global = true, help_heading = "Global options")]
    verbose: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Paparazzi flight plans: compile to flight_plan.h, simulate, validate, check
    #[command(
        subcommand,
        after_help = after_help!([
            "vouch fpl compile examples/fpl/demo.xml -o flight_plan.h",
            "vouch fpl validate examples/fpl/demo.xml",
            "vouch fpl check examples/fpl/demo.xml --deadlock-free"
        ])
    )]
    Fpl(fpl::FplCmd),
    /// MAVLink: a guarding router, and protocol checks of recordings
    #[command(
        subcommand,
        after_help = after_help!([
            "vouch mav check flight.tlog",
            "vouch mav guard -c packaging/guard.conf.example --check",
            "vouch mav lint"
        ])
    )]
    Mav(mav::MavCmd),
    /// The ROS 2 nav2 NavFn planner, bit-exact, with checked plans and a campaign
    #[command(
        subcommand,
        after_help = after_help!([
            "vouch navfn plan examples/navfn/warehouse.yaml --start 1,1 --goal 8.5,6.5",
            "vouch navfn check-bag examples/navfn/warehouse_bag",
            "vouch navfn campaign examples/navfn/suite -o report.json"
        ])
    )]
    Navfn(navfn::NavfnCmd),
    /// Print a shell completion script on standard output
    #[command(after_help = after_help!(
        ["vouch completions bash > ~/.local/share/bash-completion/completions/vouch"],
        "0 written, 2 usage or I/O error"
    ))]
    Completions(tooling::CompletionsArgs),
    /// Write man pages (one per command) into a directory, or the top page to stdout
    #[command(after_help = after_help!(
        ["vouch man -o ~/.local/share/man/man1"],
        "0 written, 2 usage or I/O error"
    ))]
    Man(tooling::ManArgs),
}

/// Parses the command line, runs the command and returns its exit code.
pub fn run() -> ExitCode {
    let args = fpl::upstream_args(std::env::args_os());
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        // clap prints help and version on stdout, exit 0
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => return command_line_error(&e, &args),
    };
    let verbosity = match (cli.quiet, cli.verbose) {
        (true, _) => Verbosity::Quiet,
        (_, true) => Verbosity::Verbose,
        _ => Verbosity::Normal,
    };
    let mut ctx = Ctx { out: Out::stdout(), format: cli.message_format, verbosity };
    contract::set_family(match &cli.command {
        Command::Fpl(_) => "fpl",
        Command::Mav(_) => "mav",
        Command::Navfn(_) => "navfn",
        Command::Completions(_) | Command::Man(_) => "vouch",
    });
    let result = match cli.command {
        Command::Fpl(cmd) => fpl::run(cmd, &mut ctx),
        Command::Mav(cmd) => mav::run(cmd, &mut ctx),
        Command::Navfn(cmd) => navfn::run(cmd, &mut ctx),
        Command::Completions(a) => tooling::completions(a, &mut ctx),
        Command::Man(a) => tooling::man(a, &mut ctx),
    };
    finish(result, &mut ctx).into()
}

/// A command line that does not parse: clap's message as a coded diagnostic of the family
/// named on it (`vouch` when none is), in the `--message-format` given if that much can be
/// read, escaped like every other message; exit 2.
fn command_line_error(e: &clap::Error, args: &[std::ffi::OsString]) -> ExitCode {
    let words: Vec<&str> = args.iter().skip(1).filter_map(|a| a.to_str()).collect();
    let family = words
        .iter()
        .find_map(|w| ["fpl", "mav", "navfn"].into_iter().find(|f| f == w))
        .unwrap_or("vouch");
    contract::set_family(family);
    let format = words
        .iter()
        .enumerate()
        .find_map(|(i, w)| match w.strip_prefix("--message-format") {
            Some("") => words.get(i + 1).copied(),
            Some(v) => v.strip_prefix('='),
            None => None,
        })
        .and_then(|v| <MessageFormat as clap::ValueEnum>::from_str(v, true).ok())
        .unwrap_or_default();
    let mut ctx = Ctx { out: Out::stdout(), format, verbosity: Verbosity::Normal };
    let failure = contract::syntax_failure(&e.render().to_string());
    finish(Err(failure), &mut ctx).into()
}

/// Flushes the main output, prints a failure once and chooses the exit code.
fn finish(result: CmdResult, ctx: &mut Ctx) -> Exit {
    let result = result.and_then(|exit| ctx.out.flush().map(|()| exit));
    match result {
        Ok(exit) => exit,
        Err(failure) => {
            if let Failure::Rejected(report) | Failure::Usage(report) = &failure {
                diagnostics::print(ctx.format, report.as_ref(), Severity::Error);
            }
            failure.exit()
        }
    }
}
