//! The device's end of the coil link: a TCP connection or a pseudo-terminal master.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// A byte stream the device reads with a timeout.
pub trait DeviceIo: Send {
    /// Reads what is there, waiting at most `timeout`: `None` on timeout, `Some(0)` when closed.
    fn read_timeout(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>>;
    /// Writes all bytes.
    fn send(&mut self, bytes: &[u8]) -> io::Result<()>;
}

impl DeviceIo for TcpStream {
    fn read_timeout(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
        self.set_read_timeout(Some(timeout.max(Duration::from_micros(100))))?;
        match self.read(buf) {
            Ok(n) => Ok(Some(n)),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(None)
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::ConnectionReset | io::ErrorKind::ConnectionAborted
                ) =>
            {
                Ok(Some(0))
            }
            Err(e) => Err(e),
        }
    }

    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.write_all(bytes)
    }
}

/// A pseudo-terminal whose slave end a host opens as a serial port.
#[cfg(unix)]
pub mod pty {
    use std::fs::File;
    use std::io::{self, Read, Write};
    use std::os::fd::{AsFd, OwnedFd};
    use std::path::{Path, PathBuf};
    use std::time::Duration;

    use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
    use nix::pty::openpty;
    use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};

    use super::DeviceIo;

    /// The master end; the slave is kept open so that a host that dies leaves the line up and
    /// only the watchdog notices (as with a real serial cable).
    pub struct Pty {
        master: File,
        _slave: OwnedFd,
        link: PathBuf,
    }

    impl Pty {
        /// Opens a pseudo-terminal in raw mode and links its slave device to `link`.
        pub fn open(link: &Path) -> io::Result<Self> {
            let p = openpty(None, None).map_err(io::Error::from)?;
            let mut t = tcgetattr(&p.slave).map_err(io::Error::from)?;
            cfmakeraw(&mut t);
            tcsetattr(&p.slave, SetArg::TCSANOW, &t).map_err(io::Error::from)?;
            let name = nix::unistd::ttyname(p.slave.as_fd()).map_err(io::Error::from)?;
            let _ = std::fs::remove_file(link);
            std::os::unix::fs::symlink(&name, link)?;
            Ok(Self {
                master: File::from(p.master),
                _slave: p.slave,
                link: link.to_path_buf(),
            })
        }
    }

    impl Drop for Pty {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.link);
        }
    }

    impl DeviceIo for Pty {
        fn read_timeout(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
            let ms = timeout.as_millis().clamp(1, 10_000) as u16;
            let mut fds = [PollFd::new(self.master.as_fd(), PollFlags::POLLIN)];
            let n = poll(&mut fds, PollTimeout::from(ms)).map_err(io::Error::from)?;
            if n == 0 {
                return Ok(None);
            }
            match self.master.read(buf) {
                Ok(n) => Ok(Some(n)),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(None),
                Err(e) => Err(e),
            }
        }

        fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
            self.master.write_all(bytes)
        }
    }
}
