//! A grey-level camera frame and the frame-stream wire format.
//!
//! A stream of frames (the emulator's camera, over TCP) is a sequence of records:
//!
//! | offset | size | field |
//! | --- | --- | --- |
//! | 0 | 4 | magic `MBF1` |
//! | 4 | 8 | frame index (u64, from 0; a gap is a dropped frame) |
//! | 12 | 8 | capture time (f64, s, device clock) |
//! | 20 | 2 | width `W` (u16) |
//! | 22 | 2 | height `H` (u16) |
//! | 24 | W·H | 8-bit grey pixels, row by row, top row first |
//! | 24+W·H | 4 | CRC-32 (ISO-HDLC) of bytes 0 .. 24+W·H |
//!
//! All integers and floats little-endian.

use std::io::{self, Read};
use std::time::Instant;

use image::GrayImage;

/// Record magic.
pub const FRAME_MAGIC: [u8; 4] = *b"MBF1";
/// Header bytes before the pixels.
pub const FRAME_HEADER: usize = 24;

/// One grey-level frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Frame counter of the source (a gap is a dropped frame).
    pub index: u64,
    /// Capture time on the source clock (s).
    pub t: f64,
    /// The pixels.
    pub image: GrayImage,
    /// When the host had the whole frame (the start of the control-loop latency).
    pub received: Instant,
}

/// Encodes a frame as one stream record.
pub fn encode_frame(f: &Frame) -> Vec<u8> {
    let (w, h) = f.image.dimensions();
    let mut out = Vec::with_capacity(FRAME_HEADER + (w * h) as usize + 4);
    out.extend_from_slice(&FRAME_MAGIC);
    out.extend_from_slice(&f.index.to_le_bytes());
    out.extend_from_slice(&f.t.to_le_bytes());
    out.extend_from_slice(&(w as u16).to_le_bytes());
    out.extend_from_slice(&(h as u16).to_le_bytes());
    out.extend_from_slice(f.image.as_raw());
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// What reading one record gave.
#[derive(Debug)]
pub enum ReadFrame {
    /// A good frame.
    Frame(Frame),
    /// A record that failed its checksum or had an impossible header (skipped; the reader
    /// resynchronises on the next magic).
    Corrupt,
}

/// Reads the next record from `r`, scanning forward to the next magic first.
///
/// I/O errors (including read timeouts) are returned as they are.
pub fn read_frame(r: &mut impl Read, max_side: u32) -> io::Result<ReadFrame> {
    let mut win = [0u8; 4];
    r.read_exact(&mut win)?;
    while win != FRAME_MAGIC {
        let mut b = [0u8; 1];
        r.read_exact(&mut b)?;
        win.rotate_left(1);
        win[3] = b[0];
    }
    let mut head = [0u8; FRAME_HEADER];
    head[..4].copy_from_slice(&FRAME_MAGIC);
    r.read_exact(&mut head[4..])?;
    let index = u64::from_le_bytes(head[4..12].try_into().unwrap());
    let t = f64::from_le_bytes(head[12..20].try_into().unwrap());
    let w = u16::from_le_bytes([head[20], head[21]]) as u32;
    let h = u16::from_le_bytes([head[22], head[23]]) as u32;
    if w == 0 || h == 0 || w > max_side || h > max_side || !t.is_finite() {
        return Ok(ReadFrame::Corrupt);
    }
    let mut body = vec![0u8; (w * h) as usize + 4];
    r.read_exact(&mut body)?;
    let n = body.len() - 4;
    let crc = u32::from_le_bytes(body[n..].try_into().unwrap());
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&head);
    hasher.update(&body[..n]);
    if hasher.finalize() != crc {
        return Ok(ReadFrame::Corrupt);
    }
    body.truncate(n);
    Ok(ReadFrame::Frame(Frame {
        index,
        t,
        image: GrayImage::from_raw(w, h, body).expect("size checked"),
        received: Instant::now(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_resync_after_corruption() {
        let img = GrayImage::from_fn(7, 5, |x, y| image::Luma([(x * 10 + y) as u8]));
        let a = Frame {
            index: 3,
            t: 0.05,
            image: img.clone(),
            received: Instant::now(),
        };
        let b = Frame {
            index: 4,
            t: 0.0666,
            image: img,
            received: Instant::now(),
        };
        let mut bytes = vec![1, 2, 3];
        let mut ea = encode_frame(&a);
        ea[30] ^= 0xFF;
        bytes.extend(ea);
        bytes.extend(encode_frame(&b));
        let mut r = &bytes[..];
        assert!(matches!(
            read_frame(&mut r, 100).unwrap(),
            ReadFrame::Corrupt
        ));
        match read_frame(&mut r, 100).unwrap() {
            ReadFrame::Frame(f) => assert_eq!((f.index, f.t, &f.image), (b.index, b.t, &b.image)),
            ReadFrame::Corrupt => panic!("second frame lost"),
        }
    }
}
