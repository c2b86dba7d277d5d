//! Raw serial port setup (8N1, no flow control, no line discipline) with termios through `libc`.
//! A dedicated crate (`serialport`) would pull udev bindings and a second I/O abstraction for
//! the ~30 lines needed here; the guard only needs a raw `File` it can read and write.

use std::fs::{File, OpenOptions};
use std::io;
use std::os::unix::fs::OpenOptionsExt;
use std::os::unix::io::AsRawFd;

fn speed(baud: u32) -> Option<libc::speed_t> {
    Some(match baud {
        1200 => libc::B1200,
        2400 => libc::B2400,
        4800 => libc::B4800,
        9600 => libc::B9600,
        19200 => libc::B19200,
        38400 => libc::B38400,
        57600 => libc::B57600,
        115200 => libc::B115200,
        230400 => libc::B230400,
        460800 => libc::B460800,
        500000 => libc::B500000,
        576000 => libc::B576000,
        921600 => libc::B921600,
        1000000 => libc::B1000000,
        1500000 => libc::B1500000,
        1152000 => libc::B1152000,
        2000000 => libc::B2000000,
        2500000 => libc::B2500000,
        3000000 => libc::B3000000,
        3500000 => libc::B3500000,
        4000000 => libc::B4000000,
        _ => return None,
    })
}

/// Opens `device` in raw mode at `baud`, with RTS/CTS flow control when asked. Reads return
/// after at most 100 ms (VMIN=0, VTIME=1) so the reader thread can notice shutdown.
pub fn open_raw(device: &str, baud: u32, flow_control: bool) -> io::Result<File> {
    let sp = speed(baud).ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, format!("unsupported baud {baud}"))
    })?;
    let file =
        OpenOptions::new().read(true).write(true).custom_flags(libc::O_NOCTTY).open(device)?;
    let fd = file.as_raw_fd();
    // SAFETY: fd is a valid open descriptor owned by `file`; termios is plain data filled by tcgetattr.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        if libc::tcgetattr(fd, &mut t) != 0 {
            return Err(io::Error::last_os_error());
        }
        libc::cfmakeraw(&mut t);
        t.c_cflag |= libc::CLOCAL | libc::CREAD;
        t.c_cflag &= !(libc::CRTSCTS | libc::CSTOPB | libc::PARENB);
        if flow_control {
            t.c_cflag |= libc::CRTSCTS;
        }
        t.c_cc[libc::VMIN] = 0;
        t.c_cc[libc::VTIME] = 1;
        if libc::cfsetispeed(&mut t, sp) != 0 || libc::cfsetospeed(&mut t, sp) != 0 {
            return Err(io::Error::last_os_error());
        }
        if libc::tcsetattr(fd, libc::TCSANOW, &t) != 0 {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(file)
}
