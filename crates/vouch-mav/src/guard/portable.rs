//! Fallbacks of `super::linux` for other systems, in safe std code: one datagram per receive
//! call and direct sends, no process control or `/proc` readings. Compiled on
//! Linux too, where its tests keep it working.

#![cfg_attr(target_os = "linux", allow(dead_code))]

/// Stream writes that never wait: none here, every piece goes through the writer thread.
pub mod stream {
    use std::io;
    use std::net::TcpStream;

    /// Always `WouldBlock`: the caller queues the bytes for the writer thread.
    pub fn send_now(_s: &TcpStream, _bytes: &[u8]) -> io::Result<usize> {
        Err(io::ErrorKind::WouldBlock.into())
    }
}

/// UDP I/O one datagram at a time.
pub mod udp_batch {
    use std::io;
    use std::net::{SocketAddr, UdpSocket};

    /// Datagrams taken per receive call.
    pub const BATCH: usize = 1;
    /// Bytes per datagram slot (larger datagrams are reported truncated).
    pub const SLOT: usize = 4096;

    /// The receive buffer of one reader thread.
    pub struct RecvBatch {
        buf: Vec<u8>,
        last: Option<(SocketAddr, usize)>,
    }

    impl RecvBatch {
        /// An empty buffer (one byte more than a slot, to see truncation).
        pub fn new() -> Self {
            RecvBatch { buf: vec![0; SLOT + 1], last: None }
        }

        /// Blocks (up to the socket's read timeout) for one datagram.
        pub fn recv(&mut self, sock: &UdpSocket) -> io::Result<usize> {
            let (n, from) = sock.recv_from(&mut self.buf)?;
            self.last = Some((from, n));
            Ok(1)
        }

        /// The datagram of the last receive: (sender, bytes, truncated).
        pub fn get(&self, _i: usize) -> (Option<SocketAddr>, &[u8], bool) {
            match self.last {
                Some((from, n)) => (Some(from), &self.buf[..n.min(SLOT)], n > SLOT),
                None => (None, &[], false),
            }
        }
    }

    /// Nothing is queued: sends go out at once.
    pub fn begin() {}

    /// Sends `bytes` to `to` now.
    pub fn send_to(sock: &UdpSocket, bytes: &[u8], to: &SocketAddr) -> bool {
        sock.send_to(bytes, to).is_ok()
    }

    /// Nothing to flush.
    pub fn flush() {}
}

/// No process control or `/proc` readings: the benchmark runs unpinned and reports no CPU time
/// or memory figures.
pub mod process {
    #[cfg(feature = "bench")]
    use std::process::Child;

    /// No-op.
    pub fn lower_current_thread_priority(_n: i32) {}
    /// No-op.
    #[cfg(feature = "bench")]
    pub fn pin_current_thread(_cpu: usize) {}
    /// No-op.
    #[cfg(feature = "bench")]
    pub fn unpin_current_thread() {}
    /// No-op.
    #[cfg(feature = "bench")]
    pub fn pin_process(_pid: u32, _cpu: usize) {}
    /// Unknown.
    #[cfg(feature = "bench")]
    pub fn cpu_seconds(_pid: u32) -> Option<f64> {
        None
    }
    /// Unknown.
    #[cfg(feature = "bench")]
    pub fn peak_rss_kb(_pid: u32) -> Option<u64> {
        None
    }
    /// Unknown.
    #[cfg(feature = "bench")]
    pub fn rss_kb(_pid: u32) -> Option<u64> {
        None
    }
    /// No-op.
    #[cfg(feature = "bench")]
    pub fn reset_peak_rss(_pid: u32) {}
    /// Unknown.
    #[cfg(feature = "bench")]
    pub fn load_average() -> Option<String> {
        None
    }
    /// Kills the child (no SIGTERM without libc).
    #[cfg(feature = "bench")]
    pub fn terminate(child: &mut Child) {
        let _ = child.kill();
    }
}

#[cfg(test)]
mod tests {
    use std::net::UdpSocket;
    use std::time::Duration;

    use super::udp_batch::{RecvBatch, SLOT};

    #[test]
    fn one_datagram_per_receive_and_oversized_ones_flagged() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
        let to = rx.local_addr().unwrap();
        let mut b = RecvBatch::new();
        tx.send_to(b"abc", to).unwrap();
        assert_eq!(b.recv(&rx).unwrap(), 1);
        assert_eq!(b.get(0), (Some(tx.local_addr().unwrap()), &b"abc"[..], false));
        tx.send_to(&vec![7u8; SLOT + 10], to).unwrap();
        b.recv(&rx).unwrap();
        let (_, bytes, truncated) = b.get(0);
        assert_eq!((bytes.len(), truncated), (SLOT, true));
    }
}
