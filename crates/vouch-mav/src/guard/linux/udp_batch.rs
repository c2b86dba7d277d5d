//! Batched UDP I/O on Linux: `recvmmsg` to take every datagram already queued in one call, and a
//! per-thread send queue flushed with `sendmmsg`. Under load this divides the system calls per
//! message by the batch size; at low rates a batch is one datagram (`MSG_WAITFORONE`), so the
//! latency of a lone message is unchanged.

use std::cell::RefCell;
use std::io;
use std::mem::{size_of, zeroed};
use std::net::{SocketAddr, SocketAddrV4, SocketAddrV6, UdpSocket};
use std::os::unix::io::{AsRawFd, RawFd};

/// Datagrams taken per `recvmmsg` call.
pub const BATCH: usize = 32;
/// Bytes per datagram slot. MAVLink datagrams are far smaller (a frame is ≤ 280 bytes); a larger
/// datagram arrives flagged truncated and is treated as junk.
pub const SLOT: usize = 4096;

fn to_storage(a: &SocketAddr) -> (libc::sockaddr_storage, libc::socklen_t) {
    // SAFETY: sockaddr_storage is plain data large enough for both address families.
    let mut ss: libc::sockaddr_storage = unsafe { zeroed() };
    let len = match a {
        SocketAddr::V4(v4) => {
            let sin = libc::sockaddr_in {
                sin_family: libc::AF_INET as libc::sa_family_t,
                sin_port: v4.port().to_be(),
                sin_addr: libc::in_addr { s_addr: u32::from_ne_bytes(v4.ip().octets()) },
                sin_zero: [0; 8],
            };
            // SAFETY: sockaddr_in fits in sockaddr_storage.
            unsafe { std::ptr::write(&mut ss as *mut _ as *mut libc::sockaddr_in, sin) };
            size_of::<libc::sockaddr_in>()
        }
        SocketAddr::V6(v6) => {
            let sin6 = libc::sockaddr_in6 {
                sin6_family: libc::AF_INET6 as libc::sa_family_t,
                sin6_port: v6.port().to_be(),
                sin6_flowinfo: v6.flowinfo(),
                sin6_addr: libc::in6_addr { s6_addr: v6.ip().octets() },
                sin6_scope_id: v6.scope_id(),
            };
            // SAFETY: sockaddr_in6 fits in sockaddr_storage.
            unsafe { std::ptr::write(&mut ss as *mut _ as *mut libc::sockaddr_in6, sin6) };
            size_of::<libc::sockaddr_in6>()
        }
    };
    (ss, len as libc::socklen_t)
}

fn from_storage(ss: &libc::sockaddr_storage) -> Option<SocketAddr> {
    match i32::from(ss.ss_family) {
        libc::AF_INET => {
            // SAFETY: the kernel wrote a sockaddr_in for AF_INET.
            let sin = unsafe { &*(ss as *const _ as *const libc::sockaddr_in) };
            let ip = std::net::Ipv4Addr::from(u32::from_be(sin.sin_addr.s_addr));
            Some(SocketAddr::V4(SocketAddrV4::new(ip, u16::from_be(sin.sin_port))))
        }
        libc::AF_INET6 => {
            // SAFETY: the kernel wrote a sockaddr_in6 for AF_INET6.
            let s = unsafe { &*(ss as *const _ as *const libc::sockaddr_in6) };
            let ip = std::net::Ipv6Addr::from(s.sin6_addr.s6_addr);
            Some(SocketAddr::V6(SocketAddrV6::new(
                ip,
                u16::from_be(s.sin6_port),
                s.sin6_flowinfo,
                s.sin6_scope_id,
            )))
        }
        _ => None,
    }
}

/// Receive buffers for one reader thread. The message headers point into the buffers; all of
/// them are heap allocations owned here and never resized, so the pointers stay valid when the
/// struct moves, and a receive allocates nothing.
pub struct RecvBatch {
    bufs: Vec<u8>,
    addrs: Vec<libc::sockaddr_storage>,
    iovs: Vec<libc::iovec>,
    hdrs: Vec<libc::mmsghdr>,
    lens: Vec<(usize, bool)>,
}

impl RecvBatch {
    pub fn new() -> Self {
        let mut bufs = vec![0u8; BATCH * SLOT];
        // SAFETY: zeroed sockaddr_storage / mmsghdr are valid plain data.
        let mut addrs: Vec<libc::sockaddr_storage> = vec![unsafe { zeroed() }; BATCH];
        let mut iovs: Vec<libc::iovec> = (0..BATCH)
            .map(|i| libc::iovec { iov_base: bufs[i * SLOT..].as_mut_ptr().cast(), iov_len: SLOT })
            .collect();
        let mut hdrs: Vec<libc::mmsghdr> = (0..BATCH).map(|_| unsafe { zeroed() }).collect();
        for i in 0..BATCH {
            hdrs[i].msg_hdr.msg_name = (&mut addrs[i] as *mut libc::sockaddr_storage).cast();
            hdrs[i].msg_hdr.msg_iov = &mut iovs[i];
            hdrs[i].msg_hdr.msg_iovlen = 1;
        }
        RecvBatch { bufs, addrs, iovs, hdrs, lens: Vec::with_capacity(BATCH) }
    }

    /// Blocks (up to the socket's read timeout) for at least one datagram, then takes all that
    /// are queued, up to BATCH. Returns how many arrived.
    pub fn recv(&mut self, sock: &UdpSocket) -> io::Result<usize> {
        debug_assert_eq!(self.iovs.len(), BATCH);
        for h in &mut self.hdrs {
            // the kernel overwrites these on every call
            h.msg_hdr.msg_namelen = size_of::<libc::sockaddr_storage>() as libc::socklen_t;
            h.msg_hdr.msg_flags = 0;
            h.msg_len = 0;
        }
        // SAFETY: fd is an open UDP socket; headers point into buffers owned by self.
        let n = unsafe {
            libc::recvmmsg(
                sock.as_raw_fd(),
                self.hdrs.as_mut_ptr(),
                BATCH as libc::c_uint,
                libc::MSG_WAITFORONE,
                std::ptr::null_mut(),
            )
        };
        if n < 0 {
            return Err(io::Error::last_os_error());
        }
        self.lens.clear();
        for h in &self.hdrs[..n as usize] {
            let truncated = h.msg_hdr.msg_flags & libc::MSG_TRUNC != 0;
            self.lens.push(((h.msg_len as usize).min(SLOT), truncated));
        }
        Ok(n as usize)
    }

    /// Datagram `i` of the last batch: (sender, bytes, truncated).
    pub fn get(&self, i: usize) -> (Option<SocketAddr>, &[u8], bool) {
        let (len, trunc) = self.lens[i];
        (from_storage(&self.addrs[i]), &self.bufs[i * SLOT..i * SLOT + len], trunc)
    }
}

struct Pending {
    fd: RawFd,
    to: libc::sockaddr_storage,
    to_len: libc::socklen_t,
    start: usize,
    end: usize,
}

#[derive(Default)]
struct SendQueue {
    active: bool,
    data: Vec<u8>,
    items: Vec<Pending>,
    /// Scratch for `sendmmsg`, kept between flushes so a flush allocates nothing once warm.
    iovs: Vec<libc::iovec>,
    hdrs: Vec<libc::mmsghdr>,
}

thread_local! {
    static QUEUE: RefCell<SendQueue> = RefCell::new(SendQueue::default());
}

/// Marks the start of a receive batch on this thread: UDP sends are queued until [`flush`].
pub fn begin() {
    QUEUE.with(|q| q.borrow_mut().active = true);
}

/// Sends `bytes` to `to` now, or queues it when a batch is active on this thread.
pub fn send_to(sock: &UdpSocket, bytes: &[u8], to: &SocketAddr) -> bool {
    let queued = QUEUE.with(|q| {
        let mut q = q.borrow_mut();
        if !q.active {
            return false;
        }
        let start = q.data.len();
        q.data.extend_from_slice(bytes);
        let (ss, len) = to_storage(to);
        let end = q.data.len();
        q.items.push(Pending { fd: sock.as_raw_fd(), to: ss, to_len: len, start, end });
        true
    });
    queued || sock.send_to(bytes, to).is_ok()
}

/// Sends everything queued since [`begin`] with as few `sendmmsg` calls as possible.
pub fn flush() {
    QUEUE.with(|q| {
        let mut q = q.borrow_mut();
        q.active = false;
        if q.items.is_empty() {
            q.data.clear();
            return;
        }
        let SendQueue { data, items, iovs, hdrs, .. } = &mut *q;
        iovs.clear();
        iovs.extend(items.iter().map(|p| libc::iovec {
            iov_base: data[p.start..].as_mut_ptr().cast(),
            iov_len: p.end - p.start,
        }));
        hdrs.clear();
        // SAFETY: plain data, pointers into `items`/`iovs`/`data` that live through the calls.
        hdrs.extend((0..items.len()).map(|_| unsafe { zeroed::<libc::mmsghdr>() }));
        for (i, p) in items.iter_mut().enumerate() {
            hdrs[i].msg_hdr.msg_name = (&mut p.to as *mut libc::sockaddr_storage).cast();
            hdrs[i].msg_hdr.msg_namelen = p.to_len;
            hdrs[i].msg_hdr.msg_iov = &mut iovs[i];
            hdrs[i].msg_hdr.msg_iovlen = 1;
        }
        let mut i = 0;
        while i < items.len() {
            let fd = items[i].fd;
            let mut j = i;
            while j < items.len() && items[j].fd == fd {
                j += 1;
            }
            // Send [i, j); a message the kernel refuses (e.g. ICMP unreachable peer) is skipped.
            let mut k = i;
            let mut attempts = 0;
            while k < j && attempts < j - i + 1 {
                attempts += 1;
                // SAFETY: hdrs[k..j] are initialised above; fd is an open socket.
                let n = unsafe {
                    libc::sendmmsg(fd, hdrs[k..].as_mut_ptr(), (j - k) as libc::c_uint, 0)
                };
                if n <= 0 {
                    k += 1;
                } else {
                    k += n as usize;
                }
            }
            i = j;
        }
        items.clear();
        data.clear();
    });
}
