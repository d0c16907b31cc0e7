//! Byte transports for the coil link: a serial port (or pseudo-terminal) and TCP.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::Duration;

use crate::rigfile::CoilEndpoint;

/// A duplex byte stream with a read timeout.
pub trait Transport: Read + Write + Send {
    /// Sets how long a read waits for the first byte.
    fn set_read_timeout(&mut self, t: Duration) -> io::Result<()>;
    /// A short description for messages, e.g. `tcp 127.0.0.1:7700`.
    fn describe(&self) -> String;
}

struct Serial {
    port: Box<dyn serialport::SerialPort>,
    path: String,
}

impl Read for Serial {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.port.read(buf)
    }
}

impl Write for Serial {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.port.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.port.flush()
    }
}

impl Transport for Serial {
    fn set_read_timeout(&mut self, t: Duration) -> io::Result<()> {
        self.port.set_timeout(t).map_err(io::Error::other)
    }
    fn describe(&self) -> String {
        format!("serial {}", self.path)
    }
}

struct Tcp {
    stream: TcpStream,
    addr: String,
}

impl Read for Tcp {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.stream.read(buf)
    }
}

impl Write for Tcp {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.stream.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.stream.flush()
    }
}

impl Transport for Tcp {
    fn set_read_timeout(&mut self, t: Duration) -> io::Result<()> {
        self.stream
            .set_read_timeout(Some(t.max(Duration::from_micros(1))))
    }
    fn describe(&self) -> String {
        format!("tcp {}", self.addr)
    }
}

/// Opens the coil link's transport.
pub fn open(endpoint: &CoilEndpoint, connect_timeout: Duration) -> io::Result<Box<dyn Transport>> {
    match endpoint {
        CoilEndpoint::Serial { path, baud } => {
            let port = serialport::new(path, *baud)
                .timeout(Duration::from_millis(10))
                .open()
                .map_err(|e| io::Error::other(format!("cannot open serial port {path}: {e}")))?;
            Ok(Box::new(Serial {
                port,
                path: path.clone(),
            }))
        }
        CoilEndpoint::Tcp(addr) => Ok(Box::new(Tcp {
            stream: connect_tcp(addr, connect_timeout)?,
            addr: addr.clone(),
        })),
    }
}

/// Connects to `addr` (HOST:PORT) with a timeout, no Nagle delay.
pub fn connect_tcp(addr: &str, timeout: Duration) -> io::Result<TcpStream> {
    use std::net::ToSocketAddrs;
    let mut last = io::Error::other(format!("{addr}: no address"));
    for a in addr.to_socket_addrs()? {
        match TcpStream::connect_timeout(&a, timeout) {
            Ok(s) => {
                s.set_nodelay(true)?;
                return Ok(s);
            }
            Err(e) => last = io::Error::new(e.kind(), format!("cannot connect to {addr}: {e}")),
        }
    }
    Err(last)
}

/// True for the error kinds a read timeout produces.
pub fn is_timeout(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
    )
}
