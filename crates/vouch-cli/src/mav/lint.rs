//! `vouch mav lint`: compile protocol files and list what they define.

use std::path::PathBuf;

use clap::Args;
use vouch_mav::monitor::MonitorSpec;
use vouch_mav::protocol::ir::UnverifiablePolicy;

use super::load_failure;
use crate::contract::{CmdResult, Ctx, Exit};

/// Arguments of `vouch mav lint`.
#[derive(Args)]
pub struct LintArgs {
    /// Protocol files (none: the standard library)
    #[arg(value_name = "PROTOCOL")]
    pub files: Vec<PathBuf>,
    /// MAVLink XML dialect (default: ardupilotmega with its includes, built in)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
    /// Print one JSON document: the protocols with their states, messages and roles
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: LintArgs, ctx: &mut Ctx) -> CmdResult {
    let spec = MonitorSpec { dialect: a.dialect, protocols: a.files, ..MonitorSpec::default() };
    let monitor = spec.build().map_err(load_failure)?;
    let protocols: Vec<serde_json::Value> = monitor
        .protocols()
        .protocols
        .iter()
        .map(|p| {
            serde_json::json!({
                "protocol": p.name,
                "states": p.states.len(),
                "messages": p.alphabet.len(),
                "roles": p.roles.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
                "unverifiable": p.unverifiable,
            })
        })
        .collect();
    if a.json {
        ctx.out.json(&serde_json::json!({ "protocols": protocols }))?;
        return Ok(Exit::Ok);
    }
    for p in &monitor.protocols().protocols {
        let roles: Vec<&str> = p.roles.iter().map(|(n, _)| n.as_str()).collect();
        let policy = match p.unverifiable {
            UnverifiablePolicy::Pass => "pass",
            UnverifiablePolicy::Drop => "drop",
        };
        writeln!(
            ctx.out,
            "ok: protocol {} ({} states, {} messages, roles {}; unverifiable answers: {policy})",
            p.name,
            p.states.len(),
            p.alphabet.len(),
            roles.join(", ")
        )?;
    }
    Ok(Exit::Ok)
}
