//! Crafting recordings with vouch's own encoder: a tlog built message by message.
#![allow(dead_code)]

use std::sync::Arc;

use vouch_mav::codec::MessageBuilder;
use vouch_mav::dialect::Dialect;
use vouch_mav::monitor::offline::{RecordingReport, check_tlog};
use vouch_mav::monitor::{Monitor, Violation};

pub const GCS: (u8, u8) = (255, 190);
pub const UAV: (u8, u8) = (1, 1);

/// The embedded default dialect; a skip (a failure under `VOUCH_REQUIRE_SHARED=1`) when the
/// build was made without one.
pub fn dialect() -> Option<Arc<Dialect>> {
    match Dialect::default_dialect() {
        Ok(d) => Some(Arc::new(d)),
        Err(e) => vouch_testkit::missing(
            vouch_testkit::Need::Shared,
            &format!("no default dialect ({e})"),
        ),
    }
}

pub struct Craft {
    pub d: Arc<Dialect>,
    pub bytes: Vec<u8>,
    pub t: u64,
    seq: u8,
}

impl Craft {
    pub fn new() -> Option<Craft> {
        Some(Craft { d: dialect()?, bytes: Vec::new(), t: 1_700_000_000_000_000, seq: 0 })
    }

    /// Appends one record: `from` sends `name` with numeric and text fields.
    pub fn send_full(
        &mut self,
        from: (u8, u8),
        name: &str,
        fields: &[(&str, f64)],
        texts: &[(&str, &str)],
    ) {
        let mut b = MessageBuilder::new(&self.d, name).expect("message in dialect");
        for (f, v) in fields {
            b = b.set(f, *v).unwrap_or_else(|e| panic!("{name}.{f}: {e}"));
        }
        for (f, t) in texts {
            b = b.set_str(f, t).expect("text field");
        }
        let frame = b.frame_v2(self.seq, from.0, from.1);
        self.seq = self.seq.wrapping_add(1);
        self.t += 10_000;
        self.bytes.extend_from_slice(&self.t.to_be_bytes());
        self.bytes.extend_from_slice(&frame);
    }

    /// A crafting run that starts with one heartbeat of each side (vehicle `armed` in
    /// `custom_mode`), so the monitor knows both roles.
    pub fn with_heartbeats(armed: bool, custom_mode: u32) -> Option<Craft> {
        let mut c = Craft::new()?;
        c.heartbeats(armed, custom_mode);
        Some(c)
    }

    pub fn send(&mut self, from: (u8, u8), name: &str, fields: &[(&str, f64)]) {
        self.send_full(from, name, fields, &[]);
    }

    /// GCS → vehicle 1/1 (target fields filled in).
    pub fn gcs(&mut self, name: &str, fields: &[(&str, f64)]) {
        let mut f = vec![("target_system", 1.0), ("target_component", 1.0)];
        f.extend_from_slice(fields);
        self.send(GCS, name, &f);
    }

    /// Vehicle → GCS 255/190 (target fields filled in when the message has them).
    pub fn uav(&mut self, name: &str, fields: &[(&str, f64)]) {
        let has_target = self.d.by_name(name).and_then(|m| m.field("target_system")).is_some();
        let mut f = if has_target {
            vec![("target_system", 255.0), ("target_component", 190.0)]
        } else {
            vec![]
        };
        f.extend_from_slice(fields);
        self.send(UAV, name, &f);
    }

    /// The vehicle reports parameter `id` = `v` (PARAM_VALUE, REAL32).
    pub fn param_value(&mut self, id: &str, v: f64) {
        self.send_full(
            UAV,
            "PARAM_VALUE",
            &[("param_value", v), ("param_type", 9.0), ("param_count", 3.0)],
            &[("param_id", id)],
        );
    }

    /// The GCS writes parameter `id` = `v` on vehicle 1/1 (PARAM_SET, REAL32).
    pub fn param_set(&mut self, id: &str, v: f64) {
        let f = [
            ("target_system", 1.0),
            ("target_component", 1.0),
            ("param_value", v),
            ("param_type", 9.0),
        ];
        self.send_full(GCS, "PARAM_SET", &f, &[("param_id", id)]);
    }

    pub fn wait_ms(&mut self, ms: u64) {
        self.t += ms * 1000;
    }

    pub fn heartbeats(&mut self, armed: bool, custom_mode: u32) {
        // MAV_TYPE_GCS = 6, MAV_AUTOPILOT_INVALID = 8; QUADROTOR = 2, ARDUPILOTMEGA = 3.
        self.send(GCS, "HEARTBEAT", &[("type", 6.0), ("autopilot", 8.0)]);
        let base_mode = if armed { 128.0 + 1.0 } else { 1.0 };
        self.send(
            UAV,
            "HEARTBEAT",
            &[
                ("type", 2.0),
                ("autopilot", 3.0),
                ("base_mode", base_mode),
                ("custom_mode", f64::from(custom_mode)),
            ],
        );
    }

    pub fn check(&self) -> RecordingReport {
        self.check_with(&[])
    }

    pub fn check_with(&self, overrides: &[(String, f64)]) -> RecordingReport {
        let mut m = Monitor::with_stdlib(self.d.clone(), overrides).expect("stdlib loads");
        check_tlog(&self.bytes, &mut m)
    }

    pub fn check_sources(&self, sources: &[(String, String)]) -> RecordingReport {
        let mut m = Monitor::from_sources(self.d.clone(), sources, &[]).expect("protocols load");
        check_tlog(&self.bytes, &mut m)
    }

    // ---- mission helpers ----

    pub fn count(&mut self, n: u16, mission_type: u8) {
        self.gcs(
            "MISSION_COUNT",
            &[("count", f64::from(n)), ("mission_type", f64::from(mission_type))],
        );
    }

    pub fn request(&mut self, seq: u16, mission_type: u8, deprecated: bool) {
        let name = if deprecated { "MISSION_REQUEST" } else { "MISSION_REQUEST_INT" };
        self.uav(name, &[("seq", f64::from(seq)), ("mission_type", f64::from(mission_type))]);
    }

    pub fn item(&mut self, seq: u16, mission_type: u8) {
        self.gcs(
            "MISSION_ITEM_INT",
            &[
                ("seq", f64::from(seq)),
                ("mission_type", f64::from(mission_type)),
                ("command", 16.0),
                ("frame", 3.0),
                ("x", 473_977_420.0),
                ("y", 85_455_940.0),
                ("z", 50.0),
            ],
        );
    }

    pub fn ack(&mut self, result: u8, mission_type: u8) {
        self.uav(
            "MISSION_ACK",
            &[("type", f64::from(result)), ("mission_type", f64::from(mission_type))],
        );
    }

    /// Request/item pairs for every sequence number in `seqs`, in order.
    pub fn transfer(
        &mut self,
        seqs: std::ops::Range<u16>,
        mission_type: u8,
        deprecated_requests: bool,
    ) {
        for s in seqs {
            self.request(s, mission_type, deprecated_requests);
            self.item(s, mission_type);
        }
    }

    /// A complete, correct upload of `n` items.
    pub fn upload(&mut self, n: u16, mission_type: u8, deprecated_requests: bool) {
        self.count(n, mission_type);
        self.transfer(0..n, mission_type, deprecated_requests);
        self.ack(0, mission_type);
    }
}

/// The violation reports of `r` as text, for assertion messages.
pub fn violation_texts(r: &RecordingReport) -> Vec<String> {
    r.violations.iter().map(|v| v.to_string()).collect()
}

/// Asserts that the recording raised no violation.
pub fn assert_clean(r: &RecordingReport) {
    assert!(r.violations.is_empty(), "expected no violation, got: {:#?}", violation_texts(r));
}

pub fn only_violation(r: &RecordingReport) -> &Violation {
    assert_eq!(
        r.violations.len(),
        1,
        "expected exactly one violation, got: {:#?}",
        violation_texts(r)
    );
    &r.violations[0]
}

pub fn value<'a>(v: &'a Violation, name: &str) -> &'a str {
    v.values
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v.as_str())
        .unwrap_or_else(|| panic!("no value {name} in {v}"))
}

/// A monitor fed frame by frame with the link side of each frame, as the guard feeds it.
pub struct Live {
    pub d: Arc<Dialect>,
    pub m: Monitor,
    pub t: u64,
}

impl Live {
    /// The standard library.
    pub fn new() -> Option<Live> {
        let d = dialect()?;
        let m = Monitor::with_stdlib(d.clone(), &[]).expect("stdlib loads");
        Some(Live { d, m, t: 1_700_000_000_000_000 })
    }

    /// Only the given protocol source.
    pub fn with_source(src: &str) -> Option<Live> {
        let d = dialect()?;
        let sources = [("t.vproto".to_string(), src.to_string())];
        let m = Monitor::from_sources(d.clone(), &sources, &[]).expect("protocol loads");
        Some(Live { d, m, t: 1_700_000_000_000_000 })
    }

    /// `from` sends `name` on link side `side`; returns the monitor's verdict.
    pub fn send_full(
        &mut self,
        side: vouch_mav::Side,
        from: (u8, u8),
        name: &str,
        fields: &[(&str, f64)],
        texts: &[(&str, &str)],
    ) -> vouch_mav::Verdict {
        let mut b = MessageBuilder::new(&self.d, name).expect("message in dialect");
        for (f, v) in fields {
            b = b.set(f, *v).unwrap_or_else(|e| panic!("{name}.{f}: {e}"));
        }
        for (f, t) in texts {
            b = b.set_str(f, t).expect("text field");
        }
        let bytes = b.frame_v2(0, from.0, from.1);
        let mut pos = 0;
        let (_, frame) =
            vouch_mav::FrameSplitter::new().next(&bytes, &mut pos, &self.d, true).expect("frame");
        self.t += 10_000;
        self.m.on_frame(&frame, Some(side), self.t)
    }

    pub fn send(
        &mut self,
        side: vouch_mav::Side,
        from: (u8, u8),
        name: &str,
        fields: &[(&str, f64)],
    ) -> vouch_mav::Verdict {
        self.send_full(side, from, name, fields, &[])
    }

    /// The vehicle 1/1 (quadrotor, ArduPilot) heartbeats on the vehicle side.
    pub fn vehicle_heartbeat(&mut self, armed: bool, custom_mode: u32) -> vouch_mav::Verdict {
        let base_mode = if armed { 129.0 } else { 1.0 };
        let f = [("type", 2.0), ("autopilot", 3.0), ("base_mode", base_mode)];
        let mut fields = f.to_vec();
        fields.push(("custom_mode", f64::from(custom_mode)));
        self.send(vouch_mav::Side::Vehicle, UAV, "HEARTBEAT", &fields)
    }
}
