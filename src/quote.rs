//! Input quoted in error messages. A message names what it refuses (a key, a token, an
//! option value), but what a file or a user gives can be megabytes long or hold control
//! bytes that a terminal would obey (escape sequences): quoted input is cut to a readable
//! length and everything not printable is escaped, so an error stays one short line.

use std::fmt::Write;

/// Characters of quoted input kept before the cut.
pub const QUOTE_CHARS: usize = 60;

/// `s` in single quotes, cut after [`QUOTE_CHARS`] characters (then followed by `…` and
/// the full length in bytes), with control and other non-printable characters escaped as
/// Rust escapes them (`\n`, `\u{1b}`).
pub fn quoted(s: &str) -> String {
    quoted_in(s, '\'')
}

/// [`quoted`] between two `mark`s instead of single quotes (`` `key` ``).
pub fn quoted_in(s: &str, mark: char) -> String {
    let mut out = String::with_capacity(s.len().min(4 * QUOTE_CHARS) + 2);
    out.push(mark);
    let mut chars = s.chars();
    for c in chars.by_ref().take(QUOTE_CHARS) {
        push_printable(&mut out, c);
    }
    out.push(mark);
    if chars.next().is_some() {
        let _ = write!(out, "… ({} bytes)", s.len());
    }
    out
}

/// `s` with its non-printable characters escaped, whole: for text that is already bounded
/// (a message of ours around quoted input, a file name given on the command line).
pub fn printable(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        push_printable(&mut out, c);
    }
    out
}

fn push_printable(out: &mut String, c: char) {
    // Control characters (C0, DEL, C1) and the invisible format and separator characters
    // that can reorder or hide what a terminal shows.
    let hidden = c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{feff}');
    if hidden {
        out.extend(c.escape_default());
    } else {
        out.push(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_printable_input_is_quoted_as_is() {
        assert_eq!(quoted("colour"), "'colour'");
        assert_eq!(quoted("höhe"), "'höhe'");
    }

    #[test]
    fn long_input_is_cut_with_its_length() {
        let long = "k".repeat(50_000_000);
        let q = quoted(&long);
        assert!(q.len() < 100, "{q}");
        assert_eq!(q, format!("'{}'… (50000000 bytes)", "k".repeat(QUOTE_CHARS)));
    }

    #[test]
    fn control_characters_are_escaped() {
        let q = quoted("a\u{1b}[31mred\nline\u{202e}");
        assert_eq!(q, "'a\\u{1b}[31mred\\nline\\u{202e}'");
        assert!(!q.chars().any(|c| c.is_control()));
        assert_eq!(printable("x\ty"), "x\\ty");
    }
}
