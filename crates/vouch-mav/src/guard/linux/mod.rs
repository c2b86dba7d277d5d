//! The guard's Linux system calls — the one module of the workspace allowed `unsafe`
//! (`#[allow(unsafe_code)]` where it is declared): batched UDP I/O (`recvmmsg`/`sendmmsg`),
//! stream writes that never wait (`MSG_DONTWAIT`), and the process control and `/proc` readings
//! of the benchmark (CPU affinity, clock ticks, SIGTERM, peak RSS). Every `unsafe` block says why
//! it is sound (`SAFETY:`). `super::portable` has the same functions for other systems.

pub mod process;
pub mod stream;
pub mod udp_batch;
