//! Reading and writing the three PNG layers with exact bit depths (via the `png` crate, which
//! keeps palette indices and 16-bit samples untouched).
//!
//! Buffers here are in image order (top row first); flipping them to the model's row 0 = lowest y
//! is the scenario loader's business, not this module's.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use png::{BitDepth, ColorType};

use crate::error::ScenarioError;
use crate::layers::LayerSource;
use crate::validate::check_world_size;

/// A decoded image: size and one sample per pixel (or three for RGB), top row first.
pub(crate) struct Image<T> {
    pub width: u32,
    pub height: u32,
    pub data: Vec<T>,
}

/// "8-bit RGB", "16-bit grayscale", "4-bit indexed", …
fn describe(color: ColorType, depth: BitDepth) -> String {
    let bits = match depth {
        BitDepth::One => 1,
        BitDepth::Two => 2,
        BitDepth::Four => 4,
        BitDepth::Eight => 8,
        BitDepth::Sixteen => 16,
    };
    let kind = match color {
        ColorType::Grayscale => "grayscale",
        ColorType::Rgb => "RGB",
        ColorType::Indexed => "indexed",
        ColorType::GrayscaleAlpha => "grayscale+alpha",
        ColorType::Rgba => "RGBA",
    };
    format!("{bits}-bit {kind}")
}

/// Raw decoded PNG: header and the packed rows.
struct Raw {
    width: u32,
    height: u32,
    color: ColorType,
    depth: BitDepth,
    line_size: usize,
    buf: Vec<u8>,
    /// Where the layer came from, for messages.
    path: PathBuf,
}

/// Bytes the PNG decoder may allocate besides the image itself (its row buffers, the
/// decompressor's window and ancillary chunks such as ICC profiles): far above what a layer of
/// [`crate::validate::MAX_WORLD_CELLS`] pixels needs, far below the machine's memory.
const DECODER_LIMIT_BYTES: usize = 64 << 20;

/// Decodes layer `name` of `src`, refusing before any allocation an image whose header claims
/// more than [`crate::validate::MAX_WORLD_CELLS`] pixels.
fn read_raw(src: &dyn LayerSource, name: &str, what: &str) -> Result<Raw, ScenarioError> {
    let path = src.path(name);
    let file = src.open(name).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            ScenarioError::MissingFile {
                path: path.clone(),
                what: what.to_string(),
            }
        } else {
            ScenarioError::Read {
                path: path.clone(),
                source: e,
            }
        }
    })?;
    let png_err = |e: png::DecodingError| ScenarioError::Png {
        path: path.clone(),
        message: e.to_string(),
    };
    let mut decoder = png::Decoder::new_with_limits(
        file,
        png::Limits {
            bytes: DECODER_LIMIT_BYTES,
        },
    );
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(png_err)?;
    let (width, height) = (reader.info().width, reader.info().height);
    check_world_size(width, height).map_err(|source| ScenarioError::Param {
        path: path.clone(),
        source,
    })?;
    let too_large = || ScenarioError::Png {
        path: path.clone(),
        message: "image too large".into(),
    };
    let size = reader.output_buffer_size().ok_or_else(too_large)?;
    let mut buf = Vec::new();
    buf.try_reserve_exact(size).map_err(|_| too_large())?;
    buf.resize(size, 0);
    let info = reader.next_frame(&mut buf).map_err(png_err)?;
    if info.width == 0 || info.height == 0 {
        return Err(ScenarioError::Png {
            path: path.clone(),
            message: "empty image".into(),
        });
    }
    Ok(Raw {
        width: info.width,
        height: info.height,
        color: info.color_type,
        depth: info.bit_depth,
        line_size: info.line_size,
        buf,
        path,
    })
}

fn wrong(expected: &str, raw: &Raw) -> ScenarioError {
    ScenarioError::PngFormat {
        path: raw.path.clone(),
        expected: expected.to_string(),
        found: describe(raw.color, raw.depth),
    }
}

/// Reads an 8-bit RGB image (the colour layer).
pub(crate) fn read_rgb8(
    src: &dyn LayerSource,
    name: &str,
    what: &str,
) -> Result<Image<[u8; 3]>, ScenarioError> {
    let raw = read_raw(src, name, what)?;
    if raw.color != ColorType::Rgb || raw.depth != BitDepth::Eight {
        return Err(wrong("8-bit RGB", &raw));
    }
    let (w, h) = (raw.width as usize, raw.height as usize);
    let mut data = Vec::with_capacity(w * h);
    for r in 0..h {
        let row = &raw.buf[r * raw.line_size..r * raw.line_size + 3 * w];
        data.extend(row.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
    }
    Ok(Image {
        width: raw.width,
        height: raw.height,
        data,
    })
}

/// Reads a 16-bit grayscale image (the elevation layer).
pub(crate) fn read_gray16(
    src: &dyn LayerSource,
    name: &str,
    what: &str,
) -> Result<Image<u16>, ScenarioError> {
    let raw = read_raw(src, name, what)?;
    if raw.color != ColorType::Grayscale || raw.depth != BitDepth::Sixteen {
        return Err(wrong("16-bit grayscale", &raw));
    }
    let (w, h) = (raw.width as usize, raw.height as usize);
    let mut data = Vec::with_capacity(w * h);
    for r in 0..h {
        let row = &raw.buf[r * raw.line_size..r * raw.line_size + 2 * w];
        data.extend(
            row.chunks_exact(2)
                .map(|c| u16::from_be_bytes([c[0], c[1]])),
        );
    }
    Ok(Image {
        width: raw.width,
        height: raw.height,
        data,
    })
}

/// Reads an index image (the terrain layer): 8-bit grayscale (the sample is the index) or
/// indexed/palette of 1, 2, 4 or 8 bits (the palette index is the index; palette colours are
/// ignored).
pub(crate) fn read_index8(
    src: &dyn LayerSource,
    name: &str,
    what: &str,
) -> Result<Image<u8>, ScenarioError> {
    let raw = read_raw(src, name, what)?;
    let bits: usize = match (raw.color, raw.depth) {
        (ColorType::Grayscale, BitDepth::Eight) => 8,
        (ColorType::Indexed, BitDepth::One) => 1,
        (ColorType::Indexed, BitDepth::Two) => 2,
        (ColorType::Indexed, BitDepth::Four) => 4,
        (ColorType::Indexed, BitDepth::Eight) => 8,
        _ => return Err(wrong("8-bit grayscale or indexed (palette)", &raw)),
    };
    let (w, h) = (raw.width as usize, raw.height as usize);
    let mask = ((1u16 << bits) - 1) as u8;
    let mut data = Vec::with_capacity(w * h);
    for r in 0..h {
        let row = &raw.buf[r * raw.line_size..(r + 1) * raw.line_size];
        for x in 0..w {
            let bit = x * bits;
            let shift = 8 - bits - (bit % 8);
            data.push((row[bit / 8] >> shift) & mask);
        }
    }
    Ok(Image {
        width: raw.width,
        height: raw.height,
        data,
    })
}

fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    color: ColorType,
    depth: BitDepth,
    bytes: &[u8],
) -> Result<(), ScenarioError> {
    let file = File::create(path).map_err(|e| ScenarioError::Write {
        path: path.to_path_buf(),
        source: e,
    })?;
    let enc_err = |e: png::EncodingError| ScenarioError::Png {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let mut enc = png::Encoder::new(BufWriter::new(file), width, height);
    enc.set_color(color);
    enc.set_depth(depth);
    let mut writer = enc.write_header().map_err(enc_err)?;
    writer.write_image_data(bytes).map_err(enc_err)?;
    writer.finish().map_err(enc_err)
}

/// Writes an 8-bit RGB image (top row first).
pub(crate) fn write_rgb8(
    path: &Path,
    width: u32,
    height: u32,
    data: &[[u8; 3]],
) -> Result<(), ScenarioError> {
    let bytes: Vec<u8> = data.iter().flatten().copied().collect();
    write_png(path, width, height, ColorType::Rgb, BitDepth::Eight, &bytes)
}

/// Writes a 16-bit grayscale image (top row first).
pub(crate) fn write_gray16(
    path: &Path,
    width: u32,
    height: u32,
    data: &[u16],
) -> Result<(), ScenarioError> {
    let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_be_bytes()).collect();
    write_png(
        path,
        width,
        height,
        ColorType::Grayscale,
        BitDepth::Sixteen,
        &bytes,
    )
}

/// Writes an 8-bit grayscale image (top row first).
pub(crate) fn write_gray8(
    path: &Path,
    width: u32,
    height: u32,
    data: &[u8],
) -> Result<(), ScenarioError> {
    write_png(
        path,
        width,
        height,
        ColorType::Grayscale,
        BitDepth::Eight,
        data,
    )
}
