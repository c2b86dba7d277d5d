//! A stream write that never waits: `send` with `MSG_DONTWAIT`, so that a routing thread can
//! hand bytes to an idle TCP connection itself instead of waking its writer thread.

use std::io;
use std::net::TcpStream;
use std::os::fd::AsRawFd;

/// Writes what the socket takes now; `WouldBlock` when it takes nothing.
pub fn send_now(s: &TcpStream, bytes: &[u8]) -> io::Result<usize> {
    // SAFETY: `bytes` is a live slice of `bytes.len()` bytes; the fd belongs to `s`, which is
    // borrowed for the call. MSG_NOSIGNAL: a closed peer gives EPIPE, not SIGPIPE.
    let n = unsafe {
        libc::send(
            s.as_raw_fd(),
            bytes.as_ptr().cast(),
            bytes.len(),
            libc::MSG_DONTWAIT | libc::MSG_NOSIGNAL,
        )
    };
    if n < 0 { Err(io::Error::last_os_error()) } else { Ok(n as usize) }
}
