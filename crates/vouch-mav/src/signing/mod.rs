//! MAVLink 2 message signing: verification with per-stream replay protection, and signing of
//! frames the guard sends toward the vehicle.
//!
//! Signature = first 6 bytes of SHA-256(secret key ‖ frame header incl. magic ‖ payload ‖ CRC ‖
//! link id ‖ 6-byte timestamp). Timestamps count 10 µs units since 2015-01-01 00:00 UTC.
//! A stream is (system id, component id, link id). Like the reference C implementation, a frame
//! is rejected when its timestamp is not *newer* than the stream's last accepted one (so an exact
//! replay is rejected), and a new stream is admitted only when its timestamp is less than one minute
//! behind the local clock. Only frames whose signature matches update any state, so forged frames
//! cannot poison the replay table. The replay table survives restarts through [`state`]: a state
//! file written at least every second and at shutdown, read back at start.

use std::collections::HashMap;
use std::fmt;
use std::time::{SystemTime, UNIX_EPOCH};

use sha2::{Digest, Sha256};

use crate::codec::frame::{FrameRef, INCOMPAT_SIGNED, SIGNATURE_LEN};
use crate::crc::frame_crc;

pub mod state;

/// UNIX seconds at 2015-01-01 00:00:00 UTC, the MAVLink signing epoch.
pub const MAVLINK_EPOCH_UNIX_S: u64 = 1_420_070_400;
/// One minute in signing timestamp units (10 µs).
pub const ONE_MINUTE: u64 = 6_000_000;
/// Bound on tracked streams: memory stays fixed under floods of validly signed new streams.
pub const MAX_STREAMS: usize = 256;
/// Message id of SETUP_SIGNING, which carries a key and must never be forwarded.
pub const SETUP_SIGNING_ID: u32 = 256;

/// A 32-byte MAVLink signing secret.
#[derive(Clone, PartialEq, Eq)]
pub struct SigningKey(pub [u8; 32]);

impl fmt::Debug for SigningKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SigningKey(…)") // never print secrets
    }
}

impl SigningKey {
    /// Parses a key as operators give it: 64 hex digits, `passphrase:TEXT` (key = SHA-256 of
    /// the text, MAVProxy's `signing setup` convention), or a path to a file holding either 32
    /// raw bytes or 64 hex digits.
    pub fn parse(spec: &str) -> Result<Self, KeyError> {
        if let Some(text) = spec.strip_prefix("passphrase:") {
            return Ok(Self::from_passphrase(text));
        }
        if let Some(k) = Self::from_hex(spec) {
            return Ok(k);
        }
        let bytes = std::fs::read(spec)
            .map_err(|source| KeyError::Unreadable { spec: spec.to_string(), source })?;
        if bytes.len() == 32 {
            let mut k = [0u8; 32];
            k.copy_from_slice(&bytes);
            return Ok(SigningKey(k));
        }
        std::str::from_utf8(&bytes)
            .ok()
            .and_then(|s| Self::from_hex(s.trim()))
            .ok_or(KeyError::BadFile { path: spec.to_string(), len: bytes.len() })
    }

    /// A key from 64 hex digits.
    pub fn from_hex(s: &str) -> Option<Self> {
        let mut k = [0u8; 32];
        hex::decode_to_slice(s.trim(), &mut k).ok()?;
        Some(SigningKey(k))
    }

    /// The key MAVProxy derives from a passphrase (SHA-256 of its text).
    pub fn from_passphrase(text: &str) -> Self {
        SigningKey(Sha256::digest(text.as_bytes()).into())
    }

    /// The 6-byte signature of `unsigned_part` (header..CRC, flag already set) with the given
    /// link id and timestamp.
    pub fn signature(&self, unsigned_part: &[u8], link_id: u8, timestamp: u64) -> [u8; 6] {
        let mut h = Sha256::new();
        h.update(self.0);
        h.update(unsigned_part);
        h.update([link_id]);
        h.update(&timestamp.to_le_bytes()[..6]);
        let d = h.finalize();
        let mut s = [0u8; 6];
        s.copy_from_slice(&d[..6]);
        s
    }
}

/// Why a signing key could not be read.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum KeyError {
    /// Neither hex nor a passphrase, and no file by that name can be read.
    #[error(
        "signing key `{spec}` is neither 64 hex digits, `passphrase:…`, nor a readable file: {source}"
    )]
    #[diagnostic(code(mav::K001))]
    Unreadable {
        /// What was given.
        spec: String,
        /// Why the file cannot be read.
        source: std::io::Error,
    },
    /// A key file that holds neither 32 raw bytes nor 64 hex digits.
    #[error("signing key file `{path}`: expected 32 raw bytes or 64 hex digits, found {len} bytes")]
    #[diagnostic(code(mav::K002))]
    BadFile {
        /// The file.
        path: String,
        /// Its length.
        len: usize,
    },
}

/// Current time in signing units (10 µs since 2015-01-01).
pub fn timestamp_now() -> u64 {
    let since_unix = SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or_default();
    (since_unix.as_micros() as u64 / 10).saturating_sub(MAVLINK_EPOCH_UNIX_S * 100_000)
}

/// Why a frame failed the signing check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SigReject {
    /// MAVLink 1 frames cannot be signed.
    NotV2,
    Unsigned,
    BadSignature,
    /// Timestamp not newer than the stream's last accepted frame (replay).
    Replayed,
    /// First frame of a stream more than a minute behind the local clock.
    TooOld,
    /// The stream table is full (bounded memory under floods).
    TooManyStreams,
}

impl SigReject {
    pub fn as_str(self) -> &'static str {
        match self {
            SigReject::NotV2 => "mavlink1-unsigned",
            SigReject::Unsigned => "unsigned",
            SigReject::BadSignature => "bad-signature",
            SigReject::Replayed => "replayed-timestamp",
            SigReject::TooOld => "stale-timestamp",
            SigReject::TooManyStreams => "too-many-streams",
        }
    }
}

/// Verifies signed frames and keeps the per-stream replay state.
pub struct Verifier {
    key: SigningKey,
    streams: HashMap<(u8, u8, u8), u64>,
    /// Highest timestamp known locally: max(clock, every accepted timestamp), as the spec says.
    local: u64,
    /// The replay state changed since [`Verifier::take_changes`] was last called.
    changed: bool,
}

/// The replay state of a [`Verifier`]: what must survive a restart.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReplayState {
    /// Last accepted timestamp per stream (system id, component id, link id).
    pub streams: Vec<((u8, u8, u8), u64)>,
    /// The highest timestamp known (clock or accepted).
    pub local: u64,
}

impl Verifier {
    pub fn new(key: SigningKey) -> Self {
        Verifier { key, streams: HashMap::new(), local: 0, changed: false }
    }

    /// The key frames are checked with.
    pub fn key(&self) -> &SigningKey {
        &self.key
    }

    /// The replay state now (streams sorted, for stable files).
    pub fn replay_state(&self) -> ReplayState {
        let mut streams: Vec<_> = self.streams.iter().map(|(k, v)| (*k, *v)).collect();
        streams.sort_unstable();
        ReplayState { streams, local: self.local }
    }

    /// Takes over a saved replay state: frames not newer than a saved stream's last timestamp
    /// are refused from now on. At most [`MAX_STREAMS`] streams are kept (the newest).
    pub fn restore(&mut self, saved: &ReplayState) {
        let mut streams = saved.streams.clone();
        streams.sort_unstable_by_key(|(_, ts)| std::cmp::Reverse(*ts));
        for (k, ts) in streams.into_iter().take(MAX_STREAMS) {
            let last = self.streams.entry(k).or_insert(ts);
            *last = (*last).max(ts);
        }
        self.local = self.local.max(saved.local);
    }

    /// Whether the replay state changed since the last call (and clears the mark).
    pub fn take_changes(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    pub fn stream_count(&self) -> usize {
        self.streams.len()
    }

    /// Checks `frame` against the key and the replay rules at local time `now` (signing units).
    /// Accepting updates the stream's last timestamp; rejecting changes nothing.
    pub fn check(&mut self, frame: &FrameRef<'_>, now: u64) -> Result<(), SigReject> {
        if !frame.is_v2() {
            return Err(SigReject::NotV2);
        }
        let Some(block) = frame.signature_block() else { return Err(SigReject::Unsigned) };
        let link_id = block[0];
        let mut ts_bytes = [0u8; 8];
        ts_bytes[..6].copy_from_slice(&block[1..7]);
        let ts = u64::from_le_bytes(ts_bytes);
        let expected = self.key.signature(frame.unsigned_part(), link_id, ts);
        if !constant_time_eq(&expected, &block[7..13]) {
            return Err(SigReject::BadSignature);
        }
        self.local = self.local.max(now);
        let key = (frame.sysid(), frame.compid(), link_id);
        match self.streams.get(&key) {
            Some(&last) if ts <= last => return Err(SigReject::Replayed),
            Some(_) => {}
            None => {
                if ts + ONE_MINUTE < self.local {
                    return Err(SigReject::TooOld);
                }
                if self.streams.len() >= MAX_STREAMS {
                    return Err(SigReject::TooManyStreams);
                }
            }
        }
        self.streams.insert(key, ts);
        self.local = self.local.max(ts);
        self.changed = true;
        Ok(())
    }
}

fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// Signs frames on one outgoing link with a strictly increasing timestamp.
pub struct Signer {
    key: SigningKey,
    link_id: u8,
    last: u64,
}

impl Signer {
    pub fn new(key: SigningKey, link_id: u8) -> Self {
        Signer { key, link_id, last: 0 }
    }

    /// Writes into `out` a copy of `frame` carrying this link's signature. A signed frame keeps
    /// its header and CRC (the flag is already set) and gets a new signature block; an unsigned
    /// MAVLink 2 frame gets the flag set and its CRC recomputed with the recovered CRC_EXTRA.
    /// MAVLink 1 frames cannot be signed: returns false and leaves `out` empty.
    pub fn sign_into(&mut self, frame: &FrameRef<'_>, now: u64, out: &mut Vec<u8>) -> bool {
        out.clear();
        if !frame.is_v2() {
            return false;
        }
        out.extend_from_slice(frame.unsigned_part());
        if !frame.is_signed() {
            let Some(extra) = frame.recover_crc_extra() else { return false };
            out[2] |= INCOMPAT_SIGNED;
            let n = out.len();
            let crc = frame_crc(&out[1..n - 2], extra);
            out[n - 2..].copy_from_slice(&crc.to_le_bytes());
        }
        // Strictly increasing even when several frames share one clock tick (spec requirement).
        let ts = now.max(self.last + 1);
        self.last = ts;
        let sig = self.key.signature(out, self.link_id, ts);
        out.push(self.link_id);
        out.extend_from_slice(&ts.to_le_bytes()[..6]);
        out.extend_from_slice(&sig);
        debug_assert_eq!(out.len(), frame.unsigned_part().len() + SIGNATURE_LEN);
        true
    }
}

#[cfg(test)]
mod tests;
