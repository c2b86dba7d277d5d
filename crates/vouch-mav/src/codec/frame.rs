//! Frame recognition: finds complete MAVLink 1/2 frames in a byte buffer without copying.
//!
//! The splitter returns the exact byte range of each frame so a proxy can forward it unchanged
//! (signatures and zero truncation stay intact). Garbage, bad checksums, truncated frames and
//! unknown message ids are counted in [`CodecStats`] instead of failing.

use std::ops::Range;

use super::crc::frame_crc;
use crate::dialect::{Dialect, MessageDef, MsgIndex};

pub const MAGIC_V1: u8 = 0xFE;
pub const MAGIC_V2: u8 = 0xFD;
/// Length of the signature block (link id, 6-byte timestamp, 6-byte signature).
pub const SIGNATURE_LEN: usize = 13;
/// `incompat_flags` bit meaning "a signature block follows the checksum".
pub const INCOMPAT_SIGNED: u8 = 0x01;
/// Header length of a MAVLink 1 frame including the magic byte.
pub const V1_HEADER_LEN: usize = 6;
/// Header length of a MAVLink 2 frame including the magic byte.
pub const V2_HEADER_LEN: usize = 10;

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Version {
    V1,
    V2,
}

/// A complete frame with a valid checksum (or an unknown id, see [`Frame::msg`]) borrowed from the input.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// The whole frame as received: header, payload, checksum and signature if any.
    pub bytes: &'a [u8],
    pub version: Version,
    pub incompat_flags: u8,
    pub compat_flags: u8,
    pub seq: u8,
    pub sysid: u8,
    pub compid: u8,
    pub msgid: u32,
    /// Payload as carried (possibly zero-truncated); readers pad with zeros.
    pub payload: &'a [u8],
    /// Dialect index of the message, `None` for an id the dialect does not know (CRC unchecked).
    pub msg: Option<MsgIndex>,
}

impl Frame<'_> {
    pub fn is_signed(&self) -> bool {
        self.version == Version::V2 && self.incompat_flags & INCOMPAT_SIGNED != 0
    }

    /// The 13 signature bytes (link id, timestamp, signature) of a signed frame.
    pub fn signature(&self) -> Option<&[u8]> {
        if self.is_signed() {
            Some(&self.bytes[self.bytes.len() - SIGNATURE_LEN..])
        } else {
            None
        }
    }
}

/// Counters of everything that was not a good frame.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct CodecStats {
    pub frames: u64,
    pub frames_v1: u64,
    pub frames_v2: u64,
    pub signed: u64,
    /// Bytes skipped while looking for a frame start.
    pub garbage_bytes: u64,
    pub bad_crc: u64,
    /// Frames of a known message with a length above its definition.
    pub bad_length: u64,
    pub unknown_id: u64,
    /// Frames with an incompatibility flag we do not understand (must be dropped).
    pub bad_incompat: u64,
    /// Frames cut off by the end of the input.
    pub truncated: u64,
}

impl CodecStats {
    pub fn errors(&self) -> u64 {
        self.bad_crc + self.bad_length + self.unknown_id + self.bad_incompat + self.truncated
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

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InvalidKind {
    NotMagic,
    BadCrc,
    BadLength,
    BadIncompat,
    UnknownId,
}

/// Header fields of a frame, once enough bytes are present.
struct Header {
    version: Version,
    len: usize,
    header_len: usize,
    incompat: u8,
    compat: u8,
    seq: u8,
    sysid: u8,
    compid: u8,
    msgid: u32,
}

/// Routing fields of a header: `(seq, sysid, compid, msgid)`. `buf` holds at least the whole
/// header of its version (MAVLink 2 when `v2`). The one place that knows where they sit; the
/// guard's dialect-free `FrameRef` reads them here too.
#[inline]
pub(crate) fn header_ids(buf: &[u8], v2: bool) -> (u8, u8, u8, u32) {
    if v2 {
        let msgid = u32::from(buf[7]) | u32::from(buf[8]) << 8 | u32::from(buf[9]) << 16;
        (buf[4], buf[5], buf[6], msgid)
    } else {
        (buf[2], buf[3], buf[4], u32::from(buf[5]))
    }
}

fn header(buf: &[u8]) -> Option<Option<Header>> {
    match buf.first() {
        Some(&MAGIC_V1) => {
            if buf.len() < V1_HEADER_LEN {
                return Some(None);
            }
            let (seq, sysid, compid, msgid) = header_ids(buf, false);
            Some(Some(Header {
                version: Version::V1,
                len: usize::from(buf[1]),
                header_len: V1_HEADER_LEN,
                incompat: 0,
                compat: 0,
                seq,
                sysid,
                compid,
                msgid,
            }))
        }
        Some(&MAGIC_V2) => {
            if buf.len() < V2_HEADER_LEN {
                return Some(None);
            }
            let (seq, sysid, compid, msgid) = header_ids(buf, true);
            Some(Some(Header {
                version: Version::V2,
                len: usize::from(buf[1]),
                header_len: V2_HEADER_LEN,
                incompat: buf[2],
                compat: buf[3],
                seq,
                sysid,
                compid,
                msgid,
            }))
        }
        _ => None,
    }
}

/// Reads one frame at `buf[0]`. `unknown_ok` tells whether a frame with an id unknown to the
/// dialect (whose CRC cannot be checked) is accepted; callers decide from context (e.g. the next
/// byte being a magic byte or the end of a datagram).
pub fn parse_frame<'a>(buf: &'a [u8], dialect: &Dialect, unknown_ok: bool) -> Parse<'a> {
    let h = match header(buf) {
        None => return Parse::Invalid(InvalidKind::NotMagic),
        Some(None) => return Parse::Incomplete,
        Some(Some(h)) => h,
    };
    if h.incompat & !INCOMPAT_SIGNED != 0 {
        return Parse::Invalid(InvalidKind::BadIncompat);
    }
    let sig = if h.incompat & INCOMPAT_SIGNED != 0 { SIGNATURE_LEN } else { 0 };
    let total = h.header_len + h.len + 2 + sig;
    let msg = dialect.index_of_id(h.msgid);
    if let Some(idx) = msg {
        let def: &MessageDef = dialect.message(idx);
        let max =
            if h.version == Version::V1 { def.base_len.max(def.max_len) } else { def.max_len };
        if h.len > usize::from(max) {
            return Parse::Invalid(InvalidKind::BadLength);
        }
    }
    if buf.len() < total {
        return Parse::Incomplete;
    }
    let body_end = h.header_len + h.len;
    let payload = &buf[h.header_len..body_end];
    match msg {
        Some(idx) => {
            let def = dialect.message(idx);
            let got = u16::from(buf[body_end]) | u16::from(buf[body_end + 1]) << 8;
            if frame_crc(&buf[1..body_end], def.crc_extra) != got {
                return Parse::Invalid(InvalidKind::BadCrc);
            }
        }
        None if !unknown_ok => return Parse::Invalid(InvalidKind::UnknownId),
        None => {}
    }
    Parse::Frame(Frame {
        bytes: &buf[..total],
        version: h.version,
        incompat_flags: h.incompat,
        compat_flags: h.compat,
        seq: h.seq,
        sysid: h.sysid,
        compid: h.compid,
        msgid: h.msgid,
        payload,
        msg,
    })
}

/// Incremental frame finder over a growing byte buffer (stream or datagram).
///
/// Usage: append received bytes to a buffer, call [`FrameSplitter::next`] with a cursor until it
/// returns `None`, forward each returned range byte for byte, then drain `buf[..cursor]`.
#[derive(Debug, Default, Clone)]
pub struct FrameSplitter {
    pub stats: CodecStats,
}

impl FrameSplitter {
    pub fn new() -> Self {
        Self::default()
    }

    /// Finds the next complete frame at or after `*pos`. Returns its absolute byte range and the
    /// frame; advances `*pos` past it. Returns `None` when more bytes are needed (`*pos` then
    /// points at the start of the incomplete frame or at the end of the buffer).
    ///
    /// `end_of_input` marks the buffer as complete (a whole datagram, or the end of a file): an
    /// incomplete frame then counts as truncated and its bytes are skipped.
    pub fn next<'a>(
        &mut self,
        buf: &'a [u8],
        pos: &mut usize,
        dialect: &Dialect,
        end_of_input: bool,
    ) -> Option<(Range<usize>, Frame<'a>)> {
        while *pos < buf.len() {
            let rest = &buf[*pos..];
            // A frame with an unknown id is believed only when it is followed by another frame
            // start or ends the input: otherwise a stray magic byte could swallow good frames.
            let unknown_ok = |len: usize| -> bool {
                match rest.get(len) {
                    None => true,
                    Some(&b) => b == MAGIC_V1 || b == MAGIC_V2,
                }
            };
            match parse_frame(rest, dialect, true) {
                Parse::Frame(f) => {
                    let len = f.bytes.len();
                    if f.msg.is_none() && !unknown_ok(len) {
                        self.skip(InvalidKind::UnknownId, pos);
                        continue;
                    }
                    let start = *pos;
                    *pos += len;
                    self.count(&f);
                    return Some((start..start + len, f));
                }
                Parse::Invalid(kind) => self.skip(kind, pos),
                Parse::Incomplete => {
                    if end_of_input {
                        self.stats.truncated += 1;
                        self.stats.garbage_bytes += (buf.len() - *pos) as u64;
                        *pos = buf.len();
                    }
                    return None;
                }
            }
        }
        None
    }

    fn skip(&mut self, kind: InvalidKind, pos: &mut usize) {
        match kind {
            InvalidKind::NotMagic => {}
            InvalidKind::BadCrc => self.stats.bad_crc += 1,
            InvalidKind::BadLength => self.stats.bad_length += 1,
            InvalidKind::BadIncompat => self.stats.bad_incompat += 1,
            InvalidKind::UnknownId => self.stats.unknown_id += 1,
        }
        self.stats.garbage_bytes += 1;
        *pos += 1;
    }

    pub(crate) fn count(&mut self, f: &Frame) {
        self.stats.frames += 1;
        match f.version {
            Version::V1 => self.stats.frames_v1 += 1,
            Version::V2 => self.stats.frames_v2 += 1,
        }
        if f.is_signed() {
            self.stats.signed += 1;
        }
        if f.msg.is_none() {
            self.stats.unknown_id += 1;
        }
    }
}
