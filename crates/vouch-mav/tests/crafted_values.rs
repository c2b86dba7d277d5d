//! Values as the autopilot reads them: the protocol language's conversions agree with C (the
//! C compiler is the reference), and every command parameter of the standard library that
//! ArduPilot or PX4 reads as an integer or enum is checked through them.

mod common;
use common::*;
use vouch_mav::monitor::eval::{Val, call};
use vouch_mav::protocol::ir::Builtin;

/// The C types of the integer conversions: (function, C type, bits, signed).
const INTS: &[(&str, &str, u8, bool)] = &[
    ("int8", "int8_t", 8, true),
    ("int16", "int16_t", 16, true),
    ("int", "int32_t", 32, true),
    ("uint8", "uint8_t", 8, false),
    ("uint16", "uint16_t", 16, false),
    ("uint32", "uint32_t", 32, false),
];

/// Inputs, as f32 values (every float field on the wire is one) and as doubles.
const INPUTS: &[f64] = &[
    0.0,
    -0.0,
    0.5,
    -0.5,
    1.999_999_9,
    2.0,
    2.5,
    2.999_999_8,
    -2.5,
    127.9,
    -128.9,
    128.0,
    255.5,
    256.0,
    -1.0,
    32_767.5,
    -32_768.7,
    65_535.99,
    65_536.0,
    65_538.0,
    -65_534.0,
    16_777_217.0,
    2_147_483_520.0,
    -2_147_483_648.0,
    4_294_967_040.0,
    1e10,
    0.1,
    std::f64::consts::PI,
    1e-40,
    1e39,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
];

fn range(bits: u8, signed: bool) -> (f64, f64) {
    if signed {
        (-(2f64.powi(i32::from(bits) - 1)), 2f64.powi(i32::from(bits) - 1) - 1.0)
    } else {
        (0.0, 2f64.powi(i32::from(bits)) - 1.0)
    }
}

/// For every input whose conversion C defines (the truncated value fits the type), the monitor's
/// conversion equals what C computes; for the others (NaN, infinities, out of range: undefined
/// in C, and different on different processors) it is unknown. `float(x)` equals C's
/// `(double)(float)x` everywhere.
#[test]
fn conversions_agree_with_c() {
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let dir = std::env::temp_dir().join(format!("vouch-conv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut c = String::from(
        "#include <stdio.h>\n#include <stdint.h>\n#include <math.h>\nint main(void) {\n  volatile double x;\n",
    );
    let mut lines = 0;
    for (i, x) in INPUTS.iter().enumerate() {
        c += &format!("  x = {};\n", c_literal(*x));
        c += &format!("  printf(\"{i} float %.17g\\n\", (double)(float)x);\n");
        lines += 1;
        for (name, ty, bits, signed) in INTS {
            let (lo, hi) = range(*bits, *signed);
            if x.is_finite() && x.trunc() >= lo && x.trunc() <= hi {
                c += &format!("  printf(\"{i} {name} %.17g\\n\", (double)({ty})x);\n");
                lines += 1;
            }
        }
    }
    c += "  return 0;\n}\n";
    std::fs::write(dir.join("conv.c"), c).unwrap();
    let exe = dir.join("conv");
    let st = std::process::Command::new(&cc)
        .arg(dir.join("conv.c"))
        .arg("-o")
        .arg(&exe)
        .arg("-lm")
        .status()
        .expect("cc runs");
    assert!(st.success(), "cc failed");
    let out = std::process::Command::new(&exe).output().expect("runs");
    let text = String::from_utf8(out.stdout).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let mut compared = 0;
    for line in text.lines() {
        let mut w = line.split(' ');
        let (i, f, v) = (w.next().unwrap(), w.next().unwrap(), w.next().unwrap());
        let x = INPUTS[i.parse::<usize>().unwrap()];
        let want: f64 = match v {
            "nan" | "-nan" => f64::NAN,
            "inf" => f64::INFINITY,
            "-inf" => f64::NEG_INFINITY,
            v => v.parse().unwrap(),
        };
        let got = call(Builtin::named(f).expect("builtin"), Val::Num(x));
        match got {
            Val::Num(g) => {
                assert!(g == want || (g.is_nan() && want.is_nan()), "{f}({x}) = {g}, C says {want}")
            }
            other => panic!("{f}({x}) = {other:?}, C says {want}"),
        }
        compared += 1;
    }
    assert_eq!(compared, lines, "every conversion C printed was compared");
    // Undefined in C: unknown here.
    for x in INPUTS {
        for (name, _, bits, signed) in INTS {
            let (lo, hi) = range(*bits, *signed);
            if !(x.is_finite() && x.trunc() >= lo && x.trunc() <= hi) {
                let got = call(Builtin::named(name).unwrap(), Val::Num(*x));
                assert_eq!(got, Val::Unknown, "{name}({x})");
            }
        }
    }
}

fn c_literal(x: f64) -> String {
    if x.is_nan() {
        "NAN".into()
    } else if x.is_infinite() {
        if x > 0.0 { "INFINITY" } else { "-INFINITY" }.into()
    } else {
        format!("{x:e}")
    }
}

#[test]
fn tests_and_text_functions() {
    let num = |f: &str, x: f64| call(Builtin::named(f).unwrap(), Val::Num(x));
    assert_eq!(num("finite", 2.0), Val::Bool(true));
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(num("finite", x), Val::Bool(false));
    }
    assert_eq!(call(Builtin::Upper, Val::text(b"mc_Pitch_p")), Val::text(b"MC_PITCH_P"));
    assert_eq!(call(Builtin::Upper, Val::Num(1.0)), Val::Unknown);
    assert_eq!(call(Builtin::Finite, Val::Unknown), Val::Unknown);
}

const PARACHUTE: f64 = 208.0;

/// DO_PARACHUTE param1 (PARACHUTE_ACTION), which ArduPilot reads as `(uint16_t)param1`: every
/// value that is a release there (2 and its fractions), a fraction another reader may round, or
/// a value whose conversion C leaves undefined (NaN, infinities, out of range), is refused while
/// the vehicle climbs, as COMMAND_LONG and as COMMAND_INT; whole numbers other than 2 pass; in a
/// safe state everything passes.
#[test]
fn parachute_action_is_read_as_the_autopilot_reads_it() {
    let f32v = |x: f32| f64::from(x);
    let refused = [
        2.0,
        2.5,
        f32v(2.999_999_8),
        f32v(2.000_000_2),
        1.5,
        f32v(1.999_999_9),
        -0.5,
        65_538.0,
        -65_534.0,
        1e10,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let passed = [0.0, -0.0, 1.0, 3.0, 65_535.0];
    for form in ["COMMAND_LONG", "COMMAND_INT"] {
        for (climb, safe) in [(2.0, false), (-0.5, true)] {
            for &action in refused.iter().chain(&passed) {
                let Some(mut c) = Craft::with_heartbeats(true, 5) else { return };
                c.send_full(
                    UAV,
                    "PARAM_VALUE",
                    &[("param_value", 10.0), ("param_type", 9.0)],
                    &[("param_id", "CHUTE_ALT_MIN")],
                );
                c.send(
                    UAV,
                    "GLOBAL_POSITION_INT",
                    &[("relative_alt", 50_000.0), ("vz", -climb * 100.0)],
                );
                c.gcs(form, &[("command", PARACHUTE), ("param1", action)]);
                let r = c.check();
                let must_refuse = !safe && !passed.contains(&action);
                let what = format!("{form} param1 = {action} (climb {climb} m/s)");
                if must_refuse {
                    let v = only_violation(&r);
                    assert_eq!(v.protocol, "datum_parachute", "{what}");
                    assert_eq!(
                        v.predicate.as_deref(),
                        Some("vehicle.climb <= CHUTE_MAX_CLIMB"),
                        "{what}"
                    );
                } else {
                    assert!(r.violations.is_empty(), "{what}: {:?}", violation_texts(&r));
                }
            }
        }
    }
}
