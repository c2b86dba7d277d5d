//! Effects (part of the compiler, see `check`): an `effect` declaration is compiled, route by
//! route, into the selectors of the messages that make the vehicle perform it; a `guard` in a
//! protocol turns those routes into the protocol's steps, with the precondition (or the refusal)
//! as their refinement. The routes are those of [`routes`](super::routes): every carrier of each
//! command of the effect, every carrier of each command that drives an output of the effect's
//! kinds, every RC override message.
//!
//! Three outcomes per message, so that nothing that may perform the effect slips through:
//! * the message performs the effect, or may (arguments whose conversion is undefined, an output
//!   value that cannot be read): the guard's refinement decides (fail closed);
//! * it drives an output whose configuration the vehicle has not reported: *unverifiable* — the
//!   protocol's `unverifiable` policy decides;
//! * anything else is no concern of the guard.

use super::ast::{self, BinOp, OutputKind};
use super::compile::{CResult, Compiler, Scope, StepCx};
use super::error::{ErrorKind, Span};
use super::ir::*;
use super::routes::{OUTPUT_COMMANDS, mav_cmd};
use crate::dialect::MsgIndex;
use crate::side::Side;

/// `e` is true or unknown (`!(known(e) && !e)`): a selector that must not let an undefined value
/// pass.
fn maybe(e: Expr) -> Expr {
    let known = Expr::Call(Builtin::Known, Box::new(e.clone()));
    Expr::Not(Box::new(Expr::Bin(BinOp::And, Box::new(known), Box::new(Expr::Not(Box::new(e))))))
}

/// `e` is unknown.
fn unknown(e: Expr) -> Expr {
    Expr::Not(Box::new(Expr::Call(Builtin::Known, Box::new(e))))
}

fn and(a: Expr, b: Expr) -> Expr {
    Expr::Bin(BinOp::And, Box::new(a), Box::new(b))
}

fn or(a: Option<Expr>, b: Expr) -> Expr {
    match a {
        Some(a) => Expr::Bin(BinOp::Or, Box::new(a), Box::new(b)),
        None => b,
    }
}

fn conjunct(expr: Expr, text: String) -> Conjunct {
    Conjunct { expr, text, shows: vec![] }
}

/// The MAV_CMD values a selector pins `command` to (`command == K`, or several joined by `||`).
fn command_pins(e: &Expr, names: &[String], consts: &[ConstIR]) -> Option<Vec<u32>> {
    match e {
        Expr::Bin(BinOp::Eq, a, b) => {
            let is_cmd = |x: &Expr| matches!(x, Expr::Field(s) if names.get(*s).is_some_and(|n| n == "command"));
            let value = |x: &Expr| match x {
                Expr::Num(v) => Some(*v),
                Expr::Const(i) => consts.get(*i).map(|c| c.value),
                _ => None,
            };
            let v = if is_cmd(a) {
                value(b)
            } else if is_cmd(b) {
                value(a)
            } else {
                None
            }?;
            let whole = v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX);
            whole.then(|| vec![v as u32])
        }
        Expr::Bin(BinOp::Or, a, b) => {
            let mut pins = command_pins(a, names, consts)?;
            pins.extend(command_pins(b, names, consts)?);
            Some(pins)
        }
        _ => None,
    }
}

impl Compiler<'_> {
    /// `effect NAME { … }`: every route to it, compiled.
    pub(super) fn effect_decl(&mut self, d: &ast::EffectDecl) -> CResult<()> {
        if self.set.effects.iter().any(|e| e.name == d.name.name) {
            return self.err(
                ErrorKind::Duplicate,
                d.name.span,
                format!("effect `{}` is defined twice", d.name.name),
            );
        }
        let mut routes = vec![];
        for c in &d.commands {
            self.effect_command(d, c, &mut routes)?;
        }
        for o in &d.outputs {
            match o.kind {
                OutputKind::Servo | OutputKind::Relay => self.output_commands(d, o, &mut routes)?,
                OutputKind::Rc => self.rc_override(d, o, &mut routes)?,
            }
        }
        if routes.is_empty() {
            return self.err(
                ErrorKind::Structure,
                d.name.span,
                format!("effect `{}` has no route: declare a `command` or an output", d.name.name),
            );
        }
        let origin = self.origin(d.name.span);
        self.set.effects.push(EffectIR { name: d.name.name.clone(), routes, origin });
        Ok(())
    }

    fn mav_cmd_of(&self, id: &ast::Ident) -> CResult<u32> {
        match mav_cmd(self.dialect, &id.name) {
            Some(v) => Ok(v),
            None => self.err(
                ErrorKind::UnknownName,
                id.span,
                format!(
                    "`{}` is not an entry of MAV_CMD in dialect {}",
                    id.name, self.dialect.name
                ),
            ),
        }
    }

    /// A fresh field context for one carrier message.
    fn carrier_cx(&self, msg: MsgIndex) -> StepCx {
        let label_text = self.dialect.message(msg).name.clone();
        StepCx { msgs: vec![msg], names: vec![], locs: vec![vec![]], label_text }
    }

    /// The conjunct `command == NAME` in the carrier of `st`.
    fn command_is(&self, st: &mut StepCx, cmd: u32, name: &str, span: Span) -> CResult<Conjunct> {
        let (slot, _) = self.field_slot(st, "command", span)?;
        let e =
            Expr::Bin(BinOp::Eq, Box::new(Expr::Field(slot)), Box::new(Expr::Num(f64::from(cmd))));
        Ok(conjunct(e, format!("command == {name}")))
    }

    /// A condition of an effect clause, compiled in a carrier's context, with its report text.
    fn clause_condition(&mut self, e: &ast::Expr, st: &mut StepCx) -> CResult<Conjunct> {
        let mut shows = vec![];
        let x = self.condition(e, &mut Scope::default(), Some(st), &mut shows)?;
        Ok(Conjunct { expr: x, text: self.text_of(e.span), shows })
    }

    fn push_demand(&mut self, d: &ast::EffectDecl, routes: Vec<Route>, span: Span) {
        let origin = self.origin(span);
        self.set.demands.push(Demand {
            subject: format!("effect {}", d.name.name),
            routes,
            origin,
        });
    }

    /// `command MAV_CMD_X [when …]`: the command on every command and mission carrier.
    fn effect_command(
        &mut self,
        d: &ast::EffectDecl,
        c: &ast::EffectCommand,
        routes: &mut Vec<EffectRoute>,
    ) -> CResult<()> {
        let cmd = self.mav_cmd_of(&c.command)?;
        let carriers = self.carriers.command_routes(cmd);
        for route in &carriers {
            let mut st = self.carrier_cx(route.msg);
            let mut conjuncts = vec![self.command_is(&mut st, cmd, &c.command.name, c.span)?];
            if let Some(w) = &c.when {
                let mut k = self.clause_condition(w, &mut st)?;
                k.expr = maybe(k.expr);
                conjuncts.push(k);
            }
            routes.push(EffectRoute {
                route: *route,
                label: c.command.name.clone(),
                field_names: st.names,
                fields: st.locs.swap_remove(0),
                effect: Pred { conjuncts },
                unknown: None,
                origin: self.origin(c.span),
            });
        }
        self.push_demand(d, carriers, c.span);
        Ok(())
    }

    /// `servo N when …` / `relay N when …`: every command that drives an output of that kind, on
    /// every carrier, with N its `param1` (as the autopilot reads it, `uint8`) and `value` its
    /// `param2`.
    fn output_commands(
        &mut self,
        d: &ast::EffectDecl,
        o: &ast::EffectOutput,
        routes: &mut Vec<EffectRoute>,
    ) -> CResult<()> {
        let sp = o.var.span;
        let number = ast::Expr::call_at("uint8", ast::Expr::name_at("param1", sp), sp);
        let value = ast::Expr::name_at("param2", sp);
        let when = o.when.substitute(&[(&o.var.name, &number)]);
        let driven =
            o.driven.as_ref().map(|e| e.substitute(&[(&o.var.name, &number), ("value", &value)]));
        for (cmd_name, _) in OUTPUT_COMMANDS.iter().filter(|(_, k)| *k == o.kind) {
            let Some(cmd) = mav_cmd(self.dialect, cmd_name) else { continue };
            let carriers = self.carriers.command_routes(cmd);
            for route in &carriers {
                let mut st = self.carrier_cx(route.msg);
                let is_cmd = self.command_is(&mut st, cmd, cmd_name, o.span)?;
                let sel = self.clause_condition(&when, &mut st)?;
                let drv = match &driven {
                    Some(e) => Some(self.clause_condition(e, &mut st)?),
                    None => None,
                };
                routes.push(self.output_route(*route, cmd_name, st, is_cmd, sel, drv, o.span));
            }
            self.push_demand(d, carriers, o.span);
        }
        Ok(())
    }

    /// The route of an output command: the effect when the output is the effect's (`sel`) and
    /// the value may drive it (`drv`); unverifiable when `sel` is unknown.
    #[expect(
        clippy::too_many_arguments,
        reason = "the parts of one route, each built by the caller"
    )]
    fn output_route(
        &self,
        route: Route,
        label: &str,
        mut st: StepCx,
        is_cmd: Conjunct,
        sel: Conjunct,
        drv: Option<Conjunct>,
        span: Span,
    ) -> EffectRoute {
        let drv = drv.map(|mut k| {
            k.expr = maybe(k.expr);
            k
        });
        let unknown_sel = conjunct(unknown(sel.expr.clone()), format!("{} is not known", sel.text));
        let check = Conjunct {
            expr: Expr::Call(Builtin::Known, Box::new(sel.expr.clone())),
            text: format!("{} (the vehicle has not reported the parameters it needs)", sel.text),
            shows: sel.shows.clone(),
        };
        let mut effect = vec![is_cmd.clone(), sel];
        let mut unknown_when = vec![is_cmd, unknown_sel];
        effect.extend(drv.clone());
        unknown_when.extend(drv);
        EffectRoute {
            route,
            label: label.to_string(),
            field_names: st.names,
            fields: st.locs.swap_remove(0),
            effect: Pred { conjuncts: effect },
            unknown: Some((Pred { conjuncts: unknown_when }, Pred { conjuncts: vec![check] })),
            origin: self.origin(span),
        }
    }

    /// `rc N in A..B when … [driven when …]`: every RC override message, each channel N of the
    /// range read from its `chanN_raw` (`value`).
    fn rc_override(
        &mut self,
        d: &ast::EffectDecl,
        o: &ast::EffectOutput,
        routes: &mut Vec<EffectRoute>,
    ) -> CResult<()> {
        let (lo, hi) = o.range.unwrap_or((1, 0));
        if lo > hi {
            return self.err(ErrorKind::Structure, o.span, "an empty channel range");
        }
        let carriers = self.carriers.rc_routes();
        for route in &carriers {
            let mut st = self.carrier_cx(route.msg);
            let (mut any, mut any_unknown) = (None, None);
            for n in lo..=hi {
                let field = format!("chan{n}_raw");
                if self.dialect.message(route.msg).field(&field).is_none() {
                    return self.err(
                        ErrorKind::UnknownName,
                        o.span,
                        format!("{} has no field `{field}`", st.label_text),
                    );
                }
                let number = ast::Expr::num_at(f64::from(n), o.var.span);
                let value = ast::Expr::name_at(&field, o.var.span);
                let map = [(o.var.name.as_str(), &number), ("value", &value)];
                let sel = self.clause_condition(&o.when.substitute(&map), &mut st)?.expr;
                let drv = match &o.driven {
                    Some(e) => {
                        Some(maybe(self.clause_condition(&e.substitute(&map), &mut st)?.expr))
                    }
                    None => None,
                };
                let (hit, unknown_hit) = match drv {
                    Some(drv) => (and(sel.clone(), drv.clone()), and(unknown(sel), drv)),
                    None => (sel.clone(), unknown(sel)),
                };
                any = Some(or(any, hit));
                any_unknown = Some(or(any_unknown, unknown_hit));
            }
            let driven = o.driven.as_ref().map(|e| format!(" driven ({})", self.text_of(e.span)));
            let what = format!(
                "{} for a channel {} in {lo}..{hi}{}",
                self.text_of(o.when.span),
                o.var.name,
                driven.unwrap_or_default()
            );
            let check = conjunct(Expr::Bool(false), format!("{what} is not known"));
            routes.push(EffectRoute {
                route: *route,
                label: st.label_text.clone(),
                field_names: st.names,
                fields: st.locs.swap_remove(0),
                effect: Pred {
                    conjuncts: vec![conjunct(any.unwrap_or(Expr::Bool(false)), what.clone())],
                },
                unknown: Some((
                    Pred {
                        conjuncts: vec![conjunct(any_unknown.unwrap_or(Expr::Bool(false)), what)],
                    },
                    Pred { conjuncts: vec![check] },
                )),
                origin: self.origin(o.span),
            });
        }
        self.push_demand(d, carriers, o.span);
        Ok(())
    }

    /// `guard EFFECT by ROUTE, … (where P | refuse)`: one step per route of the effect in those
    /// classes (two for outputs: known and unreported configuration), all in the start state.
    pub(super) fn guard(&mut self, g: &ast::GuardDecl) -> CResult<()> {
        let Some(effect) = self.set.effects.iter().find(|e| e.name == g.effect.name).cloned()
        else {
            let known: Vec<&str> = self.set.effects.iter().map(|e| e.name.as_str()).collect();
            return self
                .err(
                    ErrorKind::UnknownName,
                    g.effect.span,
                    format!("no effect `{}` is declared", g.effect.name),
                )
                .map_err(|e| e.with_help(format!("declared effects: {}", known.join(", "))));
        };
        let mut classes = vec![];
        for r in &g.routes {
            classes.push(match r.name.as_str() {
                "command" => RouteClass::Command,
                "mission" => RouteClass::Mission,
                "rc" => RouteClass::Rc,
                other => {
                    return self.err(
                        ErrorKind::UnknownName,
                        r.span,
                        format!(
                            "unknown route `{other}`: routes are `command`, `mission` and `rc`"
                        ),
                    );
                }
            });
        }
        let gcs = self.proto.roles.iter().position(|(_, s)| *s == Side::Gcs).unwrap_or(0);
        let uav = 1 - gcs;
        let mut guarded = 0;
        for r in effect.routes.iter().filter(|r| classes.contains(&r.route.class)) {
            guarded += 1;
            self.guard_route(g, &effect.name, r, gcs, uav)?;
        }
        if guarded == 0 {
            return self.err(
                ErrorKind::Structure,
                g.span,
                format!(
                    "effect `{}` has no route by {}",
                    effect.name,
                    g.routes.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join(", ")
                ),
            );
        }
        Ok(())
    }

    fn guard_route(
        &mut self,
        g: &ast::GuardDecl,
        effect: &str,
        r: &EffectRoute,
        gcs: usize,
        uav: usize,
    ) -> CResult<()> {
        let msg = r.route.msg;
        let mut st = StepCx {
            msgs: vec![msg],
            names: r.field_names.clone(),
            locs: vec![r.fields.clone()],
            label_text: self.dialect.message(msg).name.clone(),
        };
        let where_ = match &g.where_ {
            Some(e) => self.pred(e, &mut Scope::default(), Some(&mut st))?,
            None => Pred {
                conjuncts: vec![conjunct(
                    Expr::Bool(false),
                    format!(
                        "refused: effect {effect} cannot be checked when a {} brings it, only when it runs",
                        st.label_text
                    ),
                )],
            },
        };
        let (from, to) = (&self.proto.roles[gcs].0, &self.proto.roles[uav].0);
        let text = format!("{from} -> {to} : {} (effect {effect})", st.label_text);
        let step = |label: String,
                    fields: Vec<FieldLoc>,
                    names: Vec<String>,
                    when: Pred,
                    where_: Pred,
                    refusal| Transition {
            label,
            from: gcs,
            to: uav,
            msgs: vec![LabelFields { msg, fields }],
            field_names: names,
            binds: vec![],
            when: Some(when),
            where_: Some(where_),
            cont: Cont::End,
            text: text.clone(),
            refusal,
        };
        let mut new = vec![step(
            r.label.clone(),
            st.locs.swap_remove(0),
            st.names,
            r.effect.clone(),
            where_,
            Refusal::Violation,
        )];
        if let Some((sel, check)) = &r.unknown {
            let label = format!("{} (unreported configuration)", r.label);
            new.push(step(
                label,
                r.fields.clone(),
                r.field_names.clone(),
                sel.clone(),
                check.clone(),
                Refusal::Unverifiable,
            ));
        }
        self.proto.states[0].transitions.extend(new);
        self.proto.covers.push(r.route);
        Ok(())
    }

    /// A step from the ground that checks (`where`) a command it selects (`when command == K`)
    /// guards that command on its carrier, and demands the command be guarded on every carrier.
    pub(super) fn note_checked_commands(
        &mut self,
        from: usize,
        msgs: &[MsgIndex],
        when: &Pred,
        names: &[String],
        span: Span,
    ) {
        if self.proto.roles.get(from).map(|r| r.1) != Some(Side::Gcs) {
            return;
        }
        let consts = &self.set.consts;
        let Some(pins) = when.conjuncts.iter().find_map(|c| command_pins(&c.expr, names, consts))
        else {
            return;
        };
        for &msg in msgs {
            let Some(class) = self.carriers.class_of(msg).filter(|c| *c != RouteClass::Rc) else {
                continue;
            };
            for &k in &pins {
                self.proto.covers.push(Route { class, msg, command: Some(k) });
                let subject = match self.dialect.enum_value_name("MAV_CMD", u64::from(k)) {
                    Some(n) => n.to_string(),
                    None => format!("MAV_CMD {k}"),
                };
                let routes = self.carriers.command_routes(k);
                let origin = self.origin(span);
                self.set.demands.push(Demand { subject, routes, origin });
            }
        }
    }
}
