//! The line-and-token cursor of the reader: header lines are read whole, section data token by
//! token across lines. It holds no per-line or per-token tables, so its memory does not grow
//! with the file.

use std::str::{Lines, SplitWhitespace};

use super::TsplibError;

/// Largest magnitude of a non-integer-looking weight (`1e3`, `2.5`): 2⁵³, beyond which `f64`
/// no longer holds every integer.
const MAX_FLOAT_WEIGHT: f64 = 9_007_199_254_740_992.0;

/// Line-and-token cursor over the file text.
pub(super) struct Lexer<'a> {
    lines: Lines<'a>,
    /// Number of the last line taken from `lines` (0 before the first).
    line_no: usize,
    /// Length of the whole text: an upper bound for preallocations.
    text_len: usize,
    /// Tokens left on the line last loaded by `peek()`.
    tokens: Option<SplitWhitespace<'a>>,
    /// A token taken from `tokens` but not consumed.
    peeked: Option<&'a str>,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines(),
            line_no: 0,
            text_len: text.len(),
            tokens: None,
            peeked: None,
        }
    }

    /// Number of the last line read (for end-of-file errors).
    pub(super) fn last_line(&self) -> usize {
        self.line_no.max(1)
    }

    /// A capacity for `count` values read from the text: never more than the text can hold
    /// (a value and its separator take at least two bytes), whatever the header declared.
    pub(super) fn capacity(&self, count: usize) -> usize {
        count.min(self.text_len / 2 + 1)
    }

    /// Next non-blank line, trimmed, with its 1-based number.
    pub(super) fn line(&mut self) -> Option<(&'a str, usize)> {
        self.tokens = None;
        self.peeked = None;
        for l in self.lines.by_ref() {
            self.line_no += 1;
            let l = l.trim();
            if !l.is_empty() {
                return Some((l, self.line_no));
            }
        }
        None
    }

    /// Peeks the next token (possibly on a later line) without consuming it.
    pub(super) fn peek(&mut self) -> Option<(&'a str, usize)> {
        while self.peeked.is_none() {
            match self.tokens.as_mut().and_then(|t| t.next()) {
                Some(t) => self.peeked = Some(t),
                None => {
                    let l = self.lines.next()?;
                    self.line_no += 1;
                    self.tokens = Some(l.split_whitespace());
                }
            }
        }
        self.peeked.map(|t| (t, self.line_no))
    }

    pub(super) fn token(&mut self) -> Option<(&'a str, usize)> {
        let t = self.peek()?;
        self.peeked = None;
        Some(t)
    }

    /// Ends token mode: the rest of the current line must be empty.
    pub(super) fn end_tokens(&mut self) -> Result<(), TsplibError> {
        let rest = self
            .peeked
            .take()
            .or_else(|| self.tokens.as_mut().and_then(|t| t.next()));
        if let Some(t) = rest {
            return Err(TsplibError::Syntax {
                line: self.line_no,
                msg: format!("unexpected extra value '{t}'"),
            });
        }
        self.tokens = None;
        Ok(())
    }

    /// The next value of `section` (`found` of `expected` read so far) as a finite number.
    pub(super) fn number(
        &mut self,
        section: &str,
        expected: usize,
        found: usize,
    ) -> Result<(f64, usize), TsplibError> {
        let (t, line) = self.value_token(section, expected, found)?;
        match t.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok((x, line)),
            Ok(_) => Err(TsplibError::Syntax {
                line,
                msg: format!("'{t}' is not a finite number in {section}"),
            }),
            Err(_) => Err(TsplibError::Syntax {
                line,
                msg: format!("'{t}' is not a number in {section}"),
            }),
        }
    }

    /// The next value of `section` as an integer weight: an integer token, or a number of
    /// magnitude at most 2⁵³ rounded to the nearest integer.
    pub(super) fn integer(
        &mut self,
        section: &str,
        expected: usize,
        found: usize,
    ) -> Result<(i64, usize), TsplibError> {
        if let Some((t, line)) = self.peek()
            && let Ok(v) = t.parse::<i64>()
        {
            self.peeked = None;
            return Ok((v, line));
        }
        let (x, line) = self.number(section, expected, found)?;
        if x.abs() > MAX_FLOAT_WEIGHT {
            return Err(TsplibError::Syntax {
                line,
                msg: format!(
                    "value {x:e} in {section} is out of range: write integers, or numbers of \
                     magnitude at most 2^53"
                ),
            });
        }
        Ok((x.round() as i64, line))
    }

    /// Takes the next token of a section: a truncation error at the end of the text or at a
    /// keyword.
    fn value_token(
        &mut self,
        section: &str,
        expected: usize,
        found: usize,
    ) -> Result<(&'a str, usize), TsplibError> {
        let truncated = |line| TsplibError::Truncated {
            line,
            section: section.to_string(),
            expected,
            found,
            unit: "values",
        };
        let Some((t, line)) = self.peek() else {
            return Err(truncated(self.last_line()));
        };
        // `INF` and `NAN` read as numbers (and are refused as such), not as keywords.
        if t.parse::<f64>().is_err() && is_keyword(t) {
            return Err(truncated(line));
        }
        self.peeked = None;
        Ok((t, line))
    }
}

/// True for a TSPLIB keyword such as `EOF` or `GTSP_SET_SECTION:` (used to
/// tell a truncated section from a malformed value).
pub(super) fn is_keyword(t: &str) -> bool {
    let t = t.trim_end_matches(':');
    t.len() > 1
        && t.chars()
            .all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit())
        && t.starts_with(|c: char| c.is_ascii_uppercase())
}

/// True when a line starts like a number: a value of a section rather than a keyword.
pub(super) fn looks_numeric(line: &str) -> bool {
    line.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '-' | '+' | '.'))
}
