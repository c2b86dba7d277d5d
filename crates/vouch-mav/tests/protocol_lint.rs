//! The protocol language: the standard library checks, and every class of mistake is a located
//! error naming the problem (unknown message / field / enum entry, unbound variable, type
//! mismatch, syntax).

#![allow(clippy::result_large_err)]

mod common;
use common::dialect;
use vouch_mav::protocol::{ErrorKind, ProtocolError, lint, stdlib};

fn lint_src(src: &str) -> Result<(), ProtocolError> {
    let d = dialect().expect("dialect");
    lint(&d, &[("t.vproto".to_string(), src.to_string())]).map(|_| ())
}

fn err(src: &str) -> ProtocolError {
    lint_src(src).expect_err("must be rejected")
}

/// Line and column of the first occurrence of `needle` in `src` (1-based).
fn pos_of(src: &str, needle: &str) -> (usize, usize) {
    let at = src.find(needle).expect("needle in source");
    let line = src[..at].matches('\n').count() + 1;
    let col = at - src[..at].rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
    (line, col)
}

const BASE: &str = "protocol p {\n  roles gcs, uav;\n  gcs -> uav : MISSION_COUNT(n = count) where n > 0;\n  uav -> gcs : MISSION_ACK where type == MAV_MISSION_ACCEPTED;\n}\n";

#[test]
fn standard_library_checks() {
    let Some(d) = dialect() else { return };
    let set = lint(&d, &stdlib::sources()).expect("stdlib is valid");
    let names: Vec<&str> = set.protocols.iter().map(|p| p.name.as_str()).collect();
    for n in [
        "mission_upload",
        "mission_download",
        "param_set",
        "param_read",
        "param_list",
        "command",
        "set_mode",
        "datum_param_dependency",
        "datum_parachute",
    ] {
        assert!(names.contains(&n), "{n} missing from {names:?}");
    }
    assert!(lint_src(BASE).is_ok());
}

#[test]
fn unknown_message_is_located() {
    if dialect().is_none() {
        return;
    }
    let src = BASE.replace("MISSION_ACK", "MISSION_ACKK");
    let e = err(&src);
    assert!(e.message.contains("unknown message `MISSION_ACKK`"), "{}", e.message);
    assert_eq!((e.line, e.col), pos_of(&src, "MISSION_ACKK"));
}

#[test]
fn unknown_field_is_located() {
    if dialect().is_none() {
        return;
    }
    let src = BASE.replace("n = count", "n = cnt");
    let e = err(&src);
    assert!(e.message.contains("MISSION_COUNT has no field `cnt`"), "{}", e.message);
    assert_eq!((e.line, e.col), pos_of(&src, "cnt"));
}

#[test]
fn unknown_enum_entry_or_unbound_variable_is_located() {
    if dialect().is_none() {
        return;
    }
    let src = BASE.replace("MAV_MISSION_ACCEPTED", "MAV_MISSION_ACCEPTD");
    let e = err(&src);
    assert!(e.message.contains("unbound name `MAV_MISSION_ACCEPTD`"), "{}", e.message);
    assert_eq!((e.line, e.col), pos_of(&src, "MAV_MISSION_ACCEPTD"));
    // `n` is bound in the first step only within the protocol's scope: using an unbound name.
    let src = BASE.replace("where n > 0", "where m > 0");
    let e = err(&src);
    assert!(e.message.contains("unbound name `m`"), "{}", e.message);
    assert!(e.help.as_deref().unwrap_or("").contains("MISSION_COUNT"));
}

#[test]
fn type_mismatches_are_located() {
    if dialect().is_none() {
        return;
    }
    // An enum value of another enum.
    let src = BASE.replace("type == MAV_MISSION_ACCEPTED", "type == MAV_CMD_DO_PARACHUTE");
    let e = err(&src);
    assert!(e.message.contains("type mismatch"), "{}", e.message);
    assert!(
        e.message.contains("MAV_MISSION_RESULT") && e.message.contains("MAV_CMD"),
        "{}",
        e.message
    );
    // Text against a number.
    let src = "protocol p { roles gcs, uav; gcs -> uav : PARAM_SET where param_id == 3; }";
    assert!(err(src).message.contains("type mismatch"));
    // A condition that is not boolean.
    let src = "protocol p { roles gcs, uav; gcs -> uav : PARAM_SET where param_value + 1; }";
    assert!(err(src).message.contains("must be a boolean"));
    // A field missing from one of the alternative labels.
    let src =
        "protocol p { roles gcs, uav; gcs -> uav : MISSION_COUNT | MISSION_ACK where count > 1; }";
    assert!(err(src).message.contains("MISSION_ACK has no field `count`"));
}

#[test]
fn structure_errors() {
    if dialect().is_none() {
        return;
    }
    let e = err("protocol p { roles gcs, drone; gcs -> drone : HEARTBEAT; }");
    assert!(e.message.contains("unknown role `drone`"), "{}", e.message);
    let e = err("protocol p { roles gcs, uav; gcs -> uav : HEARTBEAT; continue T(); }");
    assert!(e.message.contains("outside of `rec T`"), "{}", e.message);
    let e =
        err("protocol p { roles gcs, uav; gcs -> uav : HEARTBEAT; end; gcs -> uav : HEARTBEAT; }");
    assert!(e.message.contains("unreachable"), "{}", e.message);
    let e = err("protocol p { roles gcs, uav; key nothing; gcs -> uav : HEARTBEAT; }");
    assert!(e.message.contains("key `nothing`"), "{}", e.message);
    let e = err("protocol p { roles gcs, uav; gcs -> uav : HEARTBEAT where vehicle.speed > 1; }");
    assert!(e.message.contains("unknown vehicle attribute"), "{}", e.message);
}

#[test]
fn syntax_errors_are_located() {
    if dialect().is_none() {
        return;
    }
    let src = "protocol p {\n  roles gcs, uav;\n  gcs -> uav : MISSION_COUNT where count > ;\n}";
    let e = err(src);
    assert!(e.message.contains("expected an expression"), "{}", e.message);
    assert_eq!(e.line, 3);
    let e = err("protocol p { roles gcs uav; }");
    assert!(e.message.contains("expected `;`"), "{}", e.message);
    let e = err("protocol p { roles gcs, uav; gcs -> uav : X where a < b < c; }");
    assert!(e.message.contains("cannot be chained"), "{}", e.message);
    let e = err("protocol p { roles gcs, uav; gcs -> uav : X where \"open; }");
    assert!(e.message.contains("unterminated string"), "{}", e.message);
}

#[test]
fn overrides_must_name_declared_constants() {
    let Some(d) = dialect() else { return };
    let r = vouch_mav::protocol::load_protocols(&d, &stdlib::sources(), &[("NOPE".into(), 1.0)]);
    let e = r.expect_err("unknown constant");
    assert!(e.message.contains("no constant `NOPE`"));
    assert_eq!(e.kind, ErrorKind::Override);
    assert!(
        vouch_mav::protocol::load_protocols(
            &d,
            &stdlib::sources(),
            &[("CHUTE_MAX_CLIMB".into(), 1.0)]
        )
        .is_ok()
    );
}

/// Each class of mistake has its own kind and diagnostic code, so tools can tell them apart.
#[test]
fn every_class_of_mistake_has_its_own_code() {
    if dialect().is_none() {
        return;
    }
    let cases = [
        (BASE.replace("n > 0", "n > 0 $"), ErrorKind::Lex, "mav::P001"),
        (BASE.replace("roles gcs, uav;", "roles gcs uav;"), ErrorKind::Syntax, "mav::P002"),
        (BASE.replace("MISSION_ACK", "MISSION_ACKK"), ErrorKind::UnknownName, "mav::P003"),
        (format!("{BASE}{BASE}"), ErrorKind::Duplicate, "mav::P004"),
        (BASE.replace("n > 0", "n > \"x\""), ErrorKind::Type, "mav::P005"),
        (BASE.replace("roles gcs, uav;", "roles gcs, gcs;"), ErrorKind::Structure, "mav::P006"),
    ];
    for (src, kind, code) in cases {
        let e = err(&src);
        assert_eq!(e.kind, kind, "{}", e.message);
        let got = miette::Diagnostic::code(&e).map(|c| c.to_string());
        assert_eq!(got.as_deref(), Some(code), "{}", e.message);
        assert!(miette::Diagnostic::labels(&e).is_some_and(|mut l| l.next().is_some()));
    }
}

/// Conversions, `param[…]`, `unverifiable` policies and per-role replies: what the checker accepts
/// and what it rejects, located.
#[test]
fn conversions_policies_and_replies_are_checked() {
    if dialect().is_none() {
        return;
    }
    let ok = "protocol p {\n  roles gcs, uav;\n  key command;\n  unverifiable pass;\n  strict uav -> gcs : COMMAND_ACK;\n  on violation reply gcs : COMMAND_ACK(command = command, result = MAV_RESULT_DENIED);\n  on violation by gcs reply uav : PARAM_VALUE(param_value = param[\"X\"], param_id = upper(\"x\"));\n  gcs -> uav : COMMAND_LONG when uint16(param1) == PARACHUTE_RELEASE && finite(param2) where float(param3) < int(param4) + int8(1) + uint32(2);\n}\n";
    lint_src(ok).expect("valid");
    let e = err(&ok.replace("uint16(param1)", "round(param1)"));
    assert_eq!(e.kind, ErrorKind::UnknownName);
    assert!(e.message.contains("unknown function `round`"), "{}", e.message);
    assert_eq!((e.line, e.col), pos_of(ok, "uint16(param1)"));
    let e = err(&ok.replace("finite(param2)", "finite(\"two\")"));
    assert_eq!(e.kind, ErrorKind::Type);
    let e = err(&ok.replace("upper(\"x\")", "upper(3)"));
    assert_eq!(e.kind, ErrorKind::Type);
    let e = err(&ok.replace("param[\"X\"]", "param[3]"));
    assert_eq!(e.kind, ErrorKind::Type);
    let e = err(&ok.replace("unverifiable pass", "unverifiable maybe"));
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert!(e.message.contains("`pass` or `drop`"), "{}", e.message);
    let e = err(&ok.replace("by gcs reply uav", "reply gcs"));
    assert_eq!(e.kind, ErrorKind::Duplicate, "two replies to the same role: {}", e.message);
    let e = err(&ok.replace("by gcs reply", "by pilot reply"));
    assert_eq!(e.kind, ErrorKind::UnknownName);
}
