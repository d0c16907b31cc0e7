//! The protocol's messages and their payloads.

/// Protocol version carried by [`Message::Hello`].
pub const PROTOCOL_VERSION: u8 = 1;

/// The shortest device watchdog (ms): the device raises a shorter [`Message::Hello`] request to
/// this.
pub const WATCHDOG_MIN_MS: u16 = 20;

/// The longest device watchdog (ms): the device lowers a longer [`Message::Hello`] request to
/// this, so a dead host's field is zeroed within a second whatever the host asked.
pub const WATCHDOG_MAX_MS: u16 = 1000;

/// Message type bytes.
pub mod msg_type {
    /// Host → device: open a session.
    pub const HELLO: u8 = 0x01;
    /// Host → device: set every channel's current.
    pub const SET_CURRENTS: u8 = 0x02;
    /// Host → device: keep-alive.
    pub const HEARTBEAT: u8 = 0x03;
    /// Host → device: zero every current now.
    pub const ZERO: u8 = 0x04;
    /// Device → host: acknowledgement of one sequence number.
    pub const ACK: u8 = 0x81;
    /// Device → host: a frame failed its checksum.
    pub const NAK: u8 = 0x82;
}

/// Bits of [`Message::Ack`]'s `flags`.
pub mod ack_flags {
    /// The device watchdog zeroed the currents since the previous acknowledgement.
    pub const WATCHDOG_TRIPPED: u8 = 0x01;
    /// The currents in force are all zero.
    pub const CURRENTS_ZERO: u8 = 0x02;
}

/// The outcome of a host message, as reported in [`Message::Ack`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AckStatus {
    /// Accepted and applied.
    Ok,
    /// The payload did not parse (wrong length, NaN current).
    BadPayload,
    /// Unknown message type.
    UnknownType,
    /// The channel count differs from the device's.
    ChannelMismatch,
    /// A current exceeded the device's own limit: refused, currents zeroed.
    OverLimit,
    /// A protocol version the device does not speak.
    BadVersion,
    /// A status byte this host does not know.
    Other(u8),
}

impl AckStatus {
    /// The status byte.
    pub fn code(self) -> u8 {
        match self {
            AckStatus::Ok => 0,
            AckStatus::BadPayload => 1,
            AckStatus::UnknownType => 2,
            AckStatus::ChannelMismatch => 3,
            AckStatus::OverLimit => 4,
            AckStatus::BadVersion => 5,
            AckStatus::Other(c) => c,
        }
    }

    /// The status of a byte.
    pub fn from_code(c: u8) -> Self {
        match c {
            0 => AckStatus::Ok,
            1 => AckStatus::BadPayload,
            2 => AckStatus::UnknownType,
            3 => AckStatus::ChannelMismatch,
            4 => AckStatus::OverLimit,
            5 => AckStatus::BadVersion,
            c => AckStatus::Other(c),
        }
    }
}

/// A protocol message (without its sequence number).
#[derive(Debug, Clone, PartialEq)]
pub enum Message {
    /// Open a session: protocol version, channel count, watchdog timeout (ms).
    Hello {
        /// [`PROTOCOL_VERSION`].
        version: u8,
        /// Number of current channels the host will send.
        channels: u8,
        /// The device watchdog timeout the host asks for (ms); the device clamps it to
        /// [`WATCHDOG_MIN_MS`]..=[`WATCHDOG_MAX_MS`].
        watchdog_ms: u16,
    },
    /// Set every channel's current (A).
    SetCurrents(Vec<f32>),
    /// Keep-alive; changes nothing.
    Heartbeat,
    /// Zero every current.
    Zero,
    /// Acknowledges the host message with sequence number `seq`.
    Ack {
        /// The acknowledged sequence number.
        seq: u16,
        /// What the device did with it.
        status: AckStatus,
        /// [`ack_flags`] bits.
        flags: u8,
        /// Device clock (ms since the device started, wraps).
        device_ms: u32,
    },
    /// A frame failed its checksum (the sequence number is not trusted).
    Nak,
}

impl Message {
    /// The type byte.
    pub fn type_byte(&self) -> u8 {
        match self {
            Message::Hello { .. } => msg_type::HELLO,
            Message::SetCurrents(_) => msg_type::SET_CURRENTS,
            Message::Heartbeat => msg_type::HEARTBEAT,
            Message::Zero => msg_type::ZERO,
            Message::Ack { .. } => msg_type::ACK,
            Message::Nak => msg_type::NAK,
        }
    }

    /// The payload bytes.
    pub fn payload(&self) -> Vec<u8> {
        match self {
            Message::Hello {
                version,
                channels,
                watchdog_ms,
            } => {
                let mut p = vec![*version, *channels];
                p.extend_from_slice(&watchdog_ms.to_le_bytes());
                p
            }
            Message::SetCurrents(c) => {
                let mut p = Vec::with_capacity(1 + 4 * c.len());
                p.push(c.len() as u8);
                for x in c {
                    p.extend_from_slice(&x.to_le_bytes());
                }
                p
            }
            Message::Heartbeat | Message::Zero | Message::Nak => Vec::new(),
            Message::Ack {
                seq,
                status,
                flags,
                device_ms,
            } => {
                let mut p = Vec::with_capacity(8);
                p.extend_from_slice(&seq.to_le_bytes());
                p.push(status.code());
                p.push(*flags);
                p.extend_from_slice(&device_ms.to_le_bytes());
                p
            }
        }
    }

    /// Parses a message from its type byte and payload; `Err` names what is wrong.
    pub fn parse(ty: u8, p: &[u8]) -> Result<Message, AckStatus> {
        let bad = AckStatus::BadPayload;
        match ty {
            msg_type::HELLO => {
                if p.len() != 4 {
                    return Err(bad);
                }
                Ok(Message::Hello {
                    version: p[0],
                    channels: p[1],
                    watchdog_ms: u16::from_le_bytes([p[2], p[3]]),
                })
            }
            msg_type::SET_CURRENTS => {
                let n = *p.first().ok_or(bad)? as usize;
                if p.len() != 1 + 4 * n {
                    return Err(bad);
                }
                let c: Vec<f32> = p[1..]
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect();
                if c.iter().any(|x| !x.is_finite()) {
                    return Err(bad);
                }
                Ok(Message::SetCurrents(c))
            }
            msg_type::HEARTBEAT if p.is_empty() => Ok(Message::Heartbeat),
            msg_type::ZERO if p.is_empty() => Ok(Message::Zero),
            msg_type::NAK if p.is_empty() => Ok(Message::Nak),
            msg_type::ACK if p.len() == 8 => Ok(Message::Ack {
                seq: u16::from_le_bytes([p[0], p[1]]),
                status: AckStatus::from_code(p[2]),
                flags: p[3],
                device_ms: u32::from_le_bytes([p[4], p[5], p[6], p[7]]),
            }),
            msg_type::HEARTBEAT | msg_type::ZERO | msg_type::NAK | msg_type::ACK => Err(bad),
            _ => Err(AckStatus::UnknownType),
        }
    }
}
