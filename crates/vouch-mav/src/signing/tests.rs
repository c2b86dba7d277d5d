//! Golden frames below were produced by pymavlink 2.4.50 (`MAVLink.signing` with secret key
//! bytes 0..=31, link id 7, initial timestamp 300000000000, MAVLINK20=1, source 255/230):
//! `mission_count_encode(1, 1, 100)` then `heartbeat_encode(6, 8, 0, 0, 0)`.

use super::*;

const PYMAVLINK_MISSION_COUNT: &str = "fd04010000ffe62c000064000101f8be0700b864d94500f16e608ca27f";
const PYMAVLINK_HEARTBEAT: &str =
    "fd09010000ffe600000000000000060800000360a90701b864d945008f9956aa9a36";

fn hex(s: &str) -> Vec<u8> {
    hex::decode(s).unwrap()
}

fn key() -> SigningKey {
    let mut k = [0u8; 32];
    for (i, b) in k.iter_mut().enumerate() {
        *b = i as u8;
    }
    SigningKey(k)
}

const T0: u64 = 300_000_000_000;

#[test]
fn verifies_pymavlink_signed_frames() {
    let mut v = Verifier::new(key());
    for h in [PYMAVLINK_MISSION_COUNT, PYMAVLINK_HEARTBEAT] {
        let f = hex(h);
        assert_eq!(v.check(&FrameRef::new(&f).unwrap(), T0), Ok(()));
    }
    assert_eq!(v.stream_count(), 1);
}

#[test]
fn rejects_replay_wrong_key_and_tamper() {
    let f = hex(PYMAVLINK_HEARTBEAT);
    let mut v = Verifier::new(key());
    assert_eq!(v.check(&FrameRef::new(&f).unwrap(), T0), Ok(()));
    // exact replay: same timestamp on the same stream
    assert_eq!(v.check(&FrameRef::new(&f).unwrap(), T0), Err(SigReject::Replayed));
    // older frame of the same stream after a newer one
    let older = hex(PYMAVLINK_MISSION_COUNT);
    assert_eq!(v.check(&FrameRef::new(&older).unwrap(), T0), Err(SigReject::Replayed));
    let mut other = Verifier::new(SigningKey([9; 32]));
    assert_eq!(other.check(&FrameRef::new(&f).unwrap(), T0), Err(SigReject::BadSignature));
    let mut tampered = f.clone();
    tampered[14] ^= 1; // payload byte
    let mut fresh = Verifier::new(key());
    assert_eq!(fresh.check(&FrameRef::new(&tampered).unwrap(), T0), Err(SigReject::BadSignature));
    assert_eq!(fresh.stream_count(), 0, "rejected frames leave no state");
}

#[test]
fn new_stream_more_than_a_minute_old_is_rejected() {
    let f = hex(PYMAVLINK_HEARTBEAT);
    let mut v = Verifier::new(key());
    assert_eq!(
        v.check(&FrameRef::new(&f).unwrap(), T0 + 1 + ONE_MINUTE + 1),
        Err(SigReject::TooOld)
    );
    let mut v = Verifier::new(key());
    assert_eq!(v.check(&FrameRef::new(&f).unwrap(), T0 + 1 + ONE_MINUTE - 1), Ok(()));
}

#[test]
fn unsigned_and_v1_rejected() {
    let f = hex(PYMAVLINK_HEARTBEAT);
    let unsigned = &f[..f.len() - SIGNATURE_LEN];
    let mut u = unsigned.to_vec();
    u[2] = 0;
    let mut v = Verifier::new(key());
    assert_eq!(v.check(&FrameRef::new(&u).unwrap(), T0), Err(SigReject::Unsigned));
}

#[test]
fn signer_reproduces_pymavlink_bytes() {
    // Strip pymavlink's signature, clear the flag, fix the CRC as an unsigned sender would:
    // re-signing with the same key, link and timestamp must give pymavlink's exact bytes back.
    let golden = hex(PYMAVLINK_MISSION_COUNT);
    let mut unsigned = golden[..golden.len() - SIGNATURE_LEN].to_vec();
    unsigned[2] = 0;
    let n = unsigned.len();
    let crc = frame_crc(&unsigned[1..n - 2], 221); // MISSION_COUNT CRC_EXTRA
    unsigned[n - 2..].copy_from_slice(&crc.to_le_bytes());
    let mut s = Signer::new(key(), 7);
    let mut out = Vec::new();
    assert!(s.sign_into(&FrameRef::new(&unsigned).unwrap(), T0, &mut out));
    assert_eq!(out, golden);
    // next frame in the same tick still gets a newer timestamp
    assert!(s.sign_into(&FrameRef::new(&unsigned).unwrap(), T0, &mut out));
    let mut v = Verifier::new(key());
    assert_eq!(v.check(&FrameRef::new(&golden).unwrap(), T0), Ok(()));
    assert_eq!(v.check(&FrameRef::new(&out).unwrap(), T0), Ok(()));
}

#[test]
fn key_forms() {
    assert_eq!(SigningKey::from_hex(&"00".repeat(32)), Some(SigningKey([0; 32])));
    assert!(SigningKey::from_hex("zz").is_none());
    // SHA-256("hello"), a published test vector
    let k = SigningKey::from_passphrase("hello");
    assert_eq!(k.0[..4], [0x2c, 0xf2, 0x4d, 0xba]);
    assert!(SigningKey::parse("/nonexistent/key").is_err());
}
