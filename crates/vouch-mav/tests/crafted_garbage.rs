//! Deterministic stand-in for the fuzz targets (which need nightly): random and mutated input
//! through the splitter, the tlog reader, the monitor and the protocol parser — never a panic,
//! every returned frame is an exact byte range of the input.

mod common;
use common::*;
use vouch_mav::codec::{FrameSplitter, TlogReader};
use vouch_mav::monitor::Monitor;
use vouch_mav::protocol::{lint, stdlib};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

#[test]
fn mutated_recordings_never_panic() {
    let Some(mut c) = Craft::new() else { return };
    c.heartbeats(true, 5);
    c.upload(20, 0, true);
    c.send(UAV, "GLOBAL_POSITION_INT", &[("relative_alt", 50_000.0)]);
    c.gcs("COMMAND_LONG", &[("command", 208.0), ("param1", 2.0)]);
    let base = c.bytes.clone();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let d = c.d.clone();
    for round in 0..300 {
        let mut data = base.clone();
        let flips = 1 + (rng.next() % 20) as usize;
        for _ in 0..flips {
            let i = (rng.next() as usize) % data.len();
            data[i] = rng.next() as u8;
        }
        if round % 3 == 0 {
            let cut = (rng.next() as usize) % data.len();
            data.truncate(cut);
        }
        let mut m = Monitor::with_stdlib(d.clone(), &[]).unwrap();
        let mut sp = FrameSplitter::new();
        let mut pos = 0;
        while let Some((r, f)) = sp.next(&data, &mut pos, &d, true) {
            assert_eq!(&data[r], f.bytes);
            let _ = m.on_frame(&f, None, 0);
        }
        for rec in TlogReader::new(&data, &d) {
            let _ = m.on_frame(&rec.frame, None, rec.time_us);
        }
        m.finish();
    }
    // Pure noise.
    let noise: Vec<u8> = (0..200_000).map(|_| rng.next() as u8).collect();
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    while sp.next(&noise, &mut pos, &d, true).is_some() {}
    assert_eq!(pos, noise.len());
    assert!(sp.stats.garbage_bytes > 190_000);
    let _ = TlogReader::new(&noise, &d).count();
}

#[test]
fn mutated_protocol_text_never_panics() {
    let Some(d) = dialect() else { return };
    let src = stdlib::STDLIB[0].1.as_bytes().to_vec();
    let mut rng = Rng(12345);
    let alphabet = b"{}();:,|-><=!&+*/.\"# \nabcXYZ019_";
    for _ in 0..400 {
        let mut s = src.clone();
        for _ in 0..(1 + rng.next() % 8) {
            if s.is_empty() {
                break;
            }
            let i = (rng.next() as usize) % s.len();
            match rng.next() % 3 {
                0 => s[i] = alphabet[(rng.next() as usize) % alphabet.len()],
                1 => {
                    s.remove(i);
                }
                _ => s.truncate(i),
            }
        }
        let text = String::from_utf8_lossy(&s).into_owned();
        if let Err(e) = lint(&d, &[("m.vproto".into(), text)]) {
            assert!(e.line >= 1 && e.col >= 1);
        }
    }
}
