//! `vouch mav lint`: compile protocol files, list what they define, and warn (`mav::R001`, located
//! in the protocol text) about every route to a guarded action that no loaded protocol covers.

use std::path::PathBuf;

use clap::Args;
use vouch_mav::Dialect;
use vouch_mav::monitor::{LoadError, MonitorSpec};
use vouch_mav::protocol::ir::{ProtocolSet, Route, UnverifiablePolicy};
use vouch_mav::protocol::load_protocols;
use vouch_mav::protocol::routes::{RouteWarning, describe_route, route_gaps};

use super::load_failure;
use crate::contract::{CmdResult, Ctx, Exit};

/// Arguments of `vouch mav lint`.
#[derive(Args)]
pub struct LintArgs {
    /// Protocol files (none: the standard library)
    #[arg(value_name = "PROTOCOL")]
    pub files: Vec<PathBuf>,
    /// Also load the standard library when files are given (their routes count as covered)
    #[arg(long)]
    pub with_stdlib: bool,
    /// MAVLink XML dialect (default: ardupilotmega with its includes, built in)
    #[arg(long, value_name = "FILE.xml")]
    pub dialect: Option<PathBuf>,
    /// Print one JSON document: the protocols, the effects with their routes, the unguarded routes
    #[arg(long)]
    pub json: bool,
}

/// The protocols that cover a route.
fn guarded_by<'s>(set: &'s ProtocolSet, r: &Route) -> Vec<&'s str> {
    set.protocols.iter().filter(|p| p.covers.contains(r)).map(|p| p.name.as_str()).collect()
}

fn route_json(dialect: &Dialect, set: &ProtocolSet, r: &Route) -> serde_json::Value {
    serde_json::json!({
        "route": describe_route(dialect, r),
        "class": r.class,
        "message": dialect.message(r.msg).name,
        "command": r.command.and_then(|c| dialect.enum_value_name("MAV_CMD", u64::from(c))),
        "guarded_by": guarded_by(set, r),
    })
}

pub fn run(a: LintArgs, ctx: &mut Ctx) -> CmdResult {
    let spec = MonitorSpec {
        dialect: a.dialect,
        protocols: a.files,
        with_stdlib: a.with_stdlib,
        ..MonitorSpec::default()
    };
    let dialect = spec.load_dialect().map_err(|e| load_failure(LoadError::from(e)))?;
    let sources = spec.sources().map_err(load_failure)?;
    let set =
        load_protocols(&dialect, &sources, &[]).map_err(|e| load_failure(LoadError::from(e)))?;
    let gaps = route_gaps(&set);
    for g in &gaps {
        ctx.warn(&RouteWarning::new(&dialect, g, &sources));
    }
    if a.json {
        let protocols: Vec<serde_json::Value> = set
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
        let effects: Vec<serde_json::Value> = set
            .effects
            .iter()
            .map(|e| {
                let routes: Vec<_> =
                    e.routes.iter().map(|r| route_json(&dialect, &set, &r.route)).collect();
                serde_json::json!({ "effect": e.name, "routes": routes })
            })
            .collect();
        let unguarded: Vec<_> = gaps
            .iter()
            .map(|g| {
                let mut v = route_json(&dialect, &set, &g.route);
                v["subject"] = serde_json::json!(g.subject);
                v
            })
            .collect();
        ctx.out.json(&serde_json::json!({
            "protocols": protocols,
            "effects": effects,
            "unguarded_routes": unguarded,
        }))?;
        return Ok(Exit::Ok);
    }
    for p in &set.protocols {
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
    for e in &set.effects {
        let open = e.routes.iter().filter(|r| guarded_by(&set, &r.route).is_empty()).count();
        let state = match open {
            0 => "every route guarded".to_string(),
            n => format!("{n} not guarded"),
        };
        writeln!(ctx.out, "ok: effect {} ({} routes, {state})", e.name, e.routes.len())?;
    }
    Ok(Exit::Ok)
}
