//! Control flow of a protocol (part of the checker, see `check`): message steps, choices,
//! recursion and `continue`/`end` become states, transitions and continuations of the IR, with
//! field slots resolved per alternative label.

use super::ast::{self, Stmt};
use super::compile::{CResult, Compiler, Scope, StepCx, Ty, loc_of, ty_of_loc};
use super::error::ErrorKind;
use super::error::Span;
use super::ir::*;

impl Compiler<'_> {
    fn new_var(&mut self, name: &str) -> Slot {
        self.proto.var_names.push(name.to_string());
        self.proto.var_names.len() - 1
    }

    /// Continuation of the statements `stmts`, compiled in the context of the step just taken.
    fn seq(
        &mut self,
        stmts: &[Stmt],
        scope: &mut Scope,
        step: Option<&mut StepCx>,
    ) -> CResult<Cont> {
        let Some(first) = stmts.first() else {
            return Ok(Cont::End);
        };
        let trailing = |this: &Self, what: &str| -> CResult<()> {
            if let Some(next) = stmts.get(1) {
                return this.err(
                    ErrorKind::Structure,
                    stmt_span(next),
                    format!("unreachable: nothing can follow {what}"),
                );
            }
            Ok(())
        };
        match first {
            Stmt::End(_) => {
                trailing(self, "`end`")?;
                Ok(Cont::End)
            }
            Stmt::Continue { name, assigns, .. } => {
                trailing(self, "`continue`")?;
                self.continue_to(name, assigns, scope, step)
            }
            Stmt::Rec { name, vars, invariant, body } => {
                trailing(self, "a `rec` block (end its body with `end` or `continue`)")?;
                self.enter_rec(name, vars, invariant.as_ref(), body, scope, step)
            }
            Stmt::Step { .. } | Stmt::Choice { .. } => {
                Ok(Cont::Goto(self.state_for(stmts, scope)?))
            }
        }
    }

    /// `continue NAME(v = e, …)`: the new values, checked against the variables of its `rec`.
    fn continue_to(
        &mut self,
        name: &ast::Ident,
        assigns: &[(ast::Ident, ast::Expr)],
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
    ) -> CResult<Cont> {
        let Some((_, rec, vars)) =
            scope.recs.iter().rev().find(|(n, _, _)| *n == name.name).cloned()
        else {
            return self.err(
                ErrorKind::Structure,
                name.span,
                format!("`continue {}` outside of `rec {}`", name.name, name.name),
            );
        };
        if assigns.len() > MAX_CONTINUE_ASSIGNS {
            return self.err(
                ErrorKind::Limit,
                name.span,
                format!(
                    "at most {MAX_CONTINUE_ASSIGNS} variables can be updated by one `continue`"
                ),
            );
        }
        let mut out = vec![];
        for (v, e) in assigns {
            let Some((_, slot)) = vars.iter().find(|(n, _)| *n == v.name) else {
                return self.err(
                    ErrorKind::UnknownName,
                    v.span,
                    format!("`{}` is not a variable of `rec {}`", v.name, name.name),
                );
            };
            let want =
                scope.vars.iter().rev().find(|(_, s, _)| s == slot).map(|(_, _, t)| t.clone());
            let mut shows = vec![];
            let (x, ty) = self.expr(e, scope, step.as_deref_mut(), &mut shows)?;
            if let Some(want) = want {
                self.expect_compatible(&want, &ty, e.span)?;
            }
            out.push((*slot, x));
        }
        Ok(Cont::Continue { rec, assigns: out })
    }

    /// `rec NAME(v: T = e, …) where INV { body }`: its variables, invariant and entry state.
    fn enter_rec(
        &mut self,
        name: &ast::Ident,
        vars: &[ast::VarDecl],
        invariant: Option<&ast::Expr>,
        body: &[Stmt],
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
    ) -> CResult<Cont> {
        let rec = self.proto.recs.len();
        self.proto.recs.push(Rec { name: name.name.clone(), invariant: None, entry: 0 });
        let mut assigns = vec![];
        let mut rec_vars = vec![];
        let mark = scope.vars.len();
        for v in vars {
            let mut shows = vec![];
            let (x, ty) = self.expr(&v.init, scope, step.as_deref_mut(), &mut shows)?;
            if let Some(t) = v.ty {
                let want = match t {
                    ast::TypeName::Int | ast::TypeName::Float => Ty::num(),
                    ast::TypeName::Bool => Ty::Bool,
                    ast::TypeName::Str => Ty::Str,
                };
                self.expect_compatible(&want, &ty, v.init.span)?;
            }
            let slot = self.new_var(&v.name.name);
            assigns.push((slot, x));
            rec_vars.push((v.name.name.clone(), slot, ty));
        }
        for (n, s, t) in &rec_vars {
            scope.vars.push((n.clone(), *s, t.clone()));
        }
        let slots = rec_vars.iter().map(|(n, s, _)| (n.clone(), *s)).collect();
        scope.recs.push((name.name.clone(), rec, slots));
        if let Some(inv) = invariant {
            let pred = self.pred(inv, scope, None)?;
            self.proto.recs[rec].invariant = Some(pred);
        }
        if !matches!(body.first(), Some(Stmt::Step { .. }) | Some(Stmt::Choice { .. })) {
            return self.err(
                ErrorKind::Structure,
                name.span,
                "the body of a `rec` must start with a message step or a choice",
            );
        }
        let then = self.state_for(body, scope)?;
        self.proto.recs[rec].entry = then;
        scope.recs.pop();
        scope.vars.truncate(mark);
        Ok(Cont::Enter { rec, assigns, then })
    }

    /// A state whose transitions are the step or choice at the head of `stmts`.
    pub(super) fn state_for(&mut self, stmts: &[Stmt], scope: &mut Scope) -> CResult<StateId> {
        let id = self.proto.states.len();
        self.proto.states.push(State::default());
        let mut transitions = vec![];
        let mut complete = None;
        match &stmts[0] {
            Stmt::Step { head, block } => {
                let rest = match block {
                    Some(b) => {
                        if let Some(next) = stmts.get(1) {
                            return self.err(
                                ErrorKind::Structure,
                                stmt_span(next),
                                "unreachable: a step with a block is followed by its block only",
                            );
                        }
                        &b[..]
                    }
                    None => &stmts[1..],
                };
                let label = head.labels[0].name.to_ascii_lowercase();
                transitions.push(self.transition(label, head, rest, scope)?);
            }
            Stmt::Choice { branches, complete_when, .. } => {
                if let Some(next) = stmts.get(1) {
                    return self.err(
                        ErrorKind::Structure,
                        stmt_span(next),
                        "unreachable: put what follows a choice into its branches",
                    );
                }
                for b in branches {
                    if transitions.iter().any(|t: &Transition| t.label == b.label.name) {
                        return self.err(
                            ErrorKind::Duplicate,
                            b.label.span,
                            format!("branch label `{}` used twice", b.label.name),
                        );
                    }
                    transitions.push(self.transition(
                        b.label.name.clone(),
                        &b.head,
                        &b.body,
                        scope,
                    )?);
                }
                if let Some(c) = complete_when {
                    complete = Some(self.pred(c, scope, None)?);
                }
            }
            other => {
                return self.err(
                    ErrorKind::Structure,
                    stmt_span(other),
                    "expected a message step or a choice here",
                );
            }
        }
        let st = &mut self.proto.states[id];
        st.transitions = transitions;
        st.complete_when = complete;
        Ok(id)
    }

    fn transition(
        &mut self,
        label: String,
        head: &ast::StepHead,
        rest: &[Stmt],
        scope: &mut Scope,
    ) -> CResult<Transition> {
        let from = self.role(&head.from)?;
        let to = self.role(&head.to)?;
        if from == to {
            return self.err(ErrorKind::Structure, head.to.span, "sender and receiver must differ");
        }
        let msgs = self.messages(&head.labels)?;
        let label_text =
            head.labels.iter().map(|l| l.name.as_str()).collect::<Vec<_>>().join(" | ");
        let mut step = StepCx {
            msgs: msgs.clone(),
            names: vec![],
            locs: vec![vec![]; msgs.len()],
            label_text: label_text.clone(),
        };
        let mark = scope.vars.len();
        let mut binds = vec![];
        for (v, f) in &head.binds {
            let (fslot, ty) = self.field_slot(&mut step, &f.name, f.span)?;
            let slot = self.new_var(&v.name);
            scope.vars.push((v.name.clone(), slot, ty));
            binds.push((slot, fslot));
        }
        let when = match &head.when {
            Some(e) => Some(self.pred(e, scope, Some(&mut step))?),
            None => None,
        };
        let where_ = match &head.where_ {
            Some(e) => Some(self.pred(e, scope, Some(&mut step))?),
            None => None,
        };
        if let (Some(w), Some(_)) = (&when, &where_) {
            self.note_checked_commands(from, &msgs, w, &step.names, head.span);
        }
        let cont = self.seq(rest, scope, Some(&mut step))?;
        scope.vars.truncate(mark);
        let msgs =
            msgs.iter().zip(step.locs).map(|(&msg, fields)| LabelFields { msg, fields }).collect();
        Ok(Transition {
            label,
            from,
            to,
            msgs,
            field_names: step.names,
            binds,
            when,
            where_,
            cont,
            text: format!("{} -> {} : {}", head.from.name, head.to.name, label_text),
            refusal: Refusal::Violation,
        })
    }

    /// Slot of field `name` in the current step; the field must exist in every alternative message.
    pub(super) fn field_slot(
        &self,
        step: &mut StepCx,
        name: &str,
        span: Span,
    ) -> CResult<(usize, Ty)> {
        if let Some(i) = step.names.iter().position(|n| n == name) {
            return Ok((i, ty_of_loc(&step.locs[0][i])));
        }
        let mut locs = vec![];
        for &m in &step.msgs {
            let def = self.dialect.message(m);
            match loc_of(def, name) {
                Some(l) => locs.push(l),
                None => {
                    return self.err(
                        ErrorKind::UnknownName,
                        span,
                        format!("message {} has no field `{name}`", def.name),
                    );
                }
            }
        }
        let ty = ty_of_loc(&locs[0]);
        if locs.iter().any(|l| ty_of_loc(l) != ty) {
            return self.err(
                ErrorKind::Type,
                span,
                format!("field `{name}` has different types in {}", step.label_text),
            );
        }
        step.names.push(name.to_string());
        for (i, l) in locs.into_iter().enumerate() {
            step.locs[i].push(l);
        }
        Ok((step.names.len() - 1, ty))
    }
}

pub(super) fn stmt_span(s: &Stmt) -> Span {
    match s {
        Stmt::Step { head, .. } => head.span,
        Stmt::Choice { span, .. } => *span,
        Stmt::Rec { name, .. } => name.span,
        Stmt::Continue { span, .. } => *span,
        Stmt::End(s) => *s,
    }
}
