//! Properties of the reference semantics on random plans (nested `while`/`for`, calls, sets,
//! deroutes, returns, two-step navigation stages, exceptions) and random answer sequences:
//! every call terminates within the documented bound (`step` never reports `Diverged`), and the
//! stage numbers it reports are those the extend pass assigns (always a stage of the block).

use proptest::prelude::*;
use vouch_fpl::ast::Resume;
use vouch_fpl::passes::extend::extend;
use vouch_fpl::passes::fp::{Code, Fp, FpBlock, FpException, FpStage, NavKind, NavStage, Reset};
use vouch_fpl::semantics::Interp;
use vouch_fpl::semantics::oracle::Scripted;
use vouch_fpl::span::Span;

fn stage(n_blocks: usize) -> impl Strategy<Value = FpStage> {
    let leaf = prop_oneof![
        Just(FpStage::Set { code: Code::stmt("x = 1"), span: Span::default() }),
        (any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(l, b, u)| FpStage::Call {
            fun: "f()".into(),
            loop_: l,
            brk: b,
            until: u.then(|| "u()".to_string()),
            span: Span::default()
        }),
        (0..n_blocks).prop_map(|t| FpStage::Deroute { target: t, span: Span::default() }),
        prop_oneof![Just(("0", Resume::SavedStage)), Just(("1", Resume::FirstStage))].prop_map(
            |(text, resume)| FpStage::Return {
                reset: Reset { text: text.into(), resume },
                span: Span::default()
            }
        ),
        (any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(init, appr, until)| FpStage::Nav(
            Box::new(NavStage {
                kind: NavKind::Go,
                init: init.then(|| vec![Code::stmt("init()")]),
                pre_call: None,
                before: vec![],
                approach: appr.then(|| ("near()".to_string(), 1)),
                approach_upstream: None,
                lines: vec![Code::stmt("go()")],
                until: until.then(|| "done()".to_string()),
                post_call: None,
                span: Span::default(),
            })
        )),
    ];
    leaf.prop_recursive(3, 24, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(|body| FpStage::While {
                cond: "w()".into(),
                body,
                span: Span::default()
            }),
            (prop::collection::vec(inner, 0..4), prop_oneof![Just("3"), Just("n"), Just("200")])
                .prop_map(|(body, to)| {
                    FpStage::For {
                        var: "_var_i".into(),
                        from: "1".into(),
                        to: to.into(),
                        body,
                        span: Span::default(),
                    }
                }),
        ]
    })
}

fn plan() -> impl Strategy<Value = Fp> {
    (1usize..5).prop_flat_map(|n| {
        (
            prop::collection::vec(
                (prop::collection::vec(stage(n), 0..6), prop::option::of(0..n)),
                n,
            ),
            prop::option::of(0..n),
        )
            .prop_map(move |(blocks, global)| {
                let exc = |t: usize| FpException {
                    cond: "e()".into(),
                    target: t,
                    exec: None,
                    span: Span::default(),
                };
                Fp {
                    blocks: blocks
                        .into_iter()
                        .enumerate()
                        .map(|(i, (stages, ex))| FpBlock {
                            name: format!("b{i}"),
                            pre_call: None,
                            post_call: None,
                            on_enter: None,
                            on_exit: None,
                            exceptions: ex.map(exc).into_iter().collect(),
                            stages,
                            span: Span::default(),
                        })
                        .collect(),
                    exceptions: global.map(exc).into_iter().collect(),
                    forbidden: vec![],
                    init: vec![],
                }
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn every_call_terminates_and_reports_extended_stage_numbers(
        fp in plan(),
        answers in prop::collection::vec(0i64..16, 0..400),
    ) {
        let fpe = extend(&fp);
        let mut interp = Interp::new(&fp);
        let run = interp.run(&mut Scripted::new(answers), 60);
        prop_assert!(run.is_ok(), "a call exceeded its bound: {:?}", run.err());
        for s in run.unwrap().steps {
            let b = &fpe.blocks[s.after.block];
            prop_assert!(s.after.stage <= b.default_stage, "stage {} beyond block end {}", s.after.stage, b.default_stage);
            let lb = &fpe.blocks[s.after.last_block];
            prop_assert!(s.after.last_stage <= lb.default_stage);
        }
    }
}
