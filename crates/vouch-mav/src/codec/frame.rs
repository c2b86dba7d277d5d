//! The one reader of MAVLink frame headers: wire constants, the length of a frame from its first
//! bytes ([`frame_len`]), a dialect-free view of a length-cut frame ([`FrameRef`]), and the
//! dialect-checked [`Frame`] ([`parse_frame`]: incompatibility flags, length, CRC with CRC_EXTRA).
//!
//! Everything borrows the input: a frame is always `&input[range]`, so a proxy can forward it
//! unchanged (signatures and zero truncation stay intact). Splitting buffers into frames is
//! [`split`](super::split)'s.

use crate::crc::{X25, frame_crc};
use crate::dialect::{Dialect, MsgIndex};

/// Start marker of a MAVLink 1 frame.
pub const MAGIC_V1: u8 = 0xFE;
/// Start marker of a MAVLink 2 frame.
pub const MAGIC_V2: u8 = 0xFD;
/// Length of the signature block (link id, 6-byte timestamp, 6-byte signature).
pub const SIGNATURE_LEN: usize = 13;
/// `incompat_flags` bit meaning "a signature block follows the checksum".
pub const INCOMPAT_SIGNED: u8 = 0x01;
/// Header length of a MAVLink 1 frame including the magic byte.
pub const V1_HEADER_LEN: usize = 6;
/// Header length of a MAVLink 2 frame including the magic byte.
pub const V2_HEADER_LEN: usize = 10;
/// Longest possible frame (MAVLink 2, 255-byte payload, signed).
pub const MAX_FRAME_LEN: usize = V2_HEADER_LEN + 255 + 2 + SIGNATURE_LEN;

/// MAVLink protocol version of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Version {
    /// Magic 0xFE, 6-byte header, 8-bit message ids.
    V1,
    /// Magic 0xFD, 10-byte header, 24-bit message ids, optional signature.
    V2,
}

/// Whether `b` starts a frame.
#[inline]
pub fn is_magic(b: u8) -> bool {
    b == MAGIC_V1 || b == MAGIC_V2
}

/// What the first bytes of a buffer say about a frame there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// `buf[0]` is no start marker.
    NotMagic,
    /// A start marker, but the buffer ends before the frame's length is known or reached.
    Incomplete,
    /// A frame candidate of this many bytes is complete in the buffer.
    Complete(usize),
}

/// Total length of the frame starting at `buf[0]` as its header claims, if the header is there.
/// `None` means "not a frame start" (wrong magic) or "fewer than 3 bytes".
#[inline]
pub fn frame_len(buf: &[u8]) -> Option<usize> {
    match *buf.first()? {
        MAGIC_V1 => Some(V1_HEADER_LEN + usize::from(*buf.get(1)?) + 2),
        MAGIC_V2 => {
            let payload = usize::from(*buf.get(1)?);
            let signed = *buf.get(2)? & INCOMPAT_SIGNED != 0;
            Some(V2_HEADER_LEN + payload + 2 + if signed { SIGNATURE_LEN } else { 0 })
        }
        _ => None,
    }
}

/// Cuts a frame candidate at `buf[0]` by its length field alone.
#[inline]
pub fn cut(buf: &[u8]) -> Cut {
    match buf.first() {
        Some(&b) if is_magic(b) => match frame_len(buf) {
            Some(n) if n <= buf.len() => Cut::Complete(n),
            _ => Cut::Incomplete,
        },
        Some(_) => Cut::NotMagic,
        None => Cut::Incomplete,
    }
}

/// Routing fields of a header: `(seq, sysid, compid, msgid)`. `buf` holds at least the whole
/// header of its version (MAVLink 2 when `v2`): the one place that knows where they sit.
#[inline]
fn header_ids(buf: &[u8], v2: bool) -> (u8, u8, u8, u32) {
    if v2 {
        let msgid = u32::from(buf[7]) | u32::from(buf[8]) << 8 | u32::from(buf[9]) << 16;
        (buf[4], buf[5], buf[6], msgid)
    } else {
        (buf[2], buf[3], buf[4], u32::from(buf[5]))
    }
}

/// A complete frame candidate cut by its length (the checksum is not checked): what a relay
/// needs, for any message id, without a dialect.
#[derive(Clone, Copy, Debug)]
pub struct FrameRef<'a> {
    /// Exactly the frame's bytes, signature included.
    pub bytes: &'a [u8],
}

impl<'a> FrameRef<'a> {
    /// Wraps `bytes` if they hold exactly one complete frame (by length; the CRC is not checked).
    pub fn new(bytes: &'a [u8]) -> Option<Self> {
        (frame_len(bytes)? == bytes.len()).then_some(FrameRef { bytes })
    }
    /// MAVLink 2 (else 1).
    pub fn is_v2(&self) -> bool {
        self.bytes[0] == MAGIC_V2
    }
    /// The protocol version.
    pub fn version(&self) -> Version {
        if self.is_v2() { Version::V2 } else { Version::V1 }
    }
    /// Header length including the magic byte.
    pub fn header_len(&self) -> usize {
        if self.is_v2() { V2_HEADER_LEN } else { V1_HEADER_LEN }
    }
    /// Payload length as carried (possibly zero-truncated).
    pub fn payload_len(&self) -> usize {
        usize::from(self.bytes[1])
    }
    /// Incompatibility flags (0 for MAVLink 1).
    pub fn incompat_flags(&self) -> u8 {
        if self.is_v2() { self.bytes[2] } else { 0 }
    }
    /// Compatibility flags (0 for MAVLink 1).
    pub fn compat_flags(&self) -> u8 {
        if self.is_v2() { self.bytes[3] } else { 0 }
    }
    /// Whether a signature block follows the checksum.
    pub fn is_signed(&self) -> bool {
        self.incompat_flags() & INCOMPAT_SIGNED != 0
    }
    // `new` checked the length, so the whole header is present.
    /// Sequence number.
    pub fn seq(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).0
    }
    /// Sender system id.
    pub fn sysid(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).1
    }
    /// Sender component id.
    pub fn compid(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).2
    }
    /// Message id.
    pub fn msgid(&self) -> u32 {
        header_ids(self.bytes, self.is_v2()).3
    }
    /// The payload as carried.
    pub fn payload(&self) -> &'a [u8] {
        let h = self.header_len();
        &self.bytes[h..h + self.payload_len()]
    }
    /// Everything the checksum covers before CRC_EXTRA: header after the magic, then payload.
    pub fn crc_covered(&self) -> &'a [u8] {
        &self.bytes[1..self.header_len() + self.payload_len()]
    }
    /// The checksum as sent (little-endian on the wire).
    pub fn crc(&self) -> u16 {
        let at = self.header_len() + self.payload_len();
        u16::from_le_bytes([self.bytes[at], self.bytes[at + 1]])
    }
    /// Whether the checksum holds with this CRC_EXTRA.
    pub fn crc_holds(&self, crc_extra: u8) -> bool {
        frame_crc(self.crc_covered(), crc_extra) == self.crc()
    }
    /// The frame without its signature block (what the signature covers).
    pub fn unsigned_part(&self) -> &'a [u8] {
        &self.bytes[..self.header_len() + self.payload_len() + 2]
    }
    /// The 13-byte signature block, when the frame is signed.
    pub fn signature_block(&self) -> Option<&'a [u8]> {
        self.is_signed().then(|| &self.bytes[self.bytes.len() - SIGNATURE_LEN..])
    }

    /// Recovers the CRC_EXTRA byte a valid frame was sealed with. For a fixed running CRC the
    /// final accumulation step is injective in the added byte (its high output byte is
    /// `t ^ (t >> 5)` of a bijective function of that byte), so at most one candidate matches.
    /// This lets a relay rewrite a header flag (signing) for message ids no dialect knows.
    pub fn recover_crc_extra(&self) -> Option<u8> {
        let mut running = X25::new();
        running.update(self.crc_covered());
        let want = self.crc();
        (0..=255u8).find(|&e| {
            let mut c = running.clone();
            c.push(e);
            c.get() == want
        })
    }
}

/// A complete frame whose checksum held (or whose id the dialect does not know, see
/// [`Frame::msg`]), borrowed from the input.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// The whole frame as received: header, payload, checksum and signature if any.
    pub bytes: &'a [u8],
    /// MAVLink 1 or 2.
    pub version: Version,
    /// Incompatibility flags (0 for MAVLink 1).
    pub incompat_flags: u8,
    /// Compatibility flags (0 for MAVLink 1).
    pub compat_flags: u8,
    /// Sequence number.
    pub seq: u8,
    /// Sender system id.
    pub sysid: u8,
    /// Sender component id.
    pub compid: u8,
    /// Message id.
    pub msgid: u32,
    /// Payload as carried (possibly zero-truncated); readers pad with zeros.
    pub payload: &'a [u8],
    /// Dialect index of the message, `None` for an id the dialect does not know (CRC unchecked).
    pub msg: Option<MsgIndex>,
}

impl<'a> Frame<'a> {
    fn of(f: FrameRef<'a>, msg: Option<MsgIndex>) -> Frame<'a> {
        let (seq, sysid, compid, msgid) = header_ids(f.bytes, f.is_v2());
        Frame {
            bytes: f.bytes,
            version: f.version(),
            incompat_flags: f.incompat_flags(),
            compat_flags: f.compat_flags(),
            seq,
            sysid,
            compid,
            msgid,
            payload: f.payload(),
            msg,
        }
    }

    /// The length-cut view of the same bytes.
    pub fn as_ref(&self) -> FrameRef<'a> {
        FrameRef { bytes: self.bytes }
    }

    /// Whether a signature block follows the checksum.
    pub fn is_signed(&self) -> bool {
        self.version == Version::V2 && self.incompat_flags & INCOMPAT_SIGNED != 0
    }

    /// The 13 signature bytes (link id, timestamp, signature) of a signed frame.
    pub fn signature(&self) -> Option<&[u8]> {
        self.as_ref().signature_block()
    }
}

/// Counters of everything that was not a good frame.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct CodecStats {
    /// Frames returned (good checksum, or unknown id believed by its position).
    pub frames: u64,
    /// Of which MAVLink 1.
    pub frames_v1: u64,
    /// Of which MAVLink 2.
    pub frames_v2: u64,
    /// Of which signed.
    pub signed: u64,
    /// Bytes skipped while looking for a frame start.
    pub garbage_bytes: u64,
    /// Candidates of a known message whose checksum failed.
    pub bad_crc: u64,
    /// Frames of a known message with a length above its definition.
    pub bad_length: u64,
    /// Frames of an id the dialect does not know.
    pub unknown_id: u64,
    /// Frames with an incompatibility flag we do not understand (must be dropped).
    pub bad_incompat: u64,
    /// Inputs that ended inside a frame candidate.
    pub truncated: u64,
}

impl CodecStats {
    /// Every counted problem except garbage bytes.
    pub fn errors(&self) -> u64 {
        self.bad_crc + self.bad_length + self.unknown_id + self.bad_incompat + self.truncated
    }

    /// Counts a returned frame.
    pub(crate) fn count(&mut self, f: &Frame) {
        self.frames += 1;
        match f.version {
            Version::V1 => self.frames_v1 += 1,
            Version::V2 => self.frames_v2 += 1,
        }
        if f.is_signed() {
            self.signed += 1;
        }
        if f.msg.is_none() {
            self.unknown_id += 1;
        }
    }

    /// Counts a rejected candidate.
    pub(crate) fn reject(&mut self, kind: InvalidKind) {
        match kind {
            InvalidKind::NotMagic => {}
            InvalidKind::BadCrc => self.bad_crc += 1,
            InvalidKind::BadLength => self.bad_length += 1,
            InvalidKind::BadIncompat => self.bad_incompat += 1,
            InvalidKind::UnknownId => self.unknown_id += 1,
        }
    }
}

/// Result of trying to read one frame at the start of a buffer.
#[derive(Debug)]
pub enum Parse<'a> {
    /// A frame occupies `buf[..frame.bytes.len()]`.
    Frame(Frame<'a>),
    /// `buf[0]` starts no valid frame; skip one byte (the reason is for the counters).
    Invalid(InvalidKind),
    /// `buf` starts like a frame but ends before it is complete.
    Incomplete,
}

/// Why bytes are not a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InvalidKind {
    /// No start marker.
    NotMagic,
    /// The checksum (with the message's CRC_EXTRA) does not hold.
    BadCrc,
    /// Longer than the message's definition allows.
    BadLength,
    /// An incompatibility flag this reader does not understand.
    BadIncompat,
    /// An id the dialect does not know where it cannot be believed.
    UnknownId,
}

impl InvalidKind {
    /// Short description for logs.
    pub fn as_str(self) -> &'static str {
        match self {
            InvalidKind::NotMagic => "no start marker",
            InvalidKind::BadCrc => "bad checksum",
            InvalidKind::BadLength => "length above the message's definition",
            InvalidKind::BadIncompat => "unknown incompatibility flag",
            InvalidKind::UnknownId => "unknown message id",
        }
    }
}

/// Reads one frame at `buf[0]`. `unknown_ok` tells whether a frame with an id unknown to the
/// dialect (whose CRC cannot be checked) is accepted; callers decide from context (e.g. the next
/// byte being a magic byte or the end of a datagram). Header problems (flags, length) are found
/// as soon as the header is there, before the rest of the frame arrives.
pub fn parse_frame<'a>(buf: &'a [u8], dialect: &Dialect, unknown_ok: bool) -> Parse<'a> {
    let Some(&magic) = buf.first() else { return Parse::Incomplete };
    if !is_magic(magic) {
        return Parse::Invalid(InvalidKind::NotMagic);
    }
    let v2 = magic == MAGIC_V2;
    let header_len = if v2 { V2_HEADER_LEN } else { V1_HEADER_LEN };
    if buf.len() < header_len {
        return Parse::Incomplete;
    }
    if v2 && buf[2] & !INCOMPAT_SIGNED != 0 {
        return Parse::Invalid(InvalidKind::BadIncompat);
    }
    let msg = dialect.index_of_id(header_ids(buf, v2).3);
    if let Some(def) = msg.map(|i| dialect.message(i)) {
        let max = if v2 { def.max_len } else { def.base_len.max(def.max_len) };
        if usize::from(buf[1]) > usize::from(max) {
            return Parse::Invalid(InvalidKind::BadLength);
        }
    }
    let Cut::Complete(n) = cut(buf) else { return Parse::Incomplete };
    let f = FrameRef { bytes: &buf[..n] };
    match msg {
        Some(idx) if !f.crc_holds(dialect.message(idx).crc_extra) => {
            Parse::Invalid(InvalidKind::BadCrc)
        }
        None if !unknown_ok => Parse::Invalid(InvalidKind::UnknownId),
        _ => Parse::Frame(Frame::of(f, msg)),
    }
}
