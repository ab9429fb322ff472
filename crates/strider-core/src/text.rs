//! Error text that is safe to print: messages often quote the input they reject, and an input
//! may hold line breaks, terminal escape sequences or other control characters.

/// `s` as one printable line: every run of whitespace that holds a line break becomes one space,
/// and every other control character is written as an escape (`\u{1b}`), so that quoting a
/// hostile input can neither break the line nor drive the terminal.
pub fn one_line(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut pending_space = false;
    for c in s.chars() {
        if c == '\n' || c == '\r' {
            pending_space = true;
            continue;
        }
        if pending_space {
            if !c.is_whitespace() {
                if !out.is_empty() {
                    out.push(' ');
                }
                pending_space = false;
            } else {
                continue;
            }
        }
        if c.is_control() && c != '\t' {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::one_line;

    #[test]
    fn line_breaks_collapse_and_controls_are_escaped() {
        assert_eq!(one_line("a\n   | b\r\nc"), "a | b c");
        assert_eq!(one_line("key\u{1b}[31m = 1"), "key\\u{1b}[31m = 1");
        assert_eq!(one_line("nul\0"), "nul\\u{0}");
        assert_eq!(one_line("\nlead"), "lead");
        assert_eq!(one_line("plain, ≥ 0.01 m"), "plain, ≥ 0.01 m");
    }
}
