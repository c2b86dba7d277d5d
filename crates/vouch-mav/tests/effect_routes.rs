//! Effects and their routes: the parachute release of the standard library guarded on every
//! route (commands, mission items, servo/relay commands on the parachute's output, RC override of
//! its channel, MAV_CMD_DO_AUX_FUNCTION), with the output read from the parameter cache (unknown =
//! unverifiable); the route check of `vouch mav lint`; the language's new parts, located errors.

mod common;
use common::*;

use vouch_mav::monitor::ViolationKind;
use vouch_mav::protocol::routes::{RouteWarning, describe_route, route_gaps};
use vouch_mav::protocol::{ErrorKind, load_protocols, stdlib};

const LOITER: u32 = 5;

/// Armed copter in LOITER, 50 m above home, climbing at 2 m/s (a release is unsafe), reporting
/// the parameters `params`.
fn climbing(params: &[(&str, f64)]) -> Option<Craft> {
    let mut c = Craft::with_heartbeats(true, LOITER)?;
    c.param_value("CHUTE_ALT_MIN", 10.0);
    for (id, v) in params {
        c.param_value(id, *v);
    }
    c.send(UAV, "GLOBAL_POSITION_INT", &[("relative_alt", 50_000.0), ("vz", -200.0)]);
    Some(c)
}

fn command(c: &mut Craft, cmd: f64, p1: f64, p2: f64) {
    c.gcs("COMMAND_LONG", &[("command", cmd), ("param1", p1), ("param2", p2)]);
}

/// The only violation is the parachute precondition (`vehicle.climb`), from `protocol`.
fn refused_by(r: &vouch_mav::monitor::offline::RecordingReport, protocol: &str) {
    let v = only_violation(r);
    assert_eq!(v.protocol, protocol, "{v}");
    assert_eq!(v.kind, ViolationKind::Refinement, "{v}");
}

#[test]
fn servo_commands_on_the_parachute_output_are_held_to_the_preconditions() {
    for cmd in [183.0, 184.0] {
        let Some(mut c) = climbing(&[("SERVO9_FUNCTION", 27.0), ("SERVO3_FUNCTION", 0.0)]) else {
            return;
        };
        command(&mut c, cmd, 9.0, 1900.0);
        let r = c.check();
        refused_by(&r, "datum_parachute");
        assert_eq!(r.violations[0].predicate.as_deref(), Some("vehicle.climb <= CHUTE_MAX_CLIMB"));
        let reply = r.violations[0].reply.clone().expect("an answer");
        assert!(reply.fields.contains(&("command".into(), cmd)), "{reply:?}");
        // another output: no concern of the parachute rule
        let Some(mut c) = climbing(&[("SERVO9_FUNCTION", 27.0), ("SERVO3_FUNCTION", 0.0)]) else {
            return;
        };
        command(&mut c, cmd, 3.0, 1900.0);
        assert_clean(&c.check());
    }
}

#[test]
fn an_output_whose_function_was_never_reported_is_unverifiable() {
    let Some(mut c) = climbing(&[("SERVO9_FUNCTION", 27.0)]) else { return };
    command(&mut c, 183.0, 5.0, 1900.0);
    let r = c.check();
    assert_clean(&r);
    let p = r.summary.protocol("datum_parachute").unwrap();
    assert_eq!((p.unverifiable, p.violations), (1, 0));
    // the finding names what is missing
    let v = &r.unverifiable[0];
    assert_eq!(v.kind, ViolationKind::Unverifiable);
    assert!(v.predicate.as_deref().unwrap_or("").contains("SERVO{n}_FUNCTION"), "{v}");
    assert_eq!(value(v, "param[\"SERVO{n}_FUNCTION\"]"), "unknown", "{v}");
    assert!(v.reply.is_some(), "refused like a violation under `unverifiable drop`: {v}");
}

#[test]
fn relays_as_arducopter_4_4_and_4_5_number_them() {
    // 4.4: no RELAYn_FUNCTION; CHUTE_TYPE 0 = the first relay (DO_SET_RELAY 0)
    for cmd in [181.0, 182.0] {
        let Some(mut c) = climbing(&[("CHUTE_ENABLED", 1.0), ("CHUTE_TYPE", 0.0)]) else { return };
        command(&mut c, cmd, 0.0, 1.0);
        refused_by(&c.check(), "datum_parachute");
        let Some(mut c) = climbing(&[("CHUTE_ENABLED", 1.0), ("CHUTE_TYPE", 0.0)]) else { return };
        command(&mut c, cmd, 1.0, 1.0);
        assert_clean(&c.check());
    }
    // a disabled parachute has no relay
    let Some(mut c) = climbing(&[("CHUTE_ENABLED", 0.0)]) else { return };
    command(&mut c, 181.0, 0.0, 1.0);
    assert_clean(&c.check());
    // 4.5: RELAY2_FUNCTION = 3 (parachute) is relay 1; RELAY1_FUNCTION = 1 is a plain relay
    let params = [("RELAY1_FUNCTION", 1.0), ("RELAY2_FUNCTION", 3.0), ("CHUTE_TYPE", 0.0)];
    let Some(mut c) = climbing(&params) else { return };
    command(&mut c, 181.0, 1.0, 1.0);
    refused_by(&c.check(), "datum_parachute");
    let Some(mut c) = climbing(&params) else { return };
    command(&mut c, 181.0, 0.0, 1.0);
    assert_clean(&c.check());
}

#[test]
fn aux_function_release_is_a_release() {
    for (func, pos, refused) in [
        (22.0, 2.0, true),
        (23.0, 2.0, true),
        (22.0, f64::NAN, true),
        (22.0, 1.0, false),
        (21.0, 2.0, false),
    ] {
        let Some(mut c) = climbing(&[]) else { return };
        command(&mut c, 218.0, func, pos);
        let r = c.check();
        if refused {
            refused_by(&r, "datum_parachute");
        } else {
            assert_clean(&r);
        }
    }
}

fn rc_override(c: &mut Craft, chans: &[(u8, f64)]) {
    let mut f: Vec<(String, f64)> = (1..=8).map(|n| (format!("chan{n}_raw"), 65535.0)).collect();
    for (n, v) in chans {
        f.retain(|(k, _)| *k != format!("chan{n}_raw"));
        f.push((format!("chan{n}_raw"), *v));
    }
    let fields: Vec<(&str, f64)> = f.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    c.gcs("RC_CHANNELS_OVERRIDE", &fields);
}

#[test]
fn rc_override_of_the_parachute_channel() {
    let opts = [("RC7_OPTION", 22.0), ("RC6_OPTION", 0.0), ("RC_OPTIONS", 0.0)];
    let case = |chans: &[(u8, f64)], extra: &[(&str, f64)]| {
        let mut params = opts.to_vec();
        params.extend_from_slice(extra);
        let mut c = climbing(&params)?;
        rc_override(&mut c, chans);
        Some(c.check())
    };
    let Some(r) = case(&[(7, 1900.0)], &[]) else { return };
    refused_by(&r, "datum_parachute");
    // low, middle, ignored (65535), released (0), out of range: the switch does not read high
    for v in [1000.0, 1500.0, 65535.0, 0.0, 2300.0] {
        let Some(r) = case(&[(7, v)], &[]) else { return };
        assert_clean(&r);
    }
    // another channel high: its function is not the parachute's
    let Some(r) = case(&[(6, 1900.0)], &[]) else { return };
    assert_clean(&r);
    // a reversed switch (RC7_REVERSED, RC_OPTIONS bit 7) reads low values as high
    let rev = [("RC7_REVERSED", 1.0), ("RC_OPTIONS", 128.0 + 1.0)];
    let Some(r) = case(&[(7, 1000.0)], &rev) else { return };
    refused_by(&r, "datum_parachute");
    // a channel whose option was never reported, driven high: unverifiable
    let Some(r) = case(&[(5, 1900.0)], &[]) else { return };
    assert_clean(&r);
    assert_eq!(r.summary.protocol("datum_parachute").unwrap().unverifiable, 1);
}

#[test]
fn a_release_in_an_uploaded_mission_is_refused_on_every_plan_and_carrier() {
    for (name, mission_type) in [
        ("MISSION_ITEM_INT", 0u8),
        ("MISSION_ITEM", 0),
        ("MISSION_ITEM_INT", 1),
        ("MISSION_ITEM_INT", 2),
    ] {
        let Some(mut c) = climbing(&[]) else { return };
        c.count(2, mission_type);
        c.request(0, mission_type, false);
        c.item(0, mission_type);
        c.request(1, mission_type, false);
        c.gcs(
            name,
            &[
                ("seq", 1.0),
                ("mission_type", f64::from(mission_type)),
                ("command", 208.0),
                ("param1", 2.0),
            ],
        );
        let r = c.check();
        let v = r
            .violations
            .iter()
            .find(|v| v.protocol == "datum_parachute_mission")
            .unwrap_or_else(|| panic!("{name} type {mission_type}: {:?}", violation_texts(&r)));
        assert!(v.predicate.as_deref().unwrap_or("").starts_with("refused"), "{v}");
        let replies: Vec<_> = v.replies().map(|r| (r.message.clone(), r.to)).collect();
        assert_eq!(
            replies,
            vec![
                ("MISSION_ACK".to_string(), vouch_mav::Side::Gcs),
                ("STATUSTEXT".to_string(), vouch_mav::Side::Gcs),
                ("MISSION_ACK".to_string(), vouch_mav::Side::Vehicle)
            ],
            "{v}"
        );
        let ack = v.reply.as_ref().unwrap();
        assert!(ack.fields.contains(&("type".into(), 14.0)), "DENIED: {ack:?}");
        assert!(ack.fields.contains(&("mission_type".into(), f64::from(mission_type))), "{ack:?}");
    }
    // a mission item that enables the parachute is no release
    let Some(mut c) = climbing(&[]) else { return };
    c.count(2, 0);
    c.request(0, 0, false);
    c.item(0, 0);
    c.request(1, 0, false);
    c.gcs("MISSION_ITEM_INT", &[("seq", 1.0), ("command", 208.0), ("param1", 1.0)]);
    c.ack(0, 0);
    assert_clean(&c.check());
}

#[test]
fn the_standard_library_guards_every_route_to_the_parachute() {
    let Some(d) = dialect() else { return };
    let set = load_protocols(&d, &stdlib::sources(), &[]).expect("stdlib");
    let gaps = route_gaps(&set);
    assert!(
        gaps.is_empty(),
        "{:?}",
        gaps.iter().map(|g| describe_route(&d, &g.route)).collect::<Vec<_>>()
    );
    let e = set.effects.iter().find(|e| e.name == "parachute_release").expect("the effect");
    let mut routes: Vec<String> = e.routes.iter().map(|r| describe_route(&d, &r.route)).collect();
    routes.sort();
    routes.dedup();
    // 6 commands (DO_PARACHUTE, DO_AUX_FUNCTION, DO_SET/REPEAT_SERVO, DO_SET/REPEAT_RELAY) on 4
    // carriers, and RC_CHANNELS_OVERRIDE
    assert_eq!(routes.len(), 6 * 4 + 1, "{routes:#?}");
    for needed in [
        "COMMAND_INT carrying MAV_CMD_DO_PARACHUTE (command)",
        "MISSION_ITEM carrying MAV_CMD_DO_SET_RELAY (mission)",
        "MISSION_ITEM_INT carrying MAV_CMD_DO_AUX_FUNCTION (mission)",
        "RC_CHANNELS_OVERRIDE (rc)",
    ] {
        assert!(routes.iter().any(|r| r == needed), "{needed} missing from {routes:#?}");
    }
}

const ONE_CARRIER: &str = "\
protocol chute_on_command_long {
  roles gcs, uav;
  gcs -> uav : COMMAND_LONG when command == MAV_CMD_DO_PARACHUTE && uint16(param1) == PARACHUTE_RELEASE
    where vehicle.armed;
}
";

#[test]
fn lint_names_the_carriers_a_protocol_leaves_open() {
    let Some(d) = dialect() else { return };
    let sources = vec![("chute.vproto".to_string(), ONE_CARRIER.to_string())];
    let set = load_protocols(&d, &sources, &[]).expect("valid");
    let gaps = route_gaps(&set);
    let mut named: Vec<String> = gaps.iter().map(|g| describe_route(&d, &g.route)).collect();
    named.sort();
    assert_eq!(
        named,
        vec![
            "COMMAND_INT carrying MAV_CMD_DO_PARACHUTE (command)",
            "MISSION_ITEM carrying MAV_CMD_DO_PARACHUTE (mission)",
            "MISSION_ITEM_INT carrying MAV_CMD_DO_PARACHUTE (mission)",
        ]
    );
    // located at the step that checks the command
    let w = RouteWarning::new(&d, &gaps[0], &sources);
    let text = format!("{w}");
    assert!(text.contains("no loaded protocol guards it on route COMMAND_INT"), "{text}");
    use miette::Diagnostic;
    assert_eq!(w.code().map(|c| c.to_string()).as_deref(), Some("mav::R001"));
    let label = w.labels().and_then(|mut l| l.next()).expect("located");
    assert_eq!(label.offset(), ONE_CARRIER.find("gcs -> uav").unwrap());
    // with the standard library loaded beside it, the parachute rule covers them
    let mut both = stdlib::sources();
    both.extend(sources);
    let set = load_protocols(&d, &both, &[]).expect("valid");
    assert!(route_gaps(&set).is_empty());
}

#[test]
fn an_effect_guarded_by_some_routes_only_is_reported() {
    let Some(d) = dialect() else { return };
    let src = "\
effect release {
  command MAV_CMD_DO_PARACHUTE when uint16(param1) == PARACHUTE_RELEASE;
  rc n in 1..8 when param[\"RC{n}_OPTION\"] == 22 driven when value > 1800;
}
protocol p {
  roles gcs, uav;
  guard release by command where vehicle.armed;
}
";
    let sources = vec![("e.vproto".to_string(), src.to_string())];
    let set = load_protocols(&d, &sources, &[]).expect("valid");
    let named: Vec<String> =
        route_gaps(&set).iter().map(|g| describe_route(&d, &g.route)).collect();
    assert_eq!(named.len(), 3, "{named:?}");
    assert!(named.iter().any(|n| n == "RC_CHANNELS_OVERRIDE (rc)"), "{named:?}");
    assert!(named.iter().any(|n| n.starts_with("MISSION_ITEM_INT")), "{named:?}");
}

/// Mistakes in effects and guards are located errors.
#[test]
fn effect_and_guard_mistakes_are_located() {
    let Some(d) = dialect() else { return };
    let base = "\
effect e {
  command MAV_CMD_DO_PARACHUTE when uint16(param1) == PARACHUTE_RELEASE;
  servo n when param[\"SERVO{n}_FUNCTION\"] == 27;
  rc n in 1..16 when param[\"RC{n}_OPTION\"] == 22 driven when value > 1800;
}
protocol p {
  roles gcs, uav;
  guard e by command, mission where vehicle.armed;
}
";
    let load = |src: &str| load_protocols(&d, &[("x.vproto".into(), src.into())], &[]);
    load(base).expect("valid");
    let cases: &[(&str, &str, ErrorKind, &str)] = &[
        ("guard e by", "guard f by", ErrorKind::UnknownName, "f by"),
        ("command, mission", "command, orbit", ErrorKind::UnknownName, "orbit"),
        (
            "command MAV_CMD_DO_PARACHUTE",
            "command MAV_CMD_DO_NOTHING",
            ErrorKind::UnknownName,
            "MAV_CMD_DO_NOTHING",
        ),
        ("in 1..16", "in 1..19", ErrorKind::UnknownName, "rc n in"),
        ("\"SERVO{n}_FUNCTION\"", "\"SERVO{n_FUNCTION\"", ErrorKind::Syntax, "{n_FUNCTION"),
        ("== 27", "== \"x\"", ErrorKind::Type, "param[\"SERVO"),
        (
            "where vehicle.armed;",
            "where vehicle.armed;\n  gcs -> uav : COMMAND_LONG;",
            ErrorKind::Structure,
            "gcs -> uav : COMMAND_LONG",
        ),
        ("where vehicle.armed", "maybe", ErrorKind::Syntax, "maybe"),
    ];
    for (from, to, kind, at) in cases {
        let src = base.replacen(from, to, 1);
        let e = load(&src).expect_err(&format!("{from} -> {to} must be rejected"));
        assert_eq!(e.kind, *kind, "{from} -> {to}: {}", e.message);
        let want = src.find(at).unwrap();
        let (line, col) = (
            src[..want].matches('\n').count() + 1,
            want - src[..want].rfind('\n').map_or(0, |i| i + 1) + 1,
        );
        assert_eq!((e.line, e.col), (line, col), "{from} -> {to}: {}", e.message);
    }
}

/// `known(x)` and interpolated texts in ordinary protocols.
#[test]
fn known_and_interpolation_in_refinements() {
    let src = "\
protocol p {
  roles gcs, uav;
  gcs -> uav : PARAM_SET where known(param[\"SERVO{int(param_value)}_FUNCTION\"]);
}
";
    let Some(mut c) = climbing(&[("SERVO4_FUNCTION", 0.0)]) else { return };
    for v in [4.0, 5.0] {
        c.param_set("X", v);
    }
    let r = c.check_sources(&[("p.vproto".into(), src.into())]);
    let v = only_violation(&r);
    assert_eq!(value(v, "param[\"SERVO{int(param_value)}_FUNCTION\"]"), "unknown", "{v}");
}

fn value<'v>(v: &'v vouch_mav::Violation, name: &str) -> &'v str {
    v.values.iter().find(|(n, _)| n == name).map(|(_, x)| x.as_str()).unwrap_or("<not shown>")
}
