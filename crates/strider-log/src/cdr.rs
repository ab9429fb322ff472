//! The ROS 2 wire format: OMG CDR (XCDR1) with its 4-byte encapsulation header, as rmw
//! implementations put it into MCAP's `cdr` message encoding.
//!
//! Encoding and decoding go through the [`cdr`] crate with our own serde structs (the message
//! types of the `ros2` module, which builds on this one). Three things are done by hand, for
//! safety and speed on untrusted input:
//!
//! * **Strings** ([`RosString`]) are decoded as a `sequence<uint8>` (the same bytes on the wire:
//!   a `u32` length that counts the terminating NUL, then the bytes). `cdr` 0.2's own string
//!   decoder allocates the announced length before checking that the bytes exist, so one
//!   corrupted length would ask for up to 4 GiB; serde's sequence visitor grows as bytes
//!   actually arrive.
//! * **Fixed arrays longer than 32** ([`Cov36`], the 6 × 6 covariances) have no serde impl.
//! * **Large byte arrays** (`PointCloud2.data`) are sliced directly out of the message after the
//!   serde-decoded prefix ([`Decoder::bytes`]), so a cloud's payload is neither copied nor
//!   decoded byte by byte.
//!
//! Alignment is relative to the first byte after the encapsulation header (CDR's rule, which
//! `cdr` applies by restarting its position counter there): a `u32` after a `u8` skips three
//! padding bytes, an `f64` starts on a multiple of 8.

use serde::de::{DeserializeOwned, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Errors of the CDR codec. Offsets count from the start of the message (the encapsulation
/// header included).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CdrError {
    /// Fewer than 4 bytes: no encapsulation header.
    #[error("{len} bytes: too short for the 4-byte CDR encapsulation header")]
    NoHeader {
        /// The message length.
        len: usize,
    },
    /// An encapsulation other than plain CDR (e.g. PL_CDR or XCDR2).
    #[error(
        "unsupported CDR encapsulation {0:#06x} (plain CDR_LE 0x0001 and CDR_BE 0x0000 are read)"
    )]
    Encapsulation(u16),
    /// The payload did not match the message definition.
    #[error("malformed at byte {offset}: {reason}")]
    Malformed {
        /// Byte offset at which decoding stopped.
        offset: usize,
        /// What was wrong.
        reason: String,
    },
    /// Encoding failed (a sequence longer than `u32::MAX`, …).
    #[error("cannot encode: {0}")]
    Encode(String),
}

/// Size of the encapsulation header.
pub const HEADER_LEN: usize = 4;

/// Byte order of a CDR payload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Endian {
    /// CDR_LE (what every ROS 2 rmw on x86 and ARM writes).
    Little,
    /// CDR_BE.
    Big,
}

/// Reads the encapsulation header.
pub fn endianness(msg: &[u8]) -> Result<Endian, CdrError> {
    if msg.len() < HEADER_LEN {
        return Err(CdrError::NoHeader { len: msg.len() });
    }
    match (msg[0], msg[1]) {
        (0, 1) => Ok(Endian::Little),
        (0, 0) => Ok(Endian::Big),
        (a, b) => Err(CdrError::Encapsulation(u16::from_be_bytes([a, b]))),
    }
}

/// Encodes `value` as CDR_LE with the encapsulation header.
pub fn encode<T: Serialize + ?Sized>(value: &T) -> Result<Vec<u8>, CdrError> {
    cdr::serialize::<_, _, cdr::CdrLe>(value, cdr::Infinite)
        .map_err(|e| CdrError::Encode(e.to_string()))
}

/// Decodes a whole message of type `T` (trailing bytes, e.g. rmw's alignment padding, are
/// ignored as ROS 2 does).
pub fn decode<T: DeserializeOwned>(msg: &[u8]) -> Result<T, CdrError> {
    Decoder::new(msg)?.read::<T>()
}

/// A cursor over one CDR message: serde-decoded parts and hand-read byte arrays in sequence.
pub struct Decoder<'a> {
    msg: &'a [u8],
    /// Position relative to the start of the message.
    pos: usize,
    endian: Endian,
}

impl<'a> Decoder<'a> {
    /// A decoder positioned after the encapsulation header.
    pub fn new(msg: &'a [u8]) -> Result<Self, CdrError> {
        let endian = endianness(msg)?;
        Ok(Self {
            msg,
            pos: HEADER_LEN,
            endian,
        })
    }

    /// The byte order.
    pub fn endian(&self) -> Endian {
        self.endian
    }

    /// Current offset from the start of the message.
    pub fn offset(&self) -> usize {
        self.pos
    }

    fn malformed(&self, offset: usize, reason: impl Into<String>) -> CdrError {
        CdrError::Malformed {
            offset,
            reason: reason.into(),
        }
    }

    /// Decodes the next `T` with serde. Must start at a position where CDR alignment restarts
    /// consistently: the message start, or any offset (alignment is kept relative to the
    /// header, so continuing after [`Decoder::bytes`] is correct too).
    pub fn read<T: DeserializeOwned>(&mut self) -> Result<T, CdrError> {
        let body_pos = self.pos - HEADER_LEN;
        // `cdr` aligns relative to its own position counter, which starts at 0: feed it the
        // body from the last 8-byte boundary (relative to the body start) and skip the bytes
        // up to the current position with a padding read, so every alignment is the body's.
        let base = body_pos & !7;
        let skip = body_pos - base;
        let mut rest = &self.msg[HEADER_LEN + base..];
        let before = rest.len();
        // Padding reads through the deserializer advance its position counter too.
        macro_rules! run {
            ($e:ty) => {{
                let mut de = cdr::Deserializer::<_, _, $e>::new(&mut rest, cdr::Infinite);
                (0..skip)
                    .try_for_each(|_| u8::deserialize(&mut de).map(drop))
                    .and_then(|()| T::deserialize(&mut de))
            }};
        }
        let result: Result<T, cdr::Error> = match self.endian {
            Endian::Little => run!(cdr::LittleEndian),
            Endian::Big => run!(cdr::BigEndian),
        };
        let at = HEADER_LEN + base + (before - rest.len());
        match result {
            Ok(v) => {
                self.pos = at;
                Ok(v)
            }
            Err(e) => Err(self.malformed(at, describe(&e))),
        }
    }

    /// Reads a `sequence<uint8>` (a `u32` count aligned to 4, then the bytes) as a slice of
    /// the message, checking that the bytes exist before using the count.
    pub fn bytes(&mut self) -> Result<&'a [u8], CdrError> {
        let n = self.u32()? as usize;
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.msg.len())
            .ok_or_else(|| {
                self.malformed(
                    self.pos,
                    format!(
                        "byte array of {n} bytes announced, {} left",
                        self.msg.len() - self.pos
                    ),
                )
            })?;
        let s = &self.msg[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// Reads a `sequence<float32>` (a `u32` count aligned to 4, then the elements, which need
    /// no further padding) as its element count and the slice of the message holding them,
    /// checking that the bytes exist before using the count; [`Decoder::f32_at`] reads one.
    pub fn float32s(&mut self) -> Result<(usize, &'a [u8]), CdrError> {
        let n = self.u32()? as usize;
        let end = n
            .checked_mul(4)
            .and_then(|len| self.pos.checked_add(len))
            .filter(|&e| e <= self.msg.len())
            .ok_or_else(|| {
                self.malformed(
                    self.pos,
                    format!(
                        "array of {n} float32 announced, {} bytes left",
                        self.msg.len() - self.pos
                    ),
                )
            })?;
        let s = &self.msg[self.pos..end];
        self.pos = end;
        Ok((n, s))
    }

    /// Element `k` of a `float32` array read with [`Decoder::float32s`], in the message's byte
    /// order; `None` past its end.
    pub fn f32_at(&self, data: &[u8], k: usize) -> Option<f32> {
        let b = data.get(k.checked_mul(4)?..)?.get(..4)?;
        let b = [b[0], b[1], b[2], b[3]];
        Some(match self.endian {
            Endian::Little => f32::from_le_bytes(b),
            Endian::Big => f32::from_be_bytes(b),
        })
    }

    /// Reads an aligned `u32`.
    pub fn u32(&mut self) -> Result<u32, CdrError> {
        let body = self.pos - HEADER_LEN;
        let start = self.pos + (4 - body % 4) % 4;
        let b = self
            .msg
            .get(start..start + 4)
            .ok_or_else(|| self.malformed(self.pos, "message ends inside a uint32"))?;
        let b = [b[0], b[1], b[2], b[3]];
        self.pos = start + 4;
        Ok(match self.endian {
            Endian::Little => u32::from_le_bytes(b),
            Endian::Big => u32::from_be_bytes(b),
        })
    }

    /// Reads a `bool` (one byte, 0 or 1).
    pub fn bool(&mut self) -> Result<bool, CdrError> {
        match self.msg.get(self.pos) {
            Some(&v @ (0 | 1)) => {
                self.pos += 1;
                Ok(v == 1)
            }
            Some(&v) => Err(self.malformed(self.pos, format!("bool byte {v} is neither 0 nor 1"))),
            None => Err(self.malformed(self.pos, "message ends before a bool")),
        }
    }
}

/// A short description of a `cdr` error (its I/O errors are all "ran out of bytes").
fn describe(e: &cdr::Error) -> String {
    match e {
        cdr::Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "message ends inside a field".into()
        }
        other => other.to_string(),
    }
}

/// A CDR string: UTF-8 bytes, on the wire a `u32` length counting a terminating NUL.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct RosString(pub String);

impl RosString {
    /// The text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl From<&str> for RosString {
    fn from(s: &str) -> Self {
        Self(s.to_string())
    }
}

impl Serialize for RosString {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.0)
    }
}

impl<'de> Deserialize<'de> for RosString {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // A string and a sequence<uint8> share their wire format; decoding the sequence
        // keeps the allocation proportional to the bytes actually present.
        let mut bytes = Vec::<u8>::deserialize(d)?;
        if bytes.last() == Some(&0) {
            bytes.pop();
        }
        String::from_utf8(bytes)
            .map(RosString)
            .map_err(|e| serde::de::Error::custom(format!("string is not UTF-8: {e}")))
    }
}

/// A byte array written with one `serialize_bytes` call (`sequence<uint8>` on the wire).
#[derive(Clone, Copy, Debug)]
pub struct Bytes<'a>(pub &'a [u8]);

impl Serialize for Bytes<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(self.0)
    }
}

/// `float64[36]`, a row-major 6 × 6 covariance (a fixed array: no length on the wire).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cov36(pub [f64; 36]);

impl Default for Cov36 {
    fn default() -> Self {
        Self([0.0; 36])
    }
}

impl Serialize for Cov36 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let mut t = s.serialize_tuple(36)?;
        for v in &self.0 {
            t.serialize_element(v)?;
        }
        t.end()
    }
}

impl<'de> Deserialize<'de> for Cov36 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Cov36;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("36 float64")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Cov36, A::Error> {
                let mut out = [0.0; 36];
                for (k, v) in out.iter_mut().enumerate() {
                    *v = seq
                        .next_element()?
                        .ok_or_else(|| serde::de::Error::invalid_length(k, &self))?;
                }
                Ok(Cov36(out))
            }
        }
        d.deserialize_tuple(36, V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Mixed {
        a: u8,
        b: u32,
        c: RosString,
        d: f64,
        e: Vec<u16>,
    }

    #[test]
    fn known_bytes_with_alignment() {
        let m = Mixed {
            a: 7,
            b: 0x0102_0304,
            c: "ab".into(),
            d: 1.5,
            e: vec![9],
        };
        let bytes = encode(&m).unwrap();
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            0, 1, 0, 0,             // CDR_LE encapsulation
            7, 0, 0, 0,             // u8 a, three bytes of padding before the u32
            4, 3, 2, 1,             // u32 b
            3, 0, 0, 0, b'a', b'b', 0, // string "ab": length 3 counts the NUL
            0,                      // one padding byte: the f64 starts at body offset 16
            0, 0, 0, 0, 0, 0, 0xf8, 0x3f, // f64 1.5
            1, 0, 0, 0, 9, 0,       // sequence<uint16> [9]
        ];
        assert_eq!(bytes, expected);
        assert_eq!(decode::<Mixed>(&bytes).unwrap(), m);
    }

    #[test]
    fn big_endian_decodes() {
        let m = Mixed {
            a: 1,
            b: 2,
            c: "x".into(),
            d: -3.25,
            e: vec![1, 2],
        };
        let be = cdr::serialize::<_, _, cdr::CdrBe>(&m, cdr::Infinite).unwrap();
        assert_eq!(endianness(&be).unwrap(), Endian::Big);
        assert_eq!(decode::<Mixed>(&be).unwrap(), m);
    }

    #[test]
    fn decoder_keeps_alignment_across_hand_read_parts() {
        // u8, then a byte array (aligned u32 count), then an f64 that must sit on a body offset
        // that is a multiple of 8.
        #[derive(Serialize)]
        struct W<'a> {
            a: u8,
            data: Bytes<'a>,
            x: f64,
        }
        let bytes = encode(&W {
            a: 1,
            data: Bytes(&[1, 2, 3]),
            x: 2.0,
        })
        .unwrap();
        let mut d = Decoder::new(&bytes).unwrap();
        assert_eq!(d.read::<u8>().unwrap(), 1);
        assert_eq!(d.bytes().unwrap(), &[1, 2, 3]);
        assert_eq!(d.read::<f64>().unwrap(), 2.0);
        assert_eq!(d.offset(), bytes.len());
    }

    #[test]
    fn huge_lengths_fail_without_allocating() {
        // A string announcing 4 GiB: an error, not an allocation.
        let msg = [0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, b'a'];
        let e = decode::<RosString>(&msg).unwrap_err();
        assert!(matches!(e, CdrError::Malformed { .. }), "{e}");
        let mut d = Decoder::new(&msg).unwrap();
        assert!(d.bytes().is_err());
    }

    #[test]
    fn header_errors() {
        assert_eq!(decode::<u8>(&[0, 1]), Err(CdrError::NoHeader { len: 2 }));
        assert_eq!(
            decode::<u8>(&[0, 3, 0, 0, 1]),
            Err(CdrError::Encapsulation(3))
        );
    }

    #[test]
    fn covariance_round_trip() {
        let mut c = Cov36::default();
        c.0[35] = 4.0;
        c.0[0] = 1.0;
        let b = encode(&c).unwrap();
        assert_eq!(b.len(), 4 + 36 * 8);
        assert_eq!(decode::<Cov36>(&b).unwrap(), c);
    }
}
