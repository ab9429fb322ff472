//! The mutation operators. Text operators see numbers, words and lines; binary operators see
//! little-endian integer fields (MCAP's lengths, opcodes, counts and CRCs are all such fields).

use rand::RngExt;
use rand::rngs::ChaCha8Rng;

/// Numbers at the edges of what parsers expect: zero and signs, tiny and huge magnitudes,
/// integer type limits and one past them, non-finite spellings.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-0.0",
    "1",
    "-1",
    "-3",
    "0.5",
    "3",
    "0.001",
    "1e-9",
    "1e-300",
    "4.9e-324",
    "1e9",
    "1e12",
    "1e18",
    "1e300",
    "1e309",
    "-1e300",
    "1.7976931348623157e308",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "+inf",
    "65536",
    "100000",
    "1000000",
    "5000000000",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "",
];

/// Bytes that often change a parser's path: separators, quotes, brackets, line ends, controls.
const PUNCTUATION: &[&[u8]] = &[
    b"=",
    b":",
    b"[",
    b"]",
    b"[[",
    b"\"",
    b"'",
    b"\n",
    b"\r\n",
    b"\t",
    b",",
    b"-",
    b"#",
    b"{",
    b"}",
    b"\0",
    b"\x1b[31m",
    b"\xef\xbb\xbf",
    b"\xff\xfe",
    b"EOF\n",
];

/// Integers written over binary fields.
const FIELDS: &[u64] = &[
    0,
    1,
    2,
    7,
    8,
    0x7f,
    0x80,
    0xff,
    0xffff,
    1 << 20,
    1 << 31,
    u32::MAX as u64,
    1 << 32,
    i64::MAX as u64,
    u64::MAX,
];

/// A uniform index below `n` (`n` > 0).
pub(crate) fn index(rng: &mut ChaCha8Rng, n: usize) -> usize {
    rng.random_range(0..n)
}

/// Applies one text mutation to `s`.
pub(crate) fn text(s: &mut Vec<u8>, rng: &mut ChaCha8Rng, dictionary: &[&str]) {
    match rng.random_range(0..14) {
        0..=3 => replace_number(s, rng),
        4 => replace_word(s, rng, dictionary),
        5 => delete_line(s, rng),
        6 => duplicate_line(s, rng),
        7 => swap_lines(s, rng),
        8 => insert_dictionary_line(s, rng, dictionary),
        9 => truncate(s, rng),
        10 => {
            let what = PUNCTUATION[index(rng, PUNCTUATION.len())];
            insert_at_random(s, rng, what)
        }
        11 => flip_bit(s, rng),
        12 => delete_span(s, rng),
        _ => negate_or_scale_number(s, rng),
    }
}

/// Applies one binary mutation to `b`.
pub(crate) fn binary(b: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    match rng.random_range(0..8) {
        0 | 1 => flip_bit(b, rng),
        2 | 3 => overwrite_field(b, rng),
        4 => nudge_field(b, rng),
        5 => truncate(b, rng),
        6 => delete_span(b, rng),
        _ => duplicate_span(b, rng),
    }
}

/// Byte ranges of the numbers in `s` (a digit run with its sign, point and exponent).
fn number_spans(s: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < s.len() {
        let starts = s[i].is_ascii_digit()
            || (matches!(s[i], b'-' | b'+' | b'.') && s.get(i + 1).is_some_and(u8::is_ascii_digit));
        let glued = i > 0 && (s[i - 1].is_ascii_alphanumeric() || s[i - 1] == b'_');
        if starts && !glued {
            let start = i;
            i += 1;
            while i < s.len()
                && (s[i].is_ascii_digit() || matches!(s[i], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn word_spans(s: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < s.len() {
        if s[i].is_ascii_alphabetic() || s[i] == b'_' {
            let start = i;
            while i < s.len() && (s[i].is_ascii_alphanumeric() || s[i] == b'_') {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn line_spans(s: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for (i, &b) in s.iter().enumerate() {
        if b == b'\n' {
            spans.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < s.len() {
        spans.push((start, s.len()));
    }
    spans
}

fn replace_number(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let spans = number_spans(s);
    if spans.is_empty() {
        let what = NUMBERS[index(rng, NUMBERS.len())].as_bytes();
        return insert_at_random(s, rng, what);
    }
    let (a, b) = spans[index(rng, spans.len())];
    let with = NUMBERS[index(rng, NUMBERS.len())].as_bytes();
    s.splice(a..b, with.iter().copied());
}

fn negate_or_scale_number(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let spans = number_spans(s);
    if spans.is_empty() {
        return;
    }
    let (a, b) = spans[index(rng, spans.len())];
    match rng.random_range(0..3) {
        0 => s.insert(a, b'-'),
        1 => s.splice(b..b, b"e300".iter().copied()).for_each(drop),
        _ => s.splice(b..b, b"000000000".iter().copied()).for_each(drop),
    }
}

fn replace_word(s: &mut Vec<u8>, rng: &mut ChaCha8Rng, dictionary: &[&str]) {
    let spans = word_spans(s);
    if spans.is_empty() || dictionary.is_empty() {
        return;
    }
    let (a, b) = spans[index(rng, spans.len())];
    let with = dictionary[index(rng, dictionary.len())].as_bytes();
    s.splice(a..b, with.iter().copied());
}

fn delete_line(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let lines = line_spans(s);
    if !lines.is_empty() {
        let (a, b) = lines[index(rng, lines.len())];
        s.drain(a..b);
    }
}

fn duplicate_line(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let lines = line_spans(s);
    if lines.is_empty() {
        return;
    }
    let (a, b) = lines[index(rng, lines.len())];
    let line = s[a..b].to_vec();
    let copies = if rng.random_range(0..8) == 0 { 64 } else { 1 };
    for _ in 0..copies {
        s.splice(b..b, line.iter().copied());
    }
}

fn swap_lines(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    let lines = line_spans(s);
    if lines.len() < 2 {
        return;
    }
    let mut parts: Vec<Vec<u8>> = lines.iter().map(|&(a, b)| s[a..b].to_vec()).collect();
    let (i, j) = (index(rng, parts.len()), index(rng, parts.len()));
    parts.swap(i, j);
    *s = parts.concat();
}

fn insert_dictionary_line(s: &mut Vec<u8>, rng: &mut ChaCha8Rng, dictionary: &[&str]) {
    if dictionary.is_empty() {
        return;
    }
    let word = dictionary[index(rng, dictionary.len())];
    let number = NUMBERS[index(rng, NUMBERS.len())];
    let sep = [" = ", ": ", " "][index(rng, 3)];
    let line = format!("{word}{sep}{number}\n");
    let lines = line_spans(s);
    let at = if lines.is_empty() {
        0
    } else {
        lines[index(rng, lines.len())].0
    };
    s.splice(at..at, line.bytes());
}

fn insert_at_random(s: &mut Vec<u8>, rng: &mut ChaCha8Rng, what: &[u8]) {
    let at = rng.random_range(0..=s.len());
    s.splice(at..at, what.iter().copied());
}

fn truncate(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    if !s.is_empty() {
        let at = index(rng, s.len());
        s.truncate(at);
    }
}

fn flip_bit(s: &mut [u8], rng: &mut ChaCha8Rng) {
    if !s.is_empty() {
        let i = index(rng, s.len());
        s[i] ^= 1 << rng.random_range(0..8);
    }
}

fn delete_span(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    if s.is_empty() {
        return;
    }
    let a = index(rng, s.len());
    let len = rng.random_range(1..=64usize.min(s.len() - a));
    s.drain(a..a + len);
}

fn duplicate_span(s: &mut Vec<u8>, rng: &mut ChaCha8Rng) {
    if s.is_empty() {
        return;
    }
    let a = index(rng, s.len());
    let len = rng.random_range(1..=256usize.min(s.len() - a));
    let span = s[a..a + len].to_vec();
    let at = rng.random_range(0..=s.len());
    s.splice(at..at, span);
}

/// Overwrites 1, 2, 4 or 8 bytes at a random offset with a boundary integer, little-endian.
fn overwrite_field(s: &mut [u8], rng: &mut ChaCha8Rng) {
    let width = [1usize, 2, 4, 8][index(rng, 4)];
    if s.len() < width {
        return;
    }
    let at = index(rng, s.len() - width + 1);
    let v = FIELDS[index(rng, FIELDS.len())].to_le_bytes();
    s[at..at + width].copy_from_slice(&v[..width]);
}

/// Adds a small signed delta to a 4- or 8-byte little-endian field (off-by-one lengths).
fn nudge_field(s: &mut [u8], rng: &mut ChaCha8Rng) {
    let width = [4usize, 8][index(rng, 2)];
    if s.len() < width {
        return;
    }
    let at = index(rng, s.len() - width + 1);
    let mut buf = [0u8; 8];
    buf[..width].copy_from_slice(&s[at..at + width]);
    let delta = [1i64, -1, 8, -8, 4096][index(rng, 5)];
    let v = u64::from_le_bytes(buf).wrapping_add(delta as u64);
    s[at..at + width].copy_from_slice(&v.to_le_bytes()[..width]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn numbers_are_found_with_sign_and_exponent_but_not_inside_names() {
        let s = b"x1 = -2.5e3\nDIMENSION: 17\nEUC_2D";
        let spans: Vec<&[u8]> = number_spans(s).iter().map(|&(a, b)| &s[a..b]).collect();
        assert_eq!(spans, vec![&b"-2.5e3"[..], &b"17"[..]]);
    }

    #[test]
    fn mutations_are_deterministic_for_a_seed() {
        let run = || {
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            let mut s = b"NAME: a\nDIMENSION: 3\nNODE_COORD_SECTION\n1 0 0\n".to_vec();
            for _ in 0..50 {
                text(&mut s, &mut rng, &["EOF", "DIMENSION"]);
            }
            s
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn binary_mutations_never_panic_on_tiny_inputs() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for len in 0..12 {
            for _ in 0..200 {
                let mut b = vec![0xAB; len];
                binary(&mut b, &mut rng);
                text(&mut b, &mut rng, &[]);
            }
        }
    }
}
