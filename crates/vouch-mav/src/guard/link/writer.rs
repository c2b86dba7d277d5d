//! Stream writers: every TCP connection and serial port has a writer thread fed through a queue
//! bounded in bytes, so that the reader threads that route frames never wait for a stream (a
//! stalled TCP peer, a serial link slower than the traffic). When a queue is full, what does not
//! fit is dropped (a whole piece, never part of one) and the send counts as failed.

use std::io::{self, Write};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::Arc;
use std::thread;

use crate::guard::sys::process;

/// Most bytes waiting for one stream.
pub const MAX_QUEUED_BYTES: usize = 256 * 1024;
/// Nice value of writer threads, relative to the routing threads.
const WRITER_NICE: i32 = 5;

pub(super) struct Writer {
    tx: SyncSender<Vec<u8>>,
    queued: Arc<AtomicUsize>,
}

impl Writer {
    /// Starts a thread writing what [`Writer::send`] queues to `w`; `on_error` runs once when a
    /// write fails (the thread then ends). The thread also ends when the writer is dropped.
    pub(super) fn spawn<W: Write + Send + 'static>(
        name: String,
        mut w: W,
        on_error: impl FnOnce() + Send + 'static,
    ) -> io::Result<Writer> {
        let (tx, rx) = sync_channel::<Vec<u8>>(1024);
        let queued = Arc::new(AtomicUsize::new(0));
        let q = queued.clone();
        thread::Builder::new().name(name).spawn(move || {
            // stream writes yield to the threads that route (and so to UDP delivery)
            process::lower_current_thread_priority(WRITER_NICE);
            for piece in rx {
                q.fetch_sub(piece.len(), Ordering::Relaxed);
                if w.write_all(&piece).is_err() {
                    on_error();
                    return;
                }
            }
        })?;
        Ok(Writer { tx, queued })
    }

    /// Queues `bytes`; `false` when the queue is full or the writer has ended.
    pub(super) fn send(&self, bytes: &[u8]) -> bool {
        let before = self.queued.fetch_add(bytes.len(), Ordering::Relaxed);
        if before + bytes.len() > MAX_QUEUED_BYTES || self.tx.try_send(bytes.to_vec()).is_err() {
            self.queued.fetch_sub(bytes.len(), Ordering::Relaxed);
            return false;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Condvar, Mutex};

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
        let w = Writer::spawn("t".into(), Stalled(gate.clone(), got.clone()), || {}).unwrap();
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
}
