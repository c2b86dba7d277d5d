//! Seeded randomized checks of the guard's framing and signing (bounded, deterministic):
//! stream reassembly is independent of how reads cut the bytes, CRC_EXTRA recovery is exact, and
//! any single bit flip in a signed frame is rejected.

use vouch_mav::codec::FrameRef;
use vouch_mav::codec::split::{Piece, StreamSplitter, split_datagram};
use vouch_mav::crc::frame_crc;
use vouch_mav::signing::{Signer, SigningKey, Verifier};

/// xorshift64*: a tiny deterministic generator, so failures reproduce from the seed.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
}

/// A random valid unsigned frame (v1 or v2) sealed with a random CRC_EXTRA; returns (frame, extra).
fn random_frame(r: &mut Rng) -> (Vec<u8>, u8) {
    let len = r.below(256) as usize;
    let extra = r.byte();
    let mut f = if r.below(2) == 0 {
        vec![0xFE, len as u8, r.byte(), r.byte(), r.byte(), r.byte()]
    } else {
        vec![
            0xFD,
            len as u8,
            0,
            r.byte(),
            r.byte(),
            r.byte(),
            r.byte(),
            r.byte(),
            r.byte(),
            r.byte(),
        ]
    };
    f.extend((0..len).map(|_| r.byte()));
    let crc = frame_crc(&f[1..], extra);
    f.extend_from_slice(&crc.to_le_bytes());
    (f, extra)
}

#[test]
fn crc_extra_recovery_is_exact() {
    let mut r = Rng(0x5EED_0001);
    for _ in 0..5000 {
        let (f, extra) = random_frame(&mut r);
        assert_eq!(FrameRef::new(&f).unwrap().recover_crc_extra(), Some(extra));
    }
}

#[test]
fn stream_reassembly_does_not_depend_on_read_boundaries() {
    let mut r = Rng(0x5EED_0002);
    let mut stream = vec![];
    let mut frames = vec![];
    let mut junk_total = 0;
    for _ in 0..2000 {
        if r.below(4) == 0 {
            // junk that cannot be mistaken for a frame start
            let n = 1 + r.below(20) as usize;
            stream.extend((0..n).map(|_| {
                loop {
                    let b = r.byte();
                    if b != 0xFD && b != 0xFE {
                        break b;
                    }
                }
            }));
            junk_total += n;
        }
        let (f, _) = random_frame(&mut r);
        stream.extend_from_slice(&f);
        frames.push(f);
    }
    for _ in 0..5 {
        let mut sp = StreamSplitter::default();
        let (mut got, mut junk) = (vec![], 0);
        let mut i = 0;
        while i < stream.len() {
            let n = (1 + r.below(600) as usize).min(stream.len() - i);
            sp.push(&stream[i..i + n], |b, is_frame| {
                if is_frame { got.push(b.to_vec()) } else { junk += b.len() }
            });
            i += n;
        }
        assert_eq!(got, frames);
        assert_eq!(junk, junk_total);
    }
    // the same bytes as one datagram give the same frames
    let mut from_datagram = vec![];
    split_datagram(&stream, |p| {
        if let Piece::Frame(a, b) = p {
            from_datagram.push(stream[a..b].to_vec());
        }
    });
    assert_eq!(from_datagram, frames);
}

#[test]
fn any_bit_flip_in_a_signed_frame_is_rejected() {
    let mut r = Rng(0x5EED_0003);
    let key = SigningKey([0x42; 32]);
    let mut signer = Signer::new(key.clone(), 5);
    let mut signed = vec![];
    let now = 400_000_000_000u64;
    for k in 0..400 {
        let (f, _) = loop {
            let c = random_frame(&mut r);
            if c.0[0] == 0xFD {
                break c;
            }
        };
        assert!(signer.sign_into(&FrameRef::new(&f).unwrap(), now + k, &mut signed));
        let mut v = Verifier::new(key.clone());
        assert_eq!(
            v.check(&FrameRef::new(&signed).unwrap(), now),
            Ok(()),
            "fresh signed frame accepted"
        );
        let bit = r.below(signed.len() as u64 * 8) as usize;
        let mut t = signed.clone();
        t[bit / 8] ^= 1 << (bit % 8);
        // a flip in the length or flags byte may make it no longer one frame: also a rejection
        if let Some(fr) = FrameRef::new(&t) {
            let mut v = Verifier::new(key.clone());
            assert!(v.check(&fr, now).is_err(), "bit {bit} flipped in {signed:02x?} was accepted");
        }
    }
}
