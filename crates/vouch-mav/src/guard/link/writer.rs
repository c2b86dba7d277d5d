//! Stream writers: every TCP connection and serial port has a writer thread fed through a queue
//! bounded in bytes, so that the reader threads that route frames never wait for a stream (a
//! stalled TCP peer, a serial link slower than the traffic). When a queue is full, what does not
//! fit is dropped (a whole piece, never part of one) and the send counts as failed.
//!
//! A small piece (what a receive batch carries at low rates: a frame or a few) for a TCP
//! connection with nothing queued is written by the routing thread itself, with a send that
//! never waits: waking the writer thread for every frame costs context switches that delay the
//! delivery of the next frame to the other endpoints by more than the write. Larger pieces (the
//! batches of a busy link) go to the writer thread, whose lower priority leaves the CPU to UDP
//! delivery. What the socket does not take at once goes to the queue, behind which every later
//! piece waits, so the bytes keep their order.

use std::io::{self, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread;

use crate::guard::sys::{process, stream};

/// Most bytes waiting for one stream.
pub const MAX_QUEUED_BYTES: usize = 256 * 1024;
/// Largest piece the routing thread writes itself (one frame of any size fits).
pub const DIRECT_WRITE_LIMIT: usize = 512;
/// Nice value of writer threads, relative to the routing threads.
const WRITER_NICE: i32 = 5;

pub(super) struct Writer {
    tx: SyncSender<Vec<u8>>,
    /// Bytes queued or being written by the thread: a direct write is allowed only at zero.
    pending: Arc<AtomicUsize>,
    /// Held by whoever writes to the stream (the thread, or a direct write), so that writes
    /// never interleave.
    gate: Arc<Mutex<()>>,
    /// The connection for direct writes (TCP only).
    direct: Option<TcpStream>,
}

impl Writer {
    /// Starts a thread writing what [`Writer::send`] queues to `w`; `on_error` runs once when a
    /// write fails (the thread then ends). The thread also ends when the writer is dropped.
    /// `direct`: the same connection, for direct writes when nothing is queued.
    pub(super) fn spawn<W: Write + Send + 'static>(
        name: String,
        mut w: W,
        direct: Option<TcpStream>,
        on_error: impl FnOnce() + Send + 'static,
    ) -> io::Result<Writer> {
        let (tx, rx) = sync_channel::<Vec<u8>>(1024);
        let pending = Arc::new(AtomicUsize::new(0));
        let gate = Arc::new(Mutex::new(()));
        let (p, g) = (pending.clone(), gate.clone());
        thread::Builder::new().name(name).spawn(move || {
            // stream writes yield to the threads that route (and so to UDP delivery)
            process::lower_current_thread_priority(WRITER_NICE);
            for piece in rx {
                let written = {
                    let _held = g.lock().unwrap_or_else(|e| e.into_inner());
                    w.write_all(&piece).is_ok()
                };
                p.fetch_sub(piece.len(), Ordering::Release);
                if !written {
                    on_error();
                    return;
                }
            }
        })?;
        Ok(Writer { tx, pending, gate, direct })
    }

    /// Writes a small piece now when the stream is idle and takes it, else queues what is left;
    /// `false` when the queue is full or the writer has ended.
    pub(super) fn send(&self, bytes: &[u8]) -> bool {
        let Some(conn) = self.direct.as_ref().filter(|_| bytes.len() <= DIRECT_WRITE_LIMIT) else {
            return self.enqueue(bytes);
        };
        let Ok(_held) = self.gate.try_lock() else { return self.enqueue(bytes) };
        if self.pending.load(Ordering::Acquire) != 0 {
            return self.enqueue(bytes);
        }
        match stream::send_now(conn, bytes) {
            Ok(n) if n == bytes.len() => true,
            // the rest is queued while the gate is held: nothing can be written before it
            Ok(n) => self.enqueue(&bytes[n..]),
            // would block, or failed: the thread's write reports a failure and closes
            Err(_) => self.enqueue(bytes),
        }
    }

    /// Queues `bytes` for the thread.
    fn enqueue(&self, bytes: &[u8]) -> bool {
        let before = self.pending.fetch_add(bytes.len(), Ordering::AcqRel);
        if before + bytes.len() > MAX_QUEUED_BYTES || self.tx.try_send(bytes.to_vec()).is_err() {
            self.pending.fetch_sub(bytes.len(), Ordering::AcqRel);
            return false;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Condvar;

    /// A sink that takes nothing until released.
    struct Stalled(Arc<(Mutex<bool>, Condvar)>, Arc<Mutex<Vec<u8>>>);
    impl Write for Stalled {
        fn write(&mut self, b: &[u8]) -> io::Result<usize> {
            let (m, c) = &*self.0;
            let mut open = m.lock().unwrap();
            while !*open {
                open = c.wait(open).unwrap();
            }
            self.1.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_stalled_stream_fills_its_queue_and_drops_whole_pieces() {
        let gate = Arc::new((Mutex::new(false), Condvar::new()));
        let got = Arc::new(Mutex::new(vec![]));
        let w = Writer::spawn("t".into(), Stalled(gate.clone(), got.clone()), None, || {}).unwrap();
        let piece = vec![7u8; 1000];
        let sent = (0..400).filter(|_| w.send(&piece)).count();
        // the one piece the thread holds, plus what fits in the queue
        let fit = MAX_QUEUED_BYTES / piece.len();
        assert!((fit..=fit + 1).contains(&sent), "{sent} of 400 pieces queued, {fit} fit");
        *gate.0.lock().unwrap() = true;
        gate.1.notify_all();
        drop(w);
        for _ in 0..100 {
            if got.lock().unwrap().len() == sent * 1000 {
                return;
            }
            thread::sleep(std::time::Duration::from_millis(10));
        }
        panic!("wrote {} of {} bytes", got.lock().unwrap().len(), sent * 1000);
    }

    #[test]
    fn direct_and_queued_writes_keep_order_and_whole_pieces_on_a_slow_tcp_peer() {
        use std::io::Read;
        use std::net::TcpListener;
        use std::time::{Duration, Instant};
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let sender = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (mut receiver, _) = listener.accept().unwrap();
        let direct = Some(sender.try_clone().unwrap());
        let w = Writer::spawn("t".into(), sender, direct, || {}).unwrap();
        let reading = thread::spawn(move || {
            // a peer that starts late and then reads slowly: the socket fills and drains while
            // pieces wait in the queue, so that a direct write could overtake them
            thread::sleep(Duration::from_millis(100));
            let (mut all, mut chunk) = (vec![], [0u8; 16 * 1024]);
            loop {
                match receiver.read(&mut chunk).unwrap() {
                    0 => return all,
                    n => all.extend_from_slice(&chunk[..n]),
                }
                thread::sleep(Duration::from_micros(200));
            }
        });
        const PIECE: usize = 100;
        let mut accepted = vec![];
        let until = Instant::now() + Duration::from_millis(600);
        for i in (0..u32::MAX).take_while(|_| Instant::now() < until) {
            let mut piece = [0u8; PIECE];
            piece[..4].copy_from_slice(&i.to_le_bytes());
            piece[PIECE - 4..].copy_from_slice(&i.to_le_bytes());
            if w.send(&piece) {
                accepted.push(i);
            }
        }
        drop(w);
        let all = reading.join().unwrap();
        assert_eq!(all.len() % PIECE, 0, "only whole pieces arrive");
        let got: Vec<u32> = all
            .chunks(PIECE)
            .map(|c| {
                let (head, tail) = (&c[..4], &c[PIECE - 4..]);
                assert_eq!(head, tail, "a piece arrived mixed with another");
                u32::from_le_bytes(head.try_into().unwrap())
            })
            .collect();
        assert_eq!(got, accepted, "every accepted piece arrives once, in order");
    }
}
