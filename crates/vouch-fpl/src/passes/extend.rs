//! Pass 1, *extension*: FP → FPE. Numbers the stages of every block the way upstream does
//! (GENERATOR_FACTS.md section 6), flattens loop bodies into the block's stage list, adds the
//! loop-back stages, splits two-step navigation stages, and allocates the C labels.
//!
//! Numbering per source stage: `for` = 2 + body + 1, `while` = 1 + body + 1, `eight`/`oval`/
//! `survey_rectangle` = 2, others 1; the block's default (end) stage comes last.

use serde::Serialize;

use super::fp::*;

/// An extended plan. `S` is the stage-number type and `B` the block-reference type:
/// `usize` in FPE, checked `u8` newtypes in FPS.
#[derive(Debug, Clone, Serialize)]
pub struct Ext<S, B> {
    pub blocks: Vec<ExtBlock<S, B>>,
    pub exceptions: Vec<ExtException<B>>,
    pub forbidden: Vec<ExtForbidden<B>>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExtException<B> {
    pub cond: Cond,
    pub target: B,
    pub exec: Option<Code>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExtForbidden<B> {
    pub from: B,
    pub to: B,
    pub only_when: Option<Cond>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExtBlock<S, B> {
    pub no: B,
    pub name: String,
    pub pre_call: Option<Code>,
    pub post_call: Option<Code>,
    pub on_enter: Option<Code>,
    pub on_exit: Option<Code>,
    pub exceptions: Vec<ExtException<B>>,
    pub stages: Vec<ExtStage<S, B>>,
    /// The default stage (`NextBlock()`), numbered after every other stage.
    pub default_stage: S,
    pub span: crate::span::Span,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExtStage<S, B> {
    pub no: S,
    /// Nesting depth (0 = directly in the block); the emitter indents by it.
    pub depth: usize,
    pub kind: ExtKind<B>,
}

#[derive(Debug, Clone, Serialize)]
pub enum ExtKind<B> {
    /// `while` test; `label`/`end_label` are the C labels around the loop.
    WhileTest {
        cond: Cond,
        label: String,
        end_label: String,
    },
    /// Loop-back stage after a `while` body (`END_WHILE`): jumps to the test.
    EndWhile {
        label: String,
        end_label: String,
    },
    /// `for` init stage (declares and sets the counters, falls through to the test).
    ForInit {
        var: String,
        from: String,
        to: String,
    },
    ForTest {
        var: String,
        label: String,
        end_label: String,
    },
    EndFor {
        label: String,
        end_label: String,
    },
    Set {
        code: Code,
    },
    Call {
        fun: String,
        loop_: bool,
        brk: bool,
        until: Option<Cond>,
    },
    Deroute {
        target: B,
    },
    Return {
        reset: Reset,
    },
    /// First step of a two-step navigation stage (`NAV_INIT`).
    NavInit {
        lines: Vec<Code>,
    },
    /// A navigation stage (its `init` is always `None` here).
    Nav(Box<NavStage>),
}

pub type Fpe = Ext<usize, usize>;

/// Labels are numbered by one counter for the whole plan, starting at 1 (upstream's counter is
/// process-global, quirk 14; vouch behaves like a fresh upstream process per plan).
struct Labels(usize);

impl Labels {
    fn next(&mut self, prefix: &str) -> String {
        self.0 += 1;
        format!("{prefix}_{}", self.0)
    }
}

pub fn extend(fp: &Fp) -> Fpe {
    let mut labels = Labels(0);
    let blocks = fp
        .blocks
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let mut stages = Vec::new();
            flatten(&b.stages, 0, &mut stages, &mut labels);
            ExtBlock {
                no: i,
                name: b.name.clone(),
                pre_call: b.pre_call.clone(),
                post_call: b.post_call.clone(),
                on_enter: b.on_enter.clone(),
                on_exit: b.on_exit.clone(),
                exceptions: b.exceptions.iter().map(exception).collect(),
                default_stage: stages.len(),
                stages,
                span: b.span,
            }
        })
        .collect();
    Ext {
        blocks,
        exceptions: fp.exceptions.iter().map(exception).collect(),
        forbidden: fp
            .forbidden
            .iter()
            .map(|f| ExtForbidden { from: f.from, to: f.to, only_when: f.only_when.clone() })
            .collect(),
    }
}

fn exception(e: &FpException) -> ExtException<usize> {
    ExtException { cond: e.cond.clone(), target: e.target, exec: e.exec.clone() }
}

fn push(out: &mut Vec<ExtStage<usize, usize>>, depth: usize, kind: ExtKind<usize>) {
    let no = out.len();
    out.push(ExtStage { no, depth, kind });
}

fn flatten(
    stages: &[FpStage],
    depth: usize,
    out: &mut Vec<ExtStage<usize, usize>>,
    labels: &mut Labels,
) {
    for s in stages {
        match s {
            FpStage::While { cond, body, .. } => {
                // Both labels are allocated before the body, as upstream does.
                let label = labels.next("while");
                let end_label = labels.next("endwhile");
                push(
                    out,
                    depth,
                    ExtKind::WhileTest {
                        cond: cond.clone(),
                        label: label.clone(),
                        end_label: end_label.clone(),
                    },
                );
                flatten(body, depth + 1, out, labels);
                push(out, depth + 1, ExtKind::EndWhile { label, end_label });
            }
            FpStage::For { var, from, to, body, .. } => {
                let label = labels.next("for");
                let end_label = labels.next("endfor");
                push(
                    out,
                    depth,
                    ExtKind::ForInit { var: var.clone(), from: from.clone(), to: to.clone() },
                );
                push(
                    out,
                    depth,
                    ExtKind::ForTest {
                        var: var.clone(),
                        label: label.clone(),
                        end_label: end_label.clone(),
                    },
                );
                flatten(body, depth + 1, out, labels);
                push(out, depth + 1, ExtKind::EndFor { label, end_label });
            }
            FpStage::Set { code, .. } => push(out, depth, ExtKind::Set { code: code.clone() }),
            FpStage::Call { fun, loop_, brk, until, .. } => push(
                out,
                depth,
                ExtKind::Call { fun: fun.clone(), loop_: *loop_, brk: *brk, until: until.clone() },
            ),
            FpStage::Deroute { target, .. } => {
                push(out, depth, ExtKind::Deroute { target: *target })
            }
            FpStage::Return { reset, .. } => {
                push(out, depth, ExtKind::Return { reset: reset.clone() })
            }
            FpStage::Nav(n) => {
                let mut main = (**n).clone();
                if let Some(lines) = main.init.take() {
                    push(out, depth, ExtKind::NavInit { lines });
                }
                push(out, depth, ExtKind::Nav(Box::new(main)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::span::Span;

    fn call(f: &str) -> FpStage {
        FpStage::Call {
            fun: f.into(),
            loop_: false,
            brk: false,
            until: None,
            span: Span::default(),
        }
    }

    fn fp(stages: Vec<FpStage>) -> Fp {
        Fp {
            blocks: vec![FpBlock {
                name: "b".into(),
                pre_call: None,
                post_call: None,
                on_enter: None,
                on_exit: None,
                exceptions: vec![],
                stages,
                span: Span::default(),
            }],
            exceptions: vec![],
            forbidden: vec![],
            init: vec![],
        }
    }

    #[test]
    fn numbering_follows_upstream_slot_counts() {
        // call(0); while(1) { call(2) } loop-back(3); for init(4) test(5) { call(6) } loop-back(7); end 8
        let w = FpStage::While { cond: "c".into(), body: vec![call("x")], span: Span::default() };
        let f = FpStage::For {
            var: "_var_i".into(),
            from: "1".into(),
            to: "3".into(),
            body: vec![call("y")],
            span: Span::default(),
        };
        let e = extend(&fp(vec![call("a"), w, f]));
        let b = &e.blocks[0];
        let kinds: Vec<(usize, usize, &str)> = b
            .stages
            .iter()
            .map(|s| {
                let k = match &s.kind {
                    ExtKind::Call { .. } => "call",
                    ExtKind::WhileTest { .. } => "while",
                    ExtKind::EndWhile { .. } => "endwhile",
                    ExtKind::ForInit { .. } => "forinit",
                    ExtKind::ForTest { .. } => "fortest",
                    ExtKind::EndFor { .. } => "endfor",
                    _ => "other",
                };
                (s.no, s.depth, k)
            })
            .collect();
        assert_eq!(
            kinds,
            vec![
                (0, 0, "call"),
                (1, 0, "while"),
                (2, 1, "call"),
                (3, 1, "endwhile"),
                (4, 0, "forinit"),
                (5, 0, "fortest"),
                (6, 1, "call"),
                (7, 1, "endfor")
            ]
        );
        assert_eq!(b.default_stage, 8);
        // Labels: one counter, both labels of a loop allocated before its body.
        match (&b.stages[1].kind, &b.stages[5].kind) {
            (
                ExtKind::WhileTest { label, end_label, .. },
                ExtKind::ForTest { label: l2, end_label: e2, .. },
            ) => {
                assert_eq!(
                    (label.as_str(), end_label.as_str(), l2.as_str(), e2.as_str()),
                    ("while_1", "endwhile_2", "for_3", "endfor_4")
                );
            }
            _ => panic!("unexpected kinds"),
        }
    }

    #[test]
    fn two_step_navigation_stages_use_two_numbers() {
        let nav = NavStage {
            kind: NavKind::Eight,
            init: Some(vec![Code::stmt("nav_eight_init()")]),
            pre_call: None,
            before: vec![],
            approach: None,
            approach_upstream: None,
            lines: vec![Code::stmt("Eight(1, 2, 50)")],
            until: None,
            post_call: None,
            span: Span::default(),
        };
        let e = extend(&fp(vec![FpStage::Nav(Box::new(nav)), call("z")]));
        let b = &e.blocks[0];
        assert!(matches!(b.stages[0].kind, ExtKind::NavInit { .. }));
        assert!(matches!(&b.stages[1].kind, ExtKind::Nav(n) if n.init.is_none()));
        assert_eq!((b.stages[2].no, b.default_stage), (2, 3));
    }
}
