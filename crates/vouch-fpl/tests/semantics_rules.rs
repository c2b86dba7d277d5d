//! The reference semantics on small plans written for the rules they exercise: the paper's
//! Fig. 2 run, exceptions, the RETURN-after-DEROUTE quirk, `for` counters in `int8_t`,
//! forbidden deroutes, and the per-call bound.

use vouch_fpl::passes::lower::lower;
use vouch_fpl::semantics::Interp;
use vouch_fpl::semantics::oracle::Scripted;
use vouch_fpl::semantics::trace::Event;

fn plan(body: &str, extra: &str) -> vouch_fpl::ast::FlightPlan {
    let xml = format!(
        "<flight_plan name=\"t\" lat0=\"43.46\" lon0=\"1.27\" alt=\"200\" ground_alt=\"150\" security_height=\"25\" \
         max_dist_from_home=\"1000\">\n<waypoints><waypoint name=\"HOME\" x=\"0\" y=\"0\"/></waypoints>\n{extra}\n\
         <blocks>\n{body}\n</blocks>\n</flight_plan>\n"
    );
    vouch_fpl::front::parse_str("t.xml", &xml).unwrap_or_else(|d| panic!("{d}"))
}

fn cond(text: &str, value: bool) -> Event {
    Event::Cond { text: text.into(), value }
}

fn code(text: &str) -> Event {
    Event::Code { text: text.into() }
}

#[test]
fn fig2_while_loop_then_set_then_next_block() {
    let p = plan(
        r#"<block name="init"><call_once fun="InitSensors()"/><while cond="!GPSFixValid()"/><set var="home" value="GPSPosHere()"/></block>
           <block name="takeoff"><call_once fun="StartMotors()" break="TRUE"/></block>"#,
        "",
    );
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    // calls 1..8: condition true; call 9: false.
    let mut answers = vec![1; 8];
    answers.push(0);
    let run = i.run(&mut Scripted::new(answers), 10).expect("bounded");
    assert_eq!(run.steps[0].events, vec![code("InitSensors()"), cond("!(GPSFixValid())", true)]);
    for s in &run.steps[1..8] {
        assert_eq!(s.events, vec![cond("!(GPSFixValid())", true)]);
        assert_eq!((s.after.block, s.after.stage), (0, 2), "inside the loop: the loop-back stage");
    }
    assert_eq!(
        run.steps[8].events,
        vec![cond("!(GPSFixValid())", false), code("home = GPSPosHere()")]
    );
    assert_eq!(run.steps[8].after.block, 1, "the end of block 0 goes to block 1 in the same call");
    assert_eq!(run.steps[9].events, vec![code("StartMotors()")]);
}

#[test]
fn exceptions_are_not_tested_in_their_target_block() {
    let p = plan(
        r#"<block name="a"><call_once fun="a()" break="TRUE"/><deroute block="safe"/></block><block name="safe"><call fun="wait()"/></block>"#,
        r#"<exceptions><exception cond="low()" deroute="safe"/></exceptions>"#,
    );
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    let run = i.run(&mut Scripted::new(vec![1, 1, 1]), 2).expect("bounded");
    // call 1: exception raised, deroute to safe (block 1) without running block 0.
    assert_eq!(run.steps[0].events, vec![cond("low()", true)]);
    assert_eq!((run.steps[0].after.block, run.steps[0].after.last_block), (1, 0));
    // call 2: in safe, the exception is not evaluated; the call stage runs.
    assert_eq!(run.steps[1].events, vec![cond("wait()", true)]);
}

#[test]
fn return_after_deroute_reruns_the_deroute() {
    let p = plan(
        r#"<block name="a"><deroute block="b"/></block><block name="b"><return/></block>"#,
        "",
    );
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    let run = i.run(&mut Scripted::default(), 4).expect("bounded");
    let blocks: Vec<usize> = run.steps.iter().map(|s| s.after.block).collect();
    // Quirk 1 (kept, as upstream's runtime does it): the saved stage is the deroute itself.
    assert_eq!(blocks, vec![1, 0, 1, 0]);
    assert_eq!(run.steps[1].after.stage, 0, "returned to the deroute stage");
}

#[test]
fn for_bounds_are_int8() {
    // Quirk 3: `to="200"` is -56 in int8_t, so the body never runs.
    let p = plan(
        r#"<block name="a"><for var="i" from="1" to="200"><call_once fun="body($i)" break="TRUE"/></for><call_once fun="after()" break="TRUE"/></block>"#,
        "",
    );
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    let run = i.run(&mut Scripted::default(), 1).expect("bounded");
    assert_eq!(
        run.steps[0].events,
        vec![
            Event::Value { text: "1".into(), value: 1 },
            Event::Value { text: "200".into(), value: 200 },
            code("after()")
        ]
    );
    // `to="3"` runs the body three times (`fun` is raw C: `$i` is not rewritten there).
    let p = plan(
        r#"<block name="a"><for var="i" from="1" to="3"><call_once fun="body($i)" break="TRUE"/></for></block>"#,
        "",
    );
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    // calls: test, body, test, body, test, body, test (exit) ... : 3 bodies within 10 calls.
    let run = i.run(&mut Scripted::default(), 10).expect("bounded");
    let bodies =
        run.steps.iter().flat_map(|s| &s.events).filter(|e| **e == code("body($i)")).count();
    assert_eq!(bodies, 3);
}

#[test]
fn forbidden_deroutes_block_the_change() {
    let p = plan(
        r#"<block name="a"><deroute block="c"/></block><block name="b"><call fun="x()"/></block><block name="c"><call fun="y()"/></block>"#,
        "",
    );
    let mut p = p;
    // The extension is added to the AST as the front end would produce it.
    let from = p.blocks[0].name.clone();
    let _ = from;
    p.forbidden_deroutes.push(vouch_fpl::ast::ForbiddenDeroute {
        from: vouch_fpl::ast::BlockRef {
            name: "a".into(),
            id: vouch_fpl::ids::BlockId(0),
            span: p.span,
        },
        to: vouch_fpl::ast::BlockRef {
            name: "c".into(),
            id: vouch_fpl::ids::BlockId(2),
            span: p.span,
        },
        only_when: None,
        attrs: Default::default(),
        span: p.span,
    });
    let fp = lower(&p).expect("lowers");
    let mut i = Interp::new(&fp);
    let run = i.run(&mut Scripted::default(), 3).expect("bounded");
    assert!(run.steps.iter().all(|s| s.after.block == 0), "the deroute a -> c never happens");
}

#[test]
fn nested_loops_with_empty_bodies_stay_within_the_bound() {
    let p = plan(
        r#"<block name="a"><while cond="c1()"><while cond="c2()"><while cond="c3()"/></while></while><set var="x" value="1"/></block>"#,
        "",
    );
    let fp = lower(&p).expect("lowers");
    for pattern in [
        vec![0i64; 64],
        vec![1; 64],
        (0..64).map(|k| k % 2).collect(),
        (0..64).map(|k| (k / 3) % 2).collect(),
    ] {
        let mut i = Interp::new(&fp);
        i.run(&mut Scripted::new(pattern), 30).expect("every call terminates within the bound");
    }
}
