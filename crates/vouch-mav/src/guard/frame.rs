//! Just enough MAVLink framing for a forwarding proxy: find frame boundaries in a datagram or a
//! byte stream, read the header fields routing and signing need, and compute the X.25 checksum.
//!
//! The guard never re-encodes a frame: everything here works on byte ranges of what was received.
//! Full decoding (fields, CRC_EXTRA per message) belongs to the monitor's codec; this module only
//! needs the lengths, so it works for message ids no dialect knows.

use crate::codec::crc::X25;
use crate::codec::frame::header_ids;

// The wire constants are the codec's: one definition of the format for both readers.
pub use crate::codec::frame::{
    INCOMPAT_SIGNED as IFLAG_SIGNED, MAGIC_V1, MAGIC_V2, SIGNATURE_LEN, V1_HEADER_LEN,
    V2_HEADER_LEN,
};

/// Total length of the frame starting at `buf[0]`, if the header is complete enough to tell.
/// `None` means "not a frame start" (wrong magic) or "need more bytes" (see [`frame_len_hint`]).
pub fn frame_len(buf: &[u8]) -> Option<usize> {
    match *buf.first()? {
        MAGIC_V1 => Some(V1_HEADER_LEN + *buf.get(1)? as usize + 2),
        MAGIC_V2 => {
            let payload = *buf.get(1)? as usize;
            let signed = *buf.get(2)? & IFLAG_SIGNED != 0;
            Some(V2_HEADER_LEN + payload + 2 + if signed { SIGNATURE_LEN } else { 0 })
        }
        _ => None,
    }
}

/// A view of one complete frame (the slice is exactly the frame's bytes).
#[derive(Clone, Copy, Debug)]
pub struct FrameRef<'a> {
    pub bytes: &'a [u8],
}

impl<'a> FrameRef<'a> {
    /// Wraps `bytes` if they hold exactly one complete frame (by length; the CRC is not checked).
    pub fn new(bytes: &'a [u8]) -> Option<Self> {
        (frame_len(bytes)? == bytes.len()).then_some(FrameRef { bytes })
    }
    pub fn is_v2(&self) -> bool {
        self.bytes[0] == MAGIC_V2
    }
    pub fn header_len(&self) -> usize {
        if self.is_v2() {
            V2_HEADER_LEN
        } else {
            V1_HEADER_LEN
        }
    }
    pub fn payload_len(&self) -> usize {
        self.bytes[1] as usize
    }
    pub fn incompat_flags(&self) -> u8 {
        if self.is_v2() {
            self.bytes[2]
        } else {
            0
        }
    }
    pub fn is_signed(&self) -> bool {
        self.incompat_flags() & IFLAG_SIGNED != 0
    }
    // `new` checked the length, so the whole header is present for the codec's reader.
    pub fn seq(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).0
    }
    pub fn sysid(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).1
    }
    pub fn compid(&self) -> u8 {
        header_ids(self.bytes, self.is_v2()).2
    }
    pub fn msgid(&self) -> u32 {
        header_ids(self.bytes, self.is_v2()).3
    }
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
    /// The frame without its signature block (what the signature covers).
    pub fn unsigned_part(&self) -> &'a [u8] {
        &self.bytes[..self.header_len() + self.payload_len() + 2]
    }
    /// The 13-byte signature block, when the frame is signed.
    pub fn signature_block(&self) -> Option<&'a [u8]> {
        self.is_signed().then(|| &self.bytes[self.bytes.len() - SIGNATURE_LEN..])
    }
}

/// One piece of a received datagram or stream: a complete frame or bytes that are not one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Piece {
    Frame(usize, usize),
    Garbage(usize, usize),
}

/// Splits a UDP datagram into frames and garbage by length only. A datagram is self-contained in
/// MAVLink over UDP, so a truncated frame at its end is garbage, not something to wait for.
pub fn split_datagram(buf: &[u8], mut out: impl FnMut(Piece)) {
    split_datagram_resync(buf, |p| {
        out(p);
        true
    });
}

/// Splits a UDP datagram, letting the caller reject a length-cut candidate: `out` returns `false`
/// for a `Piece::Frame` that is not a frame (bad checksum, …). The scan then resumes at the byte
/// after the rejected candidate's start marker, not after its claimed length, so a corrupt frame
/// cannot swallow the frames behind it; the rejected bytes are reported again, as garbage or
/// inside later pieces. Garbage pieces cover exactly the bytes of no accepted frame; the return
/// value of `out` for them is ignored.
pub fn split_datagram_resync(buf: &[u8], mut out: impl FnMut(Piece) -> bool) {
    let mut i = 0;
    let mut junk_start: Option<usize> = None;
    while i < buf.len() {
        if let Some(n) = frame_len(&buf[i..]).filter(|&n| i + n <= buf.len()) {
            // Garbage before a candidate is reported first so pieces come out in buffer order;
            // if the candidate is then rejected, its start simply extends the next garbage run.
            let pending = junk_start.take();
            if let Some(s) = pending {
                out(Piece::Garbage(s, i));
            }
            if out(Piece::Frame(i, i + n)) {
                i += n;
                continue;
            }
        }
        junk_start.get_or_insert(i);
        i += 1;
    }
    if let Some(s) = junk_start {
        out(Piece::Garbage(s, buf.len()));
    }
}

/// Reassembles frames from a byte stream (TCP, serial) where reads cut frames anywhere.
/// Bounded: holds at most one partial frame candidate (≤ 280 bytes) between reads.
#[derive(Default)]
pub struct StreamSplitter {
    pending: Vec<u8>,
}

impl StreamSplitter {
    /// Appends `data` and emits every complete frame or garbage run now available, as slices of
    /// an internal buffer (valid during the callback). Frames are cut by length only.
    pub fn push(&mut self, data: &[u8], mut out: impl FnMut(&[u8], bool)) {
        self.push_resync(data, |b, is_frame| {
            out(b, is_frame);
            true
        });
    }

    /// Like [`push`](Self::push), but `out` may reject a frame candidate (returns `false`, e.g.
    /// bad checksum): the scan then resumes at the byte after its start marker, as in
    /// [`split_datagram_resync`], and the rejected bytes come out again as garbage or inside
    /// later pieces.
    pub fn push_resync(&mut self, data: &[u8], mut out: impl FnMut(&[u8], bool) -> bool) {
        self.pending.extend_from_slice(data);
        let buf = &self.pending;
        let mut i = 0;
        let mut junk_start: Option<usize> = None;
        while i < buf.len() {
            let b = buf[i];
            if b != MAGIC_V1 && b != MAGIC_V2 {
                junk_start.get_or_insert(i);
                i += 1;
                continue;
            }
            match frame_len(&buf[i..]) {
                Some(n) if i + n <= buf.len() => {
                    if let Some(s) = junk_start.take() {
                        out(&buf[s..i], false);
                    }
                    if out(&buf[i..i + n], true) {
                        i += n;
                    } else {
                        junk_start = Some(i);
                        i += 1;
                    }
                }
                // incomplete frame at the end: keep it for the next read
                _ => break,
            }
        }
        if let Some(s) = junk_start {
            out(&buf[s..i], false);
        }
        self.pending.drain(..i);
    }
}

/// CRC-16/MCRF4XX ("X.25") accumulation step of MAVLink; the codec's `X25` does the work, this
/// is the register-as-`u16` form the guard's CRC_EXTRA recovery needs.
#[inline]
pub fn crc_accumulate(crc: u16, byte: u8) -> u16 {
    let mut c = X25::resume(crc);
    c.push(byte);
    c.get()
}

/// X.25 checksum of `data` starting from 0xFFFF.
pub fn crc_of(data: &[u8]) -> u16 {
    let mut c = X25::new();
    c.update(data);
    c.get()
}

/// Recovers the CRC_EXTRA byte a valid frame was sealed with. For a fixed running CRC the final
/// accumulation step is injective in the added byte (its high output byte is `t ^ (t >> 5)` of a
/// bijective function of that byte), so at most one candidate matches. This lets the guard
/// rewrite a header flag (signing toward the vehicle) for message ids no dialect knows.
pub fn recover_crc_extra(frame: &FrameRef<'_>) -> Option<u8> {
    let running = crc_of(frame.crc_covered());
    let want = frame.crc();
    (0..=255u8).find(|&e| crc_accumulate(running, e) == want)
}

#[cfg(test)]
mod tests {
    use super::*;

    // MISSION_COUNT{count=100} as MAVLink 2 from 255/230, seq 0, per PROTOCOL_FACTS (16 bytes,
    // 4-byte payload); the CRC bytes are computed here from the published algorithm + CRC_EXTRA 221.
    fn mission_count_frame() -> Vec<u8> {
        let mut f = vec![0xFD, 4, 0, 0, 0, 255, 230, 44, 0, 0, 100, 0, 1, 1];
        let mut crc = crc_of(&f[1..]);
        crc = crc_accumulate(crc, 221);
        f.extend_from_slice(&crc.to_le_bytes());
        f
    }

    #[test]
    fn crc_check_value_matches_mcrf4xx() {
        // Standard check value of CRC-16/MCRF4XX over "123456789".
        assert_eq!(crc_of(b"123456789"), 0x6F91);
    }

    #[test]
    fn header_fields_and_extra_recovery() {
        let f = mission_count_frame();
        assert_eq!(f.len(), 16);
        let fr = FrameRef::new(&f).unwrap();
        assert_eq!((fr.sysid(), fr.compid(), fr.msgid()), (255, 230, 44));
        assert_eq!(fr.payload(), &[100, 0, 1, 1]);
        assert_eq!(recover_crc_extra(&fr), Some(221));
    }

    #[test]
    fn datagram_with_junk_and_two_frames() {
        let f = mission_count_frame();
        let mut d = vec![1, 2, 3];
        d.extend_from_slice(&f);
        d.extend_from_slice(&f);
        d.extend_from_slice(&f[..5]);
        let mut pieces = vec![];
        split_datagram(&d, |p| pieces.push(p));
        assert_eq!(
            pieces,
            vec![
                Piece::Garbage(0, 3),
                Piece::Frame(3, 19),
                Piece::Frame(19, 35),
                Piece::Garbage(35, 40)
            ]
        );
    }

    #[test]
    fn stream_splitter_reassembles_across_reads() {
        let f = mission_count_frame();
        let mut all = vec![0x00];
        all.extend_from_slice(&f);
        all.extend_from_slice(&f);
        let mut sp = StreamSplitter::default();
        let mut frames = 0;
        let mut junk = 0;
        for chunk in all.chunks(3) {
            sp.push(chunk, |b, is_frame| {
                if is_frame {
                    assert_eq!(b, &f[..]);
                    frames += 1
                } else {
                    junk += b.len()
                }
            });
        }
        assert_eq!((frames, junk), (2, 1));
    }

    /// A corrupt candidate that claims the next frame's bytes is rejected by the caller; both
    /// splitters then find the frame behind it (the stream one whatever the read size).
    #[test]
    fn rejected_candidate_does_not_swallow_the_next_frame() {
        let f = mission_count_frame();
        let mut bad = f.clone();
        bad[1] = 4 + 16; // claims 10 + 20 + 2 = 32 bytes: itself and the next frame
        let mut d = bad.clone();
        d.extend_from_slice(&f);
        let crc_ok = |b: &[u8]| {
            FrameRef::new(b)
                .is_some_and(|fr| crc_accumulate(crc_of(fr.crc_covered()), 221) == fr.crc())
        };
        let mut frames = vec![];
        split_datagram_resync(&d, |p| match p {
            Piece::Frame(a, b) => {
                let ok = crc_ok(&d[a..b]);
                if ok {
                    frames.push((a, b));
                }
                ok
            }
            Piece::Garbage(..) => true,
        });
        assert_eq!(frames, vec![(16, 32)]);
        for read in [1, 3, 7, 32] {
            let mut sp = StreamSplitter::default();
            let (mut got, mut junk) = (vec![], 0);
            for chunk in d.chunks(read) {
                sp.push_resync(chunk, |b, is_frame| {
                    if !is_frame {
                        junk += b.len();
                        return true;
                    }
                    let ok = crc_ok(b);
                    if ok {
                        got.push(b.to_vec());
                    }
                    ok
                });
            }
            assert_eq!((got, junk), (vec![f.clone()], 16), "reads of {read}");
        }
    }
}
