//! What one receive batch sends, gathered per destination connection and sent at the end of the
//! batch: frames for one UDP destination leave in datagrams of up to [`DATAGRAM_LIMIT`] bytes
//! (a received datagram is never split), bytes for one stream in one write. At low rates a batch
//! is one datagram, so nothing waits; under load this divides the system calls per frame. Each
//! reader thread has its own outbox; the order of the bytes per destination is kept.

use std::cell::RefCell;

use super::link::Peer;
use super::sys::udp_batch;

/// Largest datagram the router makes by putting frames together (fits an Ethernet frame with
/// IPv4 or IPv6 and UDP headers, and most tunnels). A larger received datagram leaves as is.
pub const DATAGRAM_LIMIT: usize = 1400;
/// Largest single write to a stream.
const STREAM_LIMIT: usize = 16 * 1024;

struct Slot {
    ep: usize,
    peer: Peer,
    datagram: bool,
    buf: Vec<u8>,
    /// End offsets of the pieces (datagrams or writes) in `buf`.
    ends: Vec<usize>,
}

#[derive(Default)]
pub(super) struct Outbox {
    slots: Vec<Slot>,
}

thread_local! {
    static OUTBOX: RefCell<Outbox> = RefCell::new(Outbox::default());
}

/// Runs `f` with this thread's outbox.
pub(super) fn with<R>(f: impl FnOnce(&mut Outbox) -> R) -> R {
    OUTBOX.with(|o| f(&mut o.borrow_mut()))
}

impl Outbox {
    /// Queues `bytes` for connection `peer` of endpoint `ep` (`datagram`: a UDP endpoint).
    pub(super) fn push(&mut self, ep: usize, peer: Peer, datagram: bool, bytes: &[u8]) {
        let i = match self.slots.iter().position(|s| s.ep == ep && s.peer == peer) {
            Some(i) => i,
            None => match self.slots.iter().position(|s| s.buf.is_empty()) {
                Some(i) => {
                    let s = &mut self.slots[i];
                    (s.ep, s.peer, s.datagram) = (ep, peer, datagram);
                    i
                }
                None => {
                    self.slots.push(Slot { ep, peer, datagram, buf: vec![], ends: vec![] });
                    self.slots.len() - 1
                }
            },
        };
        let s = &mut self.slots[i];
        let limit = if s.datagram { DATAGRAM_LIMIT } else { STREAM_LIMIT };
        let start = s.ends.last().copied().unwrap_or(0);
        if s.buf.len() > start && s.buf.len() - start + bytes.len() > limit {
            s.ends.push(s.buf.len());
        }
        s.buf.extend_from_slice(bytes);
    }

    /// Whether nothing is queued.
    pub(super) fn is_empty(&self) -> bool {
        self.slots.iter().all(|s| s.buf.is_empty())
    }

    /// Sends everything queued through `send(ep, peer, bytes) -> sent`, UDP sends batched in
    /// `sendmmsg` calls, and empties the outbox (keeping its buffers).
    pub(super) fn flush(&mut self, mut send: impl FnMut(usize, Peer, &[u8]) -> bool) {
        if self.is_empty() {
            return;
        }
        // datagrams first (one sendmmsg), then streams: a slow stream write never delays them
        udp_batch::begin();
        for s in self.slots.iter_mut().filter(|s| s.datagram) {
            s.send_all(&mut send);
        }
        udp_batch::flush();
        for s in self.slots.iter_mut().filter(|s| !s.datagram) {
            s.send_all(&mut send);
        }
    }
}

impl Slot {
    /// Sends this destination's pieces and empties it (keeping its buffer).
    fn send_all(&mut self, send: &mut impl FnMut(usize, Peer, &[u8]) -> bool) {
        if self.buf.is_empty() {
            return;
        }
        if self.ends.last() != Some(&self.buf.len()) {
            self.ends.push(self.buf.len());
        }
        let mut from = 0;
        for &end in &self.ends {
            send(self.ep, self.peer, &self.buf[from..end]);
            from = end;
        }
        self.buf.clear();
        self.ends.clear();
        if self.buf.capacity() > 4 * STREAM_LIMIT {
            self.buf.shrink_to(STREAM_LIMIT);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_for_one_destination_leave_together_within_the_limit() {
        let mut o = Outbox::default();
        let a = Peer::Fixed;
        let b = Peer::Stream(7);
        o.push(0, a, true, &[1; 600]);
        o.push(1, b, false, &[9; 10]);
        o.push(0, a, true, &[2; 600]);
        o.push(0, a, true, &[3; 600]); // would pass 1400: a new datagram
        o.push(0, a, true, &[4; 2000]); // larger than the limit alone: its own datagram
        o.push(1, b, false, &[8; 10]);
        let mut sent = vec![];
        o.flush(|ep, peer, bytes| {
            sent.push((ep, peer, bytes.len(), bytes[0]));
            true
        });
        assert_eq!(
            sent,
            vec![(0, a, 1200, 1), (0, a, 600, 3), (0, a, 2000, 4), (1, b, 20, 9)],
            "per destination in order, datagrams before streams; datagrams of at most 1400 bytes \
             unless received larger"
        );
        assert!(o.is_empty());
        let mut n = 0;
        o.flush(|_, _, _| {
            n += 1;
            true
        });
        assert_eq!(n, 0, "an empty outbox sends nothing");
    }
}
