//! Framing: encoding a message, and a streaming decoder that resynchronises on garbage.

use super::Message;
use super::message::AckStatus;

/// The two sync bytes that open every frame.
pub const SYNC: [u8; 2] = [0xA5, 0x5A];
/// Bytes of a frame besides its payload: sync 2, type 1, seq 2, length 1, CRC 4.
pub const FRAME_OVERHEAD: usize = 10;
/// Largest payload.
pub const MAX_PAYLOAD: usize = 255;

/// Encodes `msg` with sequence number `seq` as one frame.
pub fn encode(seq: u16, msg: &Message) -> Vec<u8> {
    let payload = msg.payload();
    assert!(
        payload.len() <= MAX_PAYLOAD,
        "payload of {} bytes",
        payload.len()
    );
    let mut f = Vec::with_capacity(FRAME_OVERHEAD + payload.len());
    f.extend_from_slice(&SYNC);
    f.push(msg.type_byte());
    f.extend_from_slice(&seq.to_le_bytes());
    f.push(payload.len() as u8);
    f.extend_from_slice(&payload);
    let crc = crc32fast::hash(&f[2..]);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

/// What the decoder found in the byte stream.
#[derive(Debug, Clone, PartialEq)]
pub enum Decoded {
    /// A valid frame with a message that parsed.
    Message {
        /// Sequence number.
        seq: u16,
        /// The message.
        msg: Message,
    },
    /// A valid frame (checksum good) whose payload did not parse.
    Invalid {
        /// Sequence number.
        seq: u16,
        /// Type byte.
        ty: u8,
        /// Why.
        status: AckStatus,
    },
    /// A frame that failed its checksum (its bytes were skipped).
    BadChecksum,
}

/// A streaming frame decoder: feed bytes as they arrive, take frames out.
///
/// On a checksum failure it reports [`Decoded::BadChecksum`] and rescans from the byte after the
/// failed sync, so one corrupted byte costs one frame, never the link.
#[derive(Debug, Default)]
pub struct Decoder {
    buf: Vec<u8>,
}

impl Decoder {
    /// An empty decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn feed(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// Bytes waiting in the buffer.
    pub fn pending(&self) -> usize {
        self.buf.len()
    }

    /// Drops a partial frame that stopped arriving (call when the line has been idle): a frame
    /// is written in one piece, so a stalled one had a corrupted length byte.
    pub fn drop_stalled(&mut self) -> bool {
        if self.buf.is_empty() {
            return false;
        }
        self.buf.drain(..1);
        true
    }

    /// The next decoded frame, if a whole one is buffered.
    pub fn next_frame(&mut self) -> Option<Decoded> {
        let start = self.buf.windows(2).position(|w| w == SYNC);
        match start {
            None => {
                // keep a trailing first sync byte, drop the rest
                let keep = usize::from(self.buf.last() == Some(&SYNC[0]));
                let n = self.buf.len() - keep;
                self.buf.drain(..n);
                return None;
            }
            Some(s) => {
                self.buf.drain(..s);
            }
        }
        if self.buf.len() < 6 {
            return None;
        }
        let len = self.buf[5] as usize;
        if !plausible_length(self.buf[2], len) {
            self.buf.drain(..1);
            return Some(Decoded::BadChecksum);
        }
        let total = FRAME_OVERHEAD + len;
        if self.buf.len() < total {
            return None;
        }
        let crc = u32::from_le_bytes(self.buf[total - 4..total].try_into().unwrap());
        if crc32fast::hash(&self.buf[2..total - 4]) != crc {
            self.buf.drain(..1);
            // skip to the next sync; report the failure once
            return Some(Decoded::BadChecksum);
        }
        let ty = self.buf[2];
        let seq = u16::from_le_bytes([self.buf[3], self.buf[4]]);
        let out = match Message::parse(ty, &self.buf[6..6 + len]) {
            Ok(msg) => Decoded::Message { seq, msg },
            Err(status) => Decoded::Invalid { seq, ty, status },
        };
        self.buf.drain(..total);
        Some(out)
    }
}

/// False when a known message type cannot have this payload length (a corrupted header).
fn plausible_length(ty: u8, len: usize) -> bool {
    use super::msg_type::*;
    match ty {
        HELLO => len == 4,
        SET_CURRENTS => len % 4 == 1,
        HEARTBEAT | ZERO | NAK => len == 0,
        ACK => len == 8,
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_is_crc32_iso_hdlc() {
        assert_eq!(crc32fast::hash(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn documented_example_frames() {
        // the examples in docs/rigs.md, byte for byte
        let hex = |m: Message, seq: u16| {
            encode(seq, &m)
                .iter()
                .map(|b| format!("{b:02X}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        assert_eq!(
            hex(
                Message::Hello {
                    version: 1,
                    channels: 5,
                    watchdog_ms: 200
                },
                1
            ),
            "A5 5A 01 01 00 04 01 05 C8 00 4B 8A 2B 47"
        );
        assert_eq!(
            hex(Message::SetCurrents(vec![1.0, -0.5]), 7),
            "A5 5A 02 07 00 09 02 00 00 80 3F 00 00 00 BF 98 8C 4C AF"
        );
        assert_eq!(hex(Message::Heartbeat, 9), "A5 5A 03 09 00 00 7D 4B 20 3C");
        assert_eq!(hex(Message::Zero, 10), "A5 5A 04 0A 00 00 9D CD B1 A3");
        let ack = Message::Ack {
            seq: 8,
            status: AckStatus::Ok,
            flags: 0,
            device_ms: 123456,
        };
        assert_eq!(
            hex(ack, 8),
            "A5 5A 81 08 00 08 08 00 00 00 40 E2 01 00 BA D0 20 7A"
        );
        assert_eq!(hex(Message::Nak, 0), "A5 5A 82 00 00 00 AC A1 14 66");
    }

    #[test]
    fn round_trip_every_message() {
        let msgs = [
            Message::Hello {
                version: 1,
                channels: 5,
                watchdog_ms: 200,
            },
            Message::SetCurrents(vec![1.5, -2.0, 0.0, 3.25, -8.0]),
            Message::Heartbeat,
            Message::Zero,
            Message::Ack {
                seq: 65535,
                status: AckStatus::OverLimit,
                flags: 3,
                device_ms: 123456,
            },
            Message::Nak,
        ];
        let mut d = Decoder::new();
        for (i, m) in msgs.iter().enumerate() {
            d.feed(&encode(i as u16, m));
        }
        for (i, m) in msgs.iter().enumerate() {
            assert_eq!(
                d.next_frame(),
                Some(Decoded::Message {
                    seq: i as u16,
                    msg: m.clone()
                })
            );
        }
        assert_eq!(d.next_frame(), None);
    }

    #[test]
    fn resynchronises_after_garbage_and_corruption() {
        let mut d = Decoder::new();
        let a = encode(1, &Message::Heartbeat);
        let mut b = encode(2, &Message::SetCurrents(vec![1.0; 5]));
        b[9] ^= 0x10; // a corrupted payload byte
        let c = encode(3, &Message::Zero);
        d.feed(&[0x00, 0xA5, 0x13, 0xA5]);
        d.feed(&a);
        d.feed(&b);
        // split the last frame across two reads
        d.feed(&c[..4]);
        assert_eq!(
            d.next_frame(),
            Some(Decoded::Message {
                seq: 1,
                msg: Message::Heartbeat
            })
        );
        assert_eq!(d.next_frame(), Some(Decoded::BadChecksum));
        assert_eq!(d.next_frame(), None);
        d.feed(&c[4..]);
        assert_eq!(
            d.next_frame(),
            Some(Decoded::Message {
                seq: 3,
                msg: Message::Zero
            })
        );
    }

    #[test]
    fn a_nan_current_is_rejected() {
        let mut d = Decoder::new();
        d.feed(&encode(4, &Message::SetCurrents(vec![f32::NAN])));
        assert_eq!(
            d.next_frame(),
            Some(Decoded::Invalid {
                seq: 4,
                ty: 0x02,
                status: AckStatus::BadPayload
            })
        );
    }
}
