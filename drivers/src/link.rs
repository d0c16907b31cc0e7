//! The host end of the coil link: sequenced requests, acknowledgements, resends.

use std::io::{self, Read, Write};
use std::time::{Duration, Instant};

use crate::protocol::{AckStatus, Decoded, Decoder, Message, ack_flags, encode};
use crate::transport::{Transport, is_timeout};

/// Why the coil link failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinkError {
    /// The transport failed or closed.
    #[error("coil link lost ({0})")]
    Lost(String),
    /// No acknowledgement after every resend.
    #[error("coil driver did not acknowledge message {seq} after {tries} tries")]
    NoAck {
        /// Sequence number of the last try.
        seq: u16,
        /// Tries made.
        tries: u32,
    },
    /// The device refused the message.
    #[error("coil driver refused message {seq}: {status:?}")]
    Refused {
        /// Sequence number.
        seq: u16,
        /// The device's status.
        status: AckStatus,
    },
    /// The abort flag (Ctrl-C) is raised: the session sends no further command.
    #[error("interrupted: no further command sent")]
    Interrupted,
}

/// What an acknowledgement said.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AckInfo {
    /// [`ack_flags`] bits.
    pub flags: u8,
    /// The device clock (ms).
    pub device_ms: u32,
    /// Tries it took (1 = no resend).
    pub tries: u32,
    /// When the message was first written to the transport.
    pub sent: Instant,
}

impl AckInfo {
    /// The device watchdog had zeroed the currents before this message.
    pub fn watchdog_tripped(&self) -> bool {
        self.flags & ack_flags::WATCHDOG_TRIPPED != 0
    }
}

/// Counters of link trouble, for logs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LinkStats {
    /// Messages sent (first tries).
    pub sent: u64,
    /// Resends.
    pub resent: u64,
    /// NAKs received.
    pub naks: u64,
    /// Received frames that failed their checksum.
    pub bad_frames: u64,
    /// Acknowledgement timeouts.
    pub timeouts: u64,
}

/// The host end of the coil protocol over one transport.
pub struct CoilLink {
    io: Box<dyn Transport>,
    decoder: Decoder,
    seq: u16,
    ack_timeout: Duration,
    retries: u32,
    stats: LinkStats,
    lost: Option<String>,
}

impl CoilLink {
    /// A link over `io`: wait `ack_timeout` for each acknowledgement, resend up to `retries` times.
    pub fn new(io: Box<dyn Transport>, ack_timeout: Duration, retries: u32) -> Self {
        Self {
            io,
            decoder: Decoder::new(),
            seq: 0,
            ack_timeout,
            retries,
            stats: LinkStats::default(),
            lost: None,
        }
    }

    /// The transport's description.
    pub fn describe(&self) -> String {
        self.io.describe()
    }

    /// Trouble counters so far.
    pub fn stats(&self) -> LinkStats {
        self.stats
    }

    /// True once the transport has failed.
    pub fn is_lost(&self) -> bool {
        self.lost.is_some()
    }

    /// Sends `msg` and waits for its acknowledgement, resending on a NAK, a corrupted reply or
    /// a timeout.
    pub fn request(&mut self, msg: &Message) -> Result<AckInfo, LinkError> {
        if let Some(e) = &self.lost {
            return Err(LinkError::Lost(e.clone()));
        }
        self.seq = self.seq.wrapping_add(1);
        let seq = self.seq;
        let frame = encode(seq, msg);
        self.stats.sent += 1;
        let tries = self.retries + 1;
        let mut first_write = None;
        for attempt in 1..=tries {
            if attempt > 1 {
                self.stats.resent += 1;
            }
            self.write(&frame)?;
            let sent = *first_write.get_or_insert_with(Instant::now);
            match self.wait_ack(seq)? {
                Some((status, flags, device_ms)) => {
                    if status != AckStatus::Ok {
                        return Err(LinkError::Refused { seq, status });
                    }
                    return Ok(AckInfo {
                        flags,
                        device_ms,
                        tries: attempt,
                        sent,
                    });
                }
                None => continue,
            }
        }
        Err(LinkError::NoAck { seq, tries })
    }

    fn write(&mut self, frame: &[u8]) -> Result<(), LinkError> {
        let r = self.io.write_all(frame).and_then(|_| self.io.flush());
        r.map_err(|e| self.lose(e.to_string()))
    }

    fn lose(&mut self, why: String) -> LinkError {
        self.lost = Some(why.clone());
        LinkError::Lost(why)
    }

    /// Waits for the ACK of `seq`: `Some` on it, `None` when a resend is due.
    fn wait_ack(&mut self, seq: u16) -> Result<Option<(AckStatus, u8, u32)>, LinkError> {
        let deadline = Instant::now() + self.ack_timeout;
        let mut buf = [0u8; 256];
        loop {
            while let Some(d) = self.decoder.next_frame() {
                match d {
                    Decoded::Message {
                        msg:
                            Message::Ack {
                                seq: s,
                                status,
                                flags,
                                device_ms,
                            },
                        ..
                    } if s == seq => {
                        return Ok(Some((status, flags, device_ms)));
                    }
                    Decoded::Message {
                        msg: Message::Nak, ..
                    } => {
                        self.stats.naks += 1;
                        return Ok(None);
                    }
                    Decoded::BadChecksum => self.stats.bad_frames += 1,
                    _ => {} // a late ACK of an earlier try, or noise
                }
            }
            let now = Instant::now();
            if now >= deadline {
                self.stats.timeouts += 1;
                self.decoder.drop_stalled();
                return Ok(None);
            }
            self.io
                .set_read_timeout(deadline - now)
                .map_err(|e| self.lose(e.to_string()))?;
            match self.io.read(&mut buf) {
                Ok(0) => return Err(self.lose("closed by the device".into())),
                Ok(n) => self.decoder.feed(&buf[..n]),
                Err(e) if is_timeout(&e) || e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.lose(e.to_string())),
            }
        }
    }
}
