//! Every chunk compression MCAP defines (zstd, lz4, none) is read, and gives the same replay;
//! a compression MCAP does not define is named, without a repair hint.

mod common;

use common::*;
use strider_log::LogReplay;

#[test]
fn every_chunk_compression_replays_to_the_same_map() {
    let original = dir().join("compression-original.mcap");
    simple_log(&original);
    let mut reference = LogReplay::open(&original, &config(""), &gaits()).unwrap();
    let expected = drain(&mut reference).unwrap();
    let expected_map = map_of(&expected);
    for (name, compression, marker) in [
        ("zstd", Some(mcap::Compression::Zstd), &b"zstd"[..]),
        ("lz4", Some(mcap::Compression::Lz4), &b"lz4"[..]),
        ("none", None, &b""[..]),
    ] {
        let p = dir().join(format!("compression-{name}.mcap"));
        recompress(&original, &p, compression);
        let bytes = std::fs::read(&p).unwrap();
        if !marker.is_empty() {
            assert!(
                bytes.windows(marker.len()).any(|w| w == marker),
                "{name}: the chunks name their compression"
            );
        }
        let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
        let got = drain(&mut r).unwrap();
        assert_eq!(got.poses, expected.poses, "{name}");
        assert_eq!(cloud_bits(&got), cloud_bits(&expected), "{name}");
        assert_eq!(r.stats(), reference.stats(), "{name}");
        assert_same_map(&map_of(&got), &expected_map, name);
    }
}

#[test]
fn an_unknown_compression_is_named_without_a_repair_hint() {
    let original = dir().join("compression-src.mcap");
    simple_log(&original);
    let p = dir().join("compression-bz2.mcap");
    recompress(&original, &p, Some(mcap::Compression::Lz4));
    // The compression string of every chunk (and chunk index) record: length 3, "lz4".
    let mut bytes = std::fs::read(&p).unwrap();
    let from = b"\x03\0\0\0lz4";
    let mut patched = 0;
    for k in 0..bytes.len() - from.len() {
        if &bytes[k..k + from.len()] == from {
            bytes[k + 4..k + 7].copy_from_slice(b"bz2");
            patched += 1;
        }
    }
    assert!(patched > 1, "several chunks");
    std::fs::write(&p, &bytes).unwrap();
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("compression-bz2.mcap")
            && e.contains("compressed with \"bz2\", which this reader does not decompress")
            && e.contains("zstd, lz4 and uncompressed"),
        "{e}"
    );
    assert!(
        !e.contains("recover") && !e.contains("repair") && !e.contains("corrupt"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}
