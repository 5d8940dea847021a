//! Helpers for the text formats: lines with their numbers, numbers with clear errors.

use super::{Format, ReadError};
use crate::quote::quoted;

/// The lines of `bytes` with 1-based numbers; a line that is not UTF-8 is an error.
pub(crate) fn lines(
    bytes: &[u8],
    format: Format,
) -> impl Iterator<Item = Result<(usize, &str), ReadError>> {
    bytes.split(|&b| b == b'\n').enumerate().map(move |(i, raw)| {
        let line = i + 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        match std::str::from_utf8(raw) {
            Ok(s) if !s.contains('\0') => Ok((line, s)),
            _ => Err(ReadError::Syntax {
                format,
                line,
                message: "not a text line (is this a binary file?)".into(),
            }),
        }
    })
}

/// Parses a finite coordinate.
pub(crate) fn coordinate(token: Option<&str>, format: Format, line: usize) -> Result<f64, ReadError> {
    let err = |message: String| ReadError::Syntax { format, line, message };
    let t = token.ok_or_else(|| err("expected a coordinate, found the end of the line".into()))?;
    let x: f64 = t.parse().map_err(|_| err(format!("{} is not a number", quoted(t))))?;
    if !x.is_finite() {
        return Err(err(format!("coordinate {} is not a finite number", quoted(t))));
    }
    Ok(x)
}

/// Reads three coordinates.
pub(crate) fn point<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    format: Format,
    line: usize,
) -> Result<[f64; 3], ReadError> {
    Ok([
        coordinate(tokens.next(), format, line)?,
        coordinate(tokens.next(), format, line)?,
        coordinate(tokens.next(), format, line)?,
    ])
}
