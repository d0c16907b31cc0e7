//! The coil-driver wire protocol: framed, sequenced, checksummed, acknowledged messages.
//!
//! Every message is one frame (all integers little-endian):
//!
//! | offset | size | field |
//! | --- | --- | --- |
//! | 0 | 2 | sync `0xA5 0x5A` |
//! | 2 | 1 | message type |
//! | 3 | 2 | sequence number (u16, wraps) |
//! | 5 | 1 | payload length `N` (0–255) |
//! | 6 | N | payload |
//! | 6+N | 4 | CRC-32 (ISO-HDLC, as zlib) of bytes 2 .. 6+N |
//!
//! The host sends [`Message::Hello`], [`Message::SetCurrents`], [`Message::Heartbeat`] and
//! [`Message::Zero`], each with its own sequence number; the device answers each with an
//! [`Message::Ack`] naming that sequence number, or a [`Message::Nak`] when a frame fails its
//! checksum. The device zeroes its currents when it hears no valid frame for the watchdog time.
//! docs/rigs.md lists every message byte by byte.

mod codec;
mod message;

pub use codec::{Decoded, Decoder, FRAME_OVERHEAD, MAX_PAYLOAD, SYNC, encode};
pub use message::{
    AckStatus, Message, PROTOCOL_VERSION, WATCHDOG_MAX_MS, WATCHDOG_MIN_MS, ack_flags, msg_type,
};
