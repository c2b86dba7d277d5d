//! Turning a failed step into a [`Violation`]: which branch, which conjunct, which values.

use super::Monitor;
use super::eval::{Env, Val, eval, read_loc};
use super::identity::Forgery;
use super::report::{Reply, Violation, ViolationKind};
use super::session::{Arrival, Session, key_values, session_ids, vehicle_sys};
use super::step::StepResult;
use crate::codec::MessageView;
use crate::protocol::ir::{Conjunct, FieldLoc, Protocol, Refusal, ReplyIR};

impl Monitor {
    pub(super) fn violation_for(
        &self,
        s: &Session,
        role: usize,
        msg: &MessageView,
        r: StepResult,
        time_us: u64,
        is_start: bool,
    ) -> Violation {
        let p = &self.set.protocols[s.proto];
        let st = &p.states[s.state];
        let (ti, kind, conj) = match r {
            StepResult::Refused { transition, conjunct } => {
                let t = &st.transitions[transition];
                let kind = match t.refusal {
                    Refusal::Violation => ViolationKind::Refinement,
                    Refusal::Unverifiable => ViolationKind::Unverifiable,
                };
                (transition, kind, t.where_.as_ref().and_then(|w| w.conjuncts.get(conjunct)))
            }
            StepResult::Invariant { transition, rec, conjunct } => (
                transition,
                ViolationKind::Invariant,
                p.recs[rec].invariant.as_ref().and_then(|w| w.conjuncts.get(conjunct)),
            ),
            _ => (0, ViolationKind::Refinement, None),
        };
        let t = &st.transitions[ti];
        let lf = t.msgs.iter().find(|l| l.msg == msg.index);
        let fields: &[FieldLoc] = lf.map(|l| &l.fields[..]).unwrap_or(&[]);
        // Values as the step saw them: session variables plus this step's bindings, or, for a
        // broken invariant, the updated values the step left in the scratch buffer.
        let mut vars = s.vars.clone();
        if kind == ViolationKind::Invariant && self.scratch.len() == vars.len() {
            vars.copy_from_slice(&self.scratch);
        } else {
            for &(slot, f) in &t.binds {
                if let Some(loc) = fields.get(f) {
                    vars[slot] = read_loc(msg.payload, loc);
                }
            }
        }
        let env = Env {
            payload: msg.payload,
            fields,
            vars: &vars,
            consts: &self.consts,
            keys: &s.keys,
            vehicle: self.tracker.addressed(vehicle_sys(p, &s.ids)),
            param_names: &self.set.params.names,
        };
        let values = conj.map(|c| self.show_values(c, &env)).unwrap_or_default();
        let reason = match kind {
            ViolationKind::Invariant => {
                let rec = match r {
                    StepResult::Invariant { rec, .. } => p.recs[rec].name.clone(),
                    _ => String::new(),
                };
                format!("invariant of `rec {rec}` broken after branch `{}`", t.label)
            }
            ViolationKind::Unverifiable => {
                format!(
                    "branch `{}` cannot be verified: the vehicle has not reported what it needs",
                    t.label
                )
            }
            _ if is_start => format!("refinement of the opening step `{}` failed", t.label),
            _ => format!("refinement of branch `{}` failed", t.label),
        };
        Violation {
            kind,
            protocol: p.name.clone(),
            session: self.describe_session(p, s, is_start),
            message: describe_message(msg, s.ids[role], &self.targets_of(msg)),
            step: format!("{}: {}", t.label, t.text),
            expected: st.transitions.iter().map(|t| format!("{}: {}", t.label, t.text)).collect(),
            predicate: conj.map(|c| c.text.clone()),
            values,
            reason,
            time_us,
            reply: None,
            more_replies: Vec::new(),
            others: Vec::new(),
        }
        .with_replies(self.replies_for(p, s, role, &env))
    }

    pub(super) fn orphan_violation(&self, p: usize, strict: usize, arrival: &Arrival) -> Violation {
        let Arrival { msg, from: (sysid, compid), target, time_us, .. } = *arrival;
        let proto = &self.set.protocols[p];
        let rule = &proto.strict[strict];
        let ids = session_ids(rule.from, (sysid, compid), target);
        let keys = key_values(proto, msg);
        let s = Session {
            proto: p,
            state: 0,
            ids,
            keys,
            vars: vec![Val::Unknown; proto.var_names.len()],
            last_us: 0,
            serial: 0,
        };
        let env = Env {
            payload: msg.payload,
            fields: &[],
            vars: &s.vars,
            consts: &self.consts,
            keys: &s.keys,
            vehicle: None,
            param_names: &self.set.params.names,
        };
        let key_text: Vec<String> = proto
            .keys
            .iter()
            .zip(&s.keys)
            .map(|(k, v)| format!("{} = {}", k.name, self.render_key(k, v)))
            .collect();
        let (kind, what) = if rule.answer {
            (ViolationKind::Unverifiable, "answers no session seen: its opener was not observed")
        } else {
            (ViolationKind::NoSession, "nothing announced it")
        };
        Violation {
            kind,
            protocol: proto.name.clone(),
            session: "no open session".into(),
            message: describe_message(msg, (sysid, compid), &self.targets_of(msg)),
            step: format!("strict {}", rule.text),
            expected: proto.states[0]
                .transitions
                .iter()
                .map(|t| format!("{}: {}", t.label, t.text))
                .collect(),
            predicate: None,
            values: Vec::new(),
            reason: if key_text.is_empty() {
                format!("{} outside of any {} session ({what})", msg.name(), proto.name)
            } else {
                format!(
                    "{} for {} outside of any {} session ({what})",
                    msg.name(),
                    key_text.join(", "),
                    proto.name
                )
            },
            time_us,
            reply: None,
            more_replies: Vec::new(),
            others: Vec::new(),
        }
        .with_replies(self.replies_for(proto, &s, rule.from, &env))
    }

    /// The report of a frame from the GCS side that claims a vehicle's identity.
    pub(super) fn forgery(
        &self,
        msg: &MessageView,
        sysid: u8,
        compid: u8,
        why: Forgery,
        time_us: u64,
    ) -> Violation {
        let (predicate, reason) = match why {
            Forgery::VehicleIds => (
                "frames from the GCS side never carry a vehicle's system id",
                format!(
                    "system {sysid} is a vehicle (its autopilot heartbeats arrive on the vehicle \
                     side): a frame with its ids from the GCS side is forged"
                ),
            ),
            Forgery::AutopilotHeartbeat => (
                "autopilot heartbeats come from the vehicle side",
                "a HEARTBEAT describing an autopilot arrived from the GCS side".to_string(),
            ),
        };
        Violation {
            kind: ViolationKind::Forgery,
            protocol: "trust_boundary".into(),
            session: "no session".into(),
            message: describe_message(msg, (sysid, compid), &self.targets_of(msg)),
            step: String::new(),
            expected: Vec::new(),
            predicate: Some(predicate.into()),
            values: Vec::new(),
            reason,
            time_us,
            reply: None,
            more_replies: Vec::new(),
            others: Vec::new(),
        }
    }

    fn targets_of(&self, msg: &MessageView) -> Option<(u8, u8)> {
        self.targets[usize::from(msg.index)].as_ref().map(|(s, c)| {
            let n = |v: Val| if let Val::Num(x) = v { x as u8 } else { 0 };
            (n(read_loc(msg.payload, s)), n(read_loc(msg.payload, c)))
        })
    }

    fn render_key(&self, k: &crate::protocol::ir::KeyIR, v: &Val) -> String {
        let en = k.locs.first().and_then(|(_, l)| l.enum_name.as_deref());
        v.render(en, &self.dialect)
    }

    fn show_values(&self, c: &Conjunct, env: &Env) -> Vec<(String, String)> {
        c.shows
            .iter()
            .filter(|(_, e, _)| !matches!(e, crate::protocol::ir::Expr::Num(_)))
            .map(|(n, e, en)| (n.clone(), eval(e, env).render(en.as_deref(), &self.dialect)))
            .collect()
    }

    fn describe_session(&self, p: &Protocol, s: &Session, is_start: bool) -> String {
        let ids: Vec<String> =
            p.roles.iter().zip(&s.ids).map(|((n, _), (sy, co))| format!("{n} {sy}/{co}")).collect();
        let keys: Vec<String> = p
            .keys
            .iter()
            .zip(&s.keys)
            .map(|(k, v)| format!(", {} = {}", k.name, self.render_key(k, v)))
            .collect();
        let what = if is_start { "opening" } else { "session" };
        format!("{what} {}{}", ids.join(" ↔ "), keys.concat())
    }

    /// The protocol's violation replies for session `s` when role `violator` sent the
    /// offending message. A reply one of whose fields has no known value (e.g. the last value
    /// of a parameter never reported) is not sent: the guard makes no message it cannot fill
    /// truthfully.
    fn replies_for(&self, p: &Protocol, s: &Session, violator: usize, env: &Env) -> Vec<Reply> {
        let env = Env { vars: &s.vars, keys: &s.keys, fields: &[], ..*env };
        p.replies
            .iter()
            .filter(|r| r.by.is_none_or(|b| b == violator))
            .filter_map(|r| self.reply(p, r, s, &env))
            .collect()
    }

    fn reply(&self, p: &Protocol, r: &ReplyIR, s: &Session, env: &Env) -> Option<Reply> {
        let def = self.dialect.message(r.msg);
        let (to_sys, to_comp) = s.ids[r.to];
        let (from_sys, from_comp) = s.ids[1 - r.to];
        let mut fields = Vec::new();
        let mut text_fields = Vec::new();
        for (name, e) in &r.fields {
            match eval(e, env) {
                Val::Num(x) => fields.push((name.clone(), x)),
                Val::Bool(b) => fields.push((name.clone(), f64::from(u8::from(b)))),
                Val::Text(b, n) => text_fields.push((
                    name.clone(),
                    String::from_utf8_lossy(&b[..usize::from(n)]).into_owned(),
                )),
                Val::Unknown => return None,
            }
        }
        for (f, v) in [("target_system", to_sys), ("target_component", to_comp)] {
            if def.field(f).is_some() && !fields.iter().any(|(n, _)| n == f) {
                fields.push((f.to_string(), f64::from(v)));
            }
        }
        Some(Reply::build(
            def,
            p.roles[r.to].1,
            (from_sys, from_comp),
            (to_sys, to_comp),
            fields,
            text_fields,
        ))
    }
}

impl Violation {
    fn with_replies(mut self, mut replies: Vec<Reply>) -> Violation {
        if !replies.is_empty() {
            self.reply = Some(replies.remove(0));
        }
        self.more_replies = replies;
        self
    }
}

fn describe_message(msg: &MessageView, from: (u8, u8), target: &Option<(u8, u8)>) -> String {
    match target {
        Some((s, c)) => format!("{} from {}/{} to {s}/{c}", msg.name(), from.0, from.1),
        None => format!("{} from {}/{}", msg.name(), from.0, from.1),
    }
}
