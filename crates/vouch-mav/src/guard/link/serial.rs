//! Serial ports through the `serialport` crate (termios on Linux and macOS, the Win32
//! communications API on Windows): 8 data bits, no parity, one stop bit, raw bytes, RTS/CTS flow
//! control when the endpoint asks for it. Reads time out after [`POLL_INTERVAL`] so the reader
//! thread notices the stop flag.

use std::io::{self, Write};

use serialport::{DataBits, FlowControl, Parity, SerialPort, StopBits};

use super::POLL_INTERVAL;

/// An open port, readable and writable, with a clone for the other direction.
pub(super) type Port = Box<dyn SerialPort>;

/// Opens `device` at `baud` (8N1, raw), with RTS/CTS flow control when `flow_control`.
pub(super) fn open(device: &str, baud: u32, flow_control: bool) -> io::Result<Port> {
    let flow = if flow_control { FlowControl::Hardware } else { FlowControl::None };
    serialport::new(device, baud)
        .data_bits(DataBits::Eight)
        .parity(Parity::None)
        .stop_bits(StopBits::One)
        .flow_control(flow)
        .timeout(POLL_INTERVAL)
        .open()
        .map_err(|e| io::Error::new(io_kind(&e), format!("{device}: {e}")))
}

/// The writing half of a port. A write that times out (flow control holding the line, a slow
/// link) is tried again, as a blocking write would wait: the writer thread's queue, not a
/// failed write, is what absorbs a link slower than the traffic.
pub(super) struct Output(pub Port);

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        loop {
            match self.0.write(buf) {
                Err(e)
                    if matches!(e.kind(), io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock) =>
                {
                    continue;
                }
                other => return other,
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

fn io_kind(e: &serialport::Error) -> io::ErrorKind {
    match e.kind() {
        serialport::ErrorKind::NoDevice => io::ErrorKind::NotFound,
        serialport::ErrorKind::InvalidInput => io::ErrorKind::InvalidInput,
        serialport::ErrorKind::Io(kind) => kind,
        serialport::ErrorKind::Unknown => io::ErrorKind::Other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_is_no_terminal_is_refused_with_its_name() {
        let Err(e) = open("/dev/null", 57600, false) else { panic!("/dev/null is no serial port") };
        assert!(e.to_string().starts_with("/dev/null: "), "{e}");
    }

    #[test]
    fn a_missing_device_is_not_found() {
        let Err(e) = open("/nonexistent/ttyVOUCH", 57600, false) else { panic!("no such device") };
        assert!(e.to_string().contains("/nonexistent/ttyVOUCH"), "{e}");
    }
}
