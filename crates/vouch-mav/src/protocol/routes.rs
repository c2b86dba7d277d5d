//! Routes to actions, derived from the dialect, and the route check of `vouch mav lint`.
//!
//! A vehicle can be made to perform an action (an *effect*) by several messages: a command that
//! runs when it arrives (`COMMAND_LONG`, `COMMAND_INT`), an item of an uploaded mission that runs
//! when the mission reaches it (`MISSION_ITEM`, `MISSION_ITEM_INT`), a command that drives the
//! output the action is wired to (`DO_SET_SERVO`, `DO_SET_RELAY`, …) and an RC channel
//! overridden from the ground (`RC_CHANNELS_OVERRIDE`). The carriers are read from the dialect:
//! every message with a `command` field of enum MAV_CMD, a `param1` and a target carries
//! commands (with a `seq` it is a mission item), every message with `chan1_raw` and a target
//! overrides RC input. Which MAV_CMD entries drive an output by number is the one table here
//! ([`OUTPUT_COMMANDS`]), as ArduPilot reads them (`AP_Mission::mavlink_int_to_mission_cmd`).
//!
//! [`route_gaps`] compares what the loaded declarations demand (every route of a declared effect;
//! every carrier of a command that some step checks on one carrier) with what the loaded
//! protocols cover, and [`RouteWarning`] locates each gap in the protocol text.

use std::fmt;

use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};

use super::ast::OutputKind;
use super::ir::{Demand, ProtocolSet, Route, RouteClass};
use crate::dialect::{Dialect, MessageDef, MsgIndex};

/// MAV_CMD entries that drive a vehicle output chosen by number, with the kind of output. The
/// output number is `param1` and the value `param2` in all of them (ArduPilot 4.x,
/// `AP_Mission::mavlink_int_to_mission_cmd`, `GCS_MAVLINK::handle_servorelay_message`).
pub const OUTPUT_COMMANDS: &[(&str, OutputKind)] = &[
    ("MAV_CMD_DO_SET_SERVO", OutputKind::Servo),
    ("MAV_CMD_DO_REPEAT_SERVO", OutputKind::Servo),
    ("MAV_CMD_DO_SET_RELAY", OutputKind::Relay),
    ("MAV_CMD_DO_REPEAT_RELAY", OutputKind::Relay),
];

/// The messages of a dialect that can make a vehicle act, by route class.
#[derive(Debug, Clone, Default)]
pub struct Carriers {
    /// Commands performed on arrival.
    pub command: Vec<MsgIndex>,
    /// Mission items.
    pub mission: Vec<MsgIndex>,
    /// RC input overrides.
    pub rc: Vec<MsgIndex>,
}

impl Carriers {
    /// The carriers of `dialect` (see the module documentation).
    pub fn of(dialect: &Dialect) -> Carriers {
        let mut c = Carriers::default();
        for (i, m) in dialect.messages().iter().enumerate() {
            let Ok(idx) = MsgIndex::try_from(i) else { continue };
            if m.field("target_system").is_none() {
                continue;
            }
            if carries_commands(m) {
                if m.field("seq").is_some() {
                    c.mission.push(idx);
                } else {
                    c.command.push(idx);
                }
            } else if m.field("chan1_raw").is_some() {
                c.rc.push(idx);
            }
        }
        c
    }

    /// The carriers of one route class.
    pub fn of_class(&self, class: RouteClass) -> &[MsgIndex] {
        match class {
            RouteClass::Command => &self.command,
            RouteClass::Mission => &self.mission,
            RouteClass::Rc => &self.rc,
        }
    }

    /// Every route by which the vehicle can be made to run `command`.
    pub fn command_routes(&self, command: u32) -> Vec<Route> {
        let on = |class: RouteClass| {
            self.of_class(class).iter().map(move |&msg| Route {
                class,
                msg,
                command: Some(command),
            })
        };
        on(RouteClass::Command).chain(on(RouteClass::Mission)).collect()
    }

    /// Every route that overrides RC input.
    pub fn rc_routes(&self) -> Vec<Route> {
        self.rc.iter().map(|&msg| Route { class: RouteClass::Rc, msg, command: None }).collect()
    }

    /// The class of a carrier message, if it is one.
    pub fn class_of(&self, msg: MsgIndex) -> Option<RouteClass> {
        [RouteClass::Command, RouteClass::Mission, RouteClass::Rc]
            .into_iter()
            .find(|&c| self.of_class(c).contains(&msg))
    }
}

/// A `command` field of enum MAV_CMD and the command's first parameter: the message asks the
/// vehicle to run a command (COMMAND_ACK has the field but no parameters).
fn carries_commands(m: &MessageDef) -> bool {
    m.field("command").is_some_and(|f| f.enum_name.as_deref() == Some("MAV_CMD"))
        && m.field("param1").is_some()
}

/// The MAV_CMD value of an entry name, when the dialect has it.
pub fn mav_cmd(dialect: &Dialect, name: &str) -> Option<u32> {
    match dialect.enum_entry(name) {
        Some(("MAV_CMD", v)) => u32::try_from(v).ok(),
        _ => None,
    }
}

/// A route that a loaded declaration demands and no loaded protocol covers.
#[derive(Debug, Clone)]
pub struct RouteGap {
    pub route: Route,
    /// What is guarded elsewhere (`MAV_CMD_…`, `effect NAME`).
    pub subject: String,
    pub origin: super::ir::Origin,
}

/// Every route demanded and not covered, once each, located at the first declaration that
/// demands it.
pub fn route_gaps(set: &ProtocolSet) -> Vec<RouteGap> {
    let covered: Vec<Route> = set.protocols.iter().flat_map(|p| p.covers.iter().copied()).collect();
    let mut out: Vec<RouteGap> = Vec::new();
    for Demand { subject, routes, origin } in &set.demands {
        for r in routes {
            let dup = out.iter().any(|g| g.route == *r);
            if !covered.contains(r) && !dup {
                out.push(RouteGap { route: *r, subject: subject.clone(), origin: *origin });
            }
        }
    }
    out
}

/// Describes a route: `COMMAND_INT carrying MAV_CMD_DO_PARACHUTE (command)`.
pub fn describe_route(dialect: &Dialect, r: &Route) -> String {
    let msg = &dialect.message(r.msg).name;
    match r.command {
        Some(c) => {
            let cmd = dialect.enum_value_name("MAV_CMD", u64::from(c)).unwrap_or("?");
            format!("{msg} carrying {cmd} ({})", r.class.word())
        }
        None => format!("{msg} ({})", r.class.word()),
    }
}

/// A route that no loaded protocol covers, located in the protocol text that demands it
/// (`mav::R001`, a warning).
#[derive(Debug)]
pub struct RouteWarning {
    message: String,
    src: NamedSource<String>,
    span: super::error::Span,
    help: String,
}

impl RouteWarning {
    /// The warning for `gap`, located in `sources[gap.origin.file]` (`(file name, text)`).
    pub fn new(dialect: &Dialect, gap: &RouteGap, sources: &[(String, String)]) -> RouteWarning {
        let (name, text) = sources.get(gap.origin.file).cloned().unwrap_or_default();
        let route = describe_route(dialect, &gap.route);
        let (message, help) = match gap.subject.strip_prefix("effect ") {
            Some(effect) => (
                format!("no loaded protocol guards effect {effect} on route {route}"),
                format!("add `{}` to a `guard {effect} by …`", gap.route.class.word()),
            ),
            None => (
                format!(
                    "{} is checked here, but no loaded protocol guards it on route {route}",
                    gap.subject
                ),
                "guard the command on every carrier, or declare the action as an `effect` and \
                 `guard` it by command, mission (and rc, for outputs)"
                    .to_string(),
            ),
        };
        RouteWarning { message, src: NamedSource::new(name, text), span: gap.origin.span, help }
    }
}

impl fmt::Display for RouteWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for RouteWarning {}

impl Diagnostic for RouteWarning {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new("mav::R001"))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Warning)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(&self.help))
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        Some(&self.src)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = LabeledSpan::new(Some("here".into()), self.span.start, self.span.len);
        Some(Box::new(std::iter::once(span)))
    }
}
