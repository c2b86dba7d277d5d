//! The monitor's worst case: every protocol of the standard library holding its maximum of 64
//! open sessions (512 in all), then traffic that belongs to none of them — telemetry that no
//! protocol mentions, a PARAM_VALUE that every open parameter-list session takes and every
//! parameter read/write session compares, a MISSION_ACK addressed to a ground station that has no
//! session. Each stream is timed with no session open and with all 512 open, in the same run.
//!
//! `cargo bench -p vouch-mav --bench monitor_worst_case` (no input needed).

mod support;

use std::sync::Arc;

use support::{Figures, timed};
use vouch_mav::Side;
use vouch_mav::codec::{Frame, FrameSplitter, MessageBuilder};
use vouch_mav::dialect::Dialect;
use vouch_mav::monitor::{MAX_SESSIONS_PER_PROTOCOL, Monitor};

const UAV: (u8, u8) = (1, 1);

/// One frame's bytes: `name` from `from` with `fields` and `texts`.
fn frame(
    d: &Dialect,
    from: (u8, u8),
    name: &str,
    fields: &[(&str, f64)],
    texts: &[(&str, &str)],
) -> Vec<u8> {
    let mut b = MessageBuilder::new(d, name).expect("message");
    for (f, v) in fields {
        b = b.set(f, *v).expect("field");
    }
    for (f, t) in texts {
        b = b.set_str(f, t).expect("text");
    }
    b.frame_v2(0, from.0, from.1)
}

fn parse<'a>(d: &Dialect, bytes: &'a [u8]) -> Frame<'a> {
    let mut pos = 0;
    FrameSplitter::new().next(bytes, &mut pos, d, true).expect("frame").1
}

/// Opens 64 sessions in every protocol that keeps sessions open (the single-step DATUM rules
/// keep none): different ground stations, parameter names and commands.
fn open_everything(d: &Dialect, m: &mut Monitor, t: &mut u64) {
    let mut send = |m: &mut Monitor,
                    side,
                    from,
                    name: &str,
                    fields: &[(&str, f64)],
                    texts: &[(&str, &str)]| {
        *t += 1;
        let bytes = frame(d, from, name, fields, texts);
        m.on_frame(&parse(d, &bytes), Some(side), *t);
    };
    send(m, Side::Vehicle, UAV, "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0)], &[]);
    let to = [("target_system", 1.0), ("target_component", 1.0)];
    for k in 0..MAX_SESSIONS_PER_PROTOCOL as u8 {
        let gcs = (100 + k, 190);
        let with = |extra: &[(&'static str, f64)]| [&to[..], extra].concat();
        send(m, Side::Gcs, gcs, "MISSION_COUNT", &with(&[("count", 10.0)]), &[]);
        send(m, Side::Gcs, gcs, "MISSION_REQUEST_LIST", &to, &[]);
        send(m, Side::Gcs, gcs, "MISSION_CLEAR_ALL", &to, &[]);
        send(m, Side::Gcs, gcs, "PARAM_REQUEST_LIST", &to, &[]);
        send(m, Side::Gcs, gcs, "SET_MODE", &[("target_system", 1.0), ("custom_mode", 5.0)], &[]);
        let name = format!("P{k:02}");
        send(
            m,
            Side::Gcs,
            (255, 190),
            "PARAM_SET",
            &with(&[("param_value", 1.0)]),
            &[("param_id", &name)],
        );
        let read = format!("R{k:02}");
        send(
            m,
            Side::Gcs,
            (255, 190),
            "PARAM_REQUEST_READ",
            &with(&[("param_index", -1.0)]),
            &[("param_id", &read)],
        );
        send(
            m,
            Side::Gcs,
            (255, 190),
            "COMMAND_LONG",
            &with(&[("command", 300.0 + f64::from(k))]),
            &[],
        );
    }
}

fn main() {
    let dialect = match Dialect::default_dialect() {
        Ok(d) => Arc::new(d),
        Err(e) => {
            eprintln!("monitor_worst_case: no default dialect ({e})");
            return;
        }
    };
    let d = &*dialect;
    let streams: [(&str, Vec<u8>); 3] = [
        (
            "telemetry no protocol mentions (ATTITUDE)",
            frame(d, UAV, "ATTITUDE", &[("roll", 0.1)], &[]),
        ),
        (
            "PARAM_VALUE nobody asked for",
            frame(
                d,
                UAV,
                "PARAM_VALUE",
                &[("param_value", 2.0), ("param_count", 900.0)],
                &[("param_id", "X_UNASKED")],
            ),
        ),
        (
            "MISSION_ACK to a ground station with no session",
            frame(d, UAV, "MISSION_ACK", &[("target_system", 7.0), ("target_component", 7.0)], &[]),
        ),
    ];
    let n = 100_000u64;
    let reps = 5;
    for (what, bytes) in &streams {
        let f = parse(d, bytes);
        let mut results = Vec::new();
        for open in [false, true] {
            let mut figures = Figures::default();
            let mut sessions = 0;
            for _ in 0..reps {
                let mut m = Monitor::with_stdlib(dialect.clone(), &[]).expect("stdlib");
                let mut t = 1_000_000u64;
                if open {
                    open_everything(d, &mut m, &mut t);
                } else {
                    let hb = frame(d, UAV, "HEARTBEAT", &[("type", 2.0), ("autopilot", 3.0)], &[]);
                    m.on_frame(&parse(d, &hb), Some(Side::Vehicle), t);
                }
                sessions = m.summary().open_sessions;
                // 1 µs of message time per message: no session times out during the run
                figures.add(
                    timed(|| {
                        for i in 0..n {
                            std::hint::black_box(m.on_frame(&f, Some(Side::Vehicle), t + i));
                        }
                    }),
                    n,
                );
                assert_eq!(m.summary().violations, 0);
            }
            results.push((sessions, figures));
        }
        println!("{what}:");
        for (sessions, mut figures) in results {
            println!("  {sessions:>3} open sessions: {}", figures.line());
        }
    }
}
