//! The shapes of fuzz inputs: text formats, binary formats, and bundles of named files (a
//! scenario's TOML with its PNG layers). Each knows how to mutate itself and how to round-trip
//! through bytes, so a failing case can be stored and replayed.

use rand::rngs::ChaCha8Rng;

use crate::mutate;

/// A fuzz input: mutable in place, stored as bytes.
pub trait FuzzInput: Clone {
    /// Applies one structure-aware mutation. `dictionary` holds tokens of the format (keywords,
    /// key names) that mutations may insert.
    fn mutate(&mut self, rng: &mut ChaCha8Rng, dictionary: &[&str]);
    /// The bytes stored for this input.
    fn to_bytes(&self) -> Vec<u8>;
    /// The input stored as `bytes`, or `None` when they are not one of this shape.
    fn from_bytes(bytes: &[u8]) -> Option<Self>;
}

/// A text format (TSPLIB, CSV, TOML). Mutations work on tokens and lines; an input may stop
/// being valid UTF-8 (byte flips), which is itself a case worth testing.
#[derive(Clone, Debug)]
pub struct Text(pub Vec<u8>);

/// A binary format (MCAP). Mutations overwrite fields with boundary integers, flip bits, cut and
/// splice.
#[derive(Clone, Debug)]
pub struct Binary(pub Vec<u8>);

/// Named files that form one input, e.g. `scenario.toml` and its PNG layers. A mutation picks
/// one file and mutates it as text or binary by its extension.
#[derive(Clone, Debug)]
pub struct Bundle(pub Vec<(String, Vec<u8>)>);

/// Inputs beyond this size are cut: large inputs slow every case and find nothing a small one
/// would not.
pub const MAX_INPUT_BYTES: usize = 1 << 20;

impl FuzzInput for Text {
    fn mutate(&mut self, rng: &mut ChaCha8Rng, dictionary: &[&str]) {
        mutate::text(&mut self.0, rng, dictionary);
        self.0.truncate(MAX_INPUT_BYTES);
    }
    fn to_bytes(&self) -> Vec<u8> {
        self.0.clone()
    }
    fn from_bytes(bytes: &[u8]) -> Option<Self> {
        Some(Self(bytes.to_vec()))
    }
}

impl FuzzInput for Binary {
    fn mutate(&mut self, rng: &mut ChaCha8Rng, _dictionary: &[&str]) {
        mutate::binary(&mut self.0, rng);
        self.0.truncate(MAX_INPUT_BYTES);
    }
    fn to_bytes(&self) -> Vec<u8> {
        self.0.clone()
    }
    fn from_bytes(bytes: &[u8]) -> Option<Self> {
        Some(Self(bytes.to_vec()))
    }
}

impl FuzzInput for Bundle {
    fn mutate(&mut self, rng: &mut ChaCha8Rng, dictionary: &[&str]) {
        if self.0.is_empty() {
            return;
        }
        let k = mutate::index(rng, self.0.len());
        let (name, bytes) = &mut self.0[k];
        if name.ends_with(".png") {
            mutate::binary(bytes, rng);
        } else {
            mutate::text(bytes, rng, dictionary);
        }
        bytes.truncate(MAX_INPUT_BYTES);
    }

    /// `name\0length(u32 LE)bytes` per file.
    fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        for (name, bytes) in &self.0 {
            out.extend_from_slice(name.as_bytes());
            out.push(0);
            out.extend_from_slice(&(bytes.len() as u32).to_le_bytes());
            out.extend_from_slice(bytes);
        }
        out
    }

    fn from_bytes(mut bytes: &[u8]) -> Option<Self> {
        let mut files = Vec::new();
        while !bytes.is_empty() {
            let end = bytes.iter().position(|&b| b == 0)?;
            let name = String::from_utf8(bytes[..end].to_vec()).ok()?;
            let rest = &bytes[end + 1..];
            let len = u32::from_le_bytes(rest.get(..4)?.try_into().ok()?) as usize;
            let body = rest.get(4..4 + len)?;
            files.push((name, body.to_vec()));
            bytes = &rest[4 + len..];
        }
        Some(Self(files))
    }
}
