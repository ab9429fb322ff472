//! The line-and-token cursor of the reader: header lines are read whole, section data token by
//! token across lines.

use super::TsplibError;

/// Line-and-token cursor over the file text.
pub(super) struct Lexer<'a> {
    lines: Vec<&'a str>,
    /// Index of the next line to read.
    next: usize,
    /// Tokens left on the line last loaded by `token()`, with its number.
    pending: Vec<&'a str>,
    pending_line: usize,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().collect(),
            next: 0,
            pending: Vec::new(),
            pending_line: 0,
        }
    }

    /// Number of the last line (for end-of-file errors).
    pub(super) fn last_line(&self) -> usize {
        self.lines.len().max(1)
    }

    /// Next non-blank line, trimmed, with its 1-based number.
    pub(super) fn line(&mut self) -> Option<(&'a str, usize)> {
        debug_assert!(self.pending.is_empty());
        while self.next < self.lines.len() {
            let l = self.lines[self.next].trim();
            self.next += 1;
            if !l.is_empty() {
                return Some((l, self.next));
            }
        }
        None
    }

    /// Peeks the next token (possibly on a later line) without consuming it.
    pub(super) fn peek(&mut self) -> Option<(&'a str, usize)> {
        while self.pending.is_empty() {
            if self.next >= self.lines.len() {
                return None;
            }
            let l = self.lines[self.next];
            self.next += 1;
            self.pending = l.split_whitespace().rev().collect();
            self.pending_line = self.next;
        }
        self.pending.last().map(|t| (*t, self.pending_line))
    }

    pub(super) fn token(&mut self) -> Option<(&'a str, usize)> {
        let t = self.peek()?;
        self.pending.pop();
        Some(t)
    }

    /// Ends token mode: the rest of the current line must be empty.
    pub(super) fn end_tokens(&mut self) -> Result<(), TsplibError> {
        if let Some(t) = self.pending.last() {
            return Err(TsplibError::Syntax {
                line: self.pending_line,
                msg: format!("unexpected extra value '{t}'"),
            });
        }
        Ok(())
    }

    /// Reads `count` numbers of a section.
    pub(super) fn numbers(
        &mut self,
        count: usize,
        section: &str,
    ) -> Result<Vec<(f64, usize)>, TsplibError> {
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let Some((t, line)) = self.peek() else {
                return Err(TsplibError::Truncated {
                    line: self.last_line(),
                    section: section.to_string(),
                    expected: count,
                    found: out.len(),
                });
            };
            match t.parse::<f64>() {
                Ok(x) if x.is_finite() => {
                    self.pending.pop();
                    out.push((x, line));
                }
                _ => {
                    if is_keyword(t) {
                        return Err(TsplibError::Truncated {
                            line,
                            section: section.to_string(),
                            expected: count,
                            found: out.len(),
                        });
                    }
                    return Err(TsplibError::Syntax {
                        line,
                        msg: format!("'{t}' is not a number in {section}"),
                    });
                }
            }
        }
        Ok(out)
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
