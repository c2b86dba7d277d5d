//! `vouch completions` and `vouch man`: generated from the same clap command tree as the parser.

use std::path::PathBuf;

use clap::{Args, CommandFactory};
use clap_complete::Shell;

use crate::Cli;
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch completions`.
#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell to write the completion script for
    #[arg(value_enum)]
    shell: Shell,
}

/// Arguments of `vouch man`.
#[derive(Args)]
pub struct ManArgs {
    /// Directory that receives one page per command (`vouch.1`, `vouch-fpl-compile.1`, …);
    /// without it the top page is written to standard output
    #[arg(short, long, value_name = "DIR")]
    output: Option<PathBuf>,
}

/// Writes the completion script of `shell` to standard output.
pub fn completions(a: CompletionsArgs, ctx: &mut Ctx) -> CmdResult {
    let mut cmd = Cli::command();
    let mut script = Vec::new();
    clap_complete::generate(a.shell, &mut cmd, "vouch", &mut script);
    ctx.out.write_all(&script)?;
    Ok(Exit::Ok)
}

/// Writes the man pages (a directory) or the top page (standard output).
pub fn man(a: ManArgs, ctx: &mut Ctx) -> CmdResult {
    let cmd = Cli::command();
    match a.output {
        Some(dir) => {
            std::fs::create_dir_all(&dir).map_err(|e| Failure::io(&dir, &e))?;
            clap_mangen::generate_to(cmd, &dir).map_err(|e| Failure::io(&dir, &e))?;
            Ok(Exit::Ok)
        }
        None => {
            let mut page = Vec::new();
            clap_mangen::Man::new(cmd)
                .render(&mut page)
                .map_err(|e| Failure::usage(format_args!("man page: {e}")))?;
            ctx.out.write_all(&page)?;
            Ok(Exit::Ok)
        }
    }
}
