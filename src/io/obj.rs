//! Wavefront OBJ: `v` and `f` statements; polygons are fan-triangulated, `vt`/`vn` and the
//! other statements are ignored. Negative (relative) indices are supported. A text file whose
//! lines begin with no OBJ statement at all (a note, a CSV table, an XYZ point list saved as
//! `.obj`) is said not to be an OBJ file, rather than an OBJ without vertices.

use super::text::{lines, point};
use super::{Format, ReadError, ReadSoup};
use crate::mesh::TriangleSoup;
use crate::quote::quoted;

const F: Format = Format::Obj;

/// The statements of the OBJ specification (geometry, grouping, display and render
/// attributes, free-form curves and surfaces): a line that begins with one of them is OBJ.
const STATEMENTS: &[&str] = &[
    "v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "mg", "usemtl", "mtllib", "usemap", "maplib", "bevel",
    "c_interp", "d_interp", "lod", "shadow_obj", "trace_obj", "ctech", "stech", "cstype", "deg", "bmat", "step",
    "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con", "call", "csh",
];

pub(crate) fn read(bytes: &[u8]) -> Result<ReadSoup, ReadError> {
    let mut soup = TriangleSoup::default();
    let mut origin = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    let mut any_statement = false;
    // The first line that is neither blank, a comment nor an OBJ statement.
    let mut first_other: Option<(usize, String)> = None;
    for item in lines(bytes, F) {
        let (line, text) = item?;
        let text = text.split('#').next().unwrap_or("");
        let mut tokens = text.split_ascii_whitespace();
        let keyword = tokens.next();
        match keyword {
            Some(k) if STATEMENTS.contains(&k) => any_statement = true,
            Some(k) if first_other.is_none() => first_other = Some((line, k.chars().take(20).collect())),
            _ => {}
        }
        match keyword {
            Some("v") => soup.positions.push(point(&mut tokens, F, line)?),
            Some("f") => {
                polygon.clear();
                for t in tokens {
                    polygon.push(vertex_index(t, soup.positions.len(), line)?);
                }
                if polygon.len() < 3 {
                    let message = format!("a face needs 3 or more vertices, found {}", polygon.len());
                    return Err(ReadError::Syntax { format: F, line, message });
                }
                for k in 1..polygon.len() - 1 {
                    soup.triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                    origin.push(line as u32);
                }
            }
            _ => {}
        }
    }
    if let (false, Some((line, word))) = (any_statement, first_other) {
        let message = format!("not an OBJ file: no line begins with an OBJ statement (v, f, ...); line {line} begins '{word}'");
        return Err(ReadError::Invalid { format: F, message });
    }
    Ok(ReadSoup { soup, origin })
}

/// The 0-based vertex of a face token `v`, `v/vt`, `v//vn` or `v/vt/vn`.
fn vertex_index(token: &str, defined: usize, line: usize) -> Result<u32, ReadError> {
    let err = |message: String| ReadError::Syntax { format: F, line, message };
    let first = token.split('/').next().unwrap_or("");
    let i: i64 = first.parse().map_err(|_| err(format!("{} is not a vertex index", quoted(token))))?;
    let index = match i {
        0 => return Err(err("vertex index 0 (OBJ counts from 1)".into())),
        i if i < 0 => defined as i64 + i,
        i => i - 1,
    };
    if index < 0 || index >= u32::MAX as i64 {
        return Err(err(format!("vertex index {i} is out of range ({defined} vertices so far)")));
    }
    Ok(index as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_are_fanned_and_indices_resolved() {
        let text = b"# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 -2/1 -1/1\n";
        let r = read(text).unwrap();
        assert_eq!(r.soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(r.origin, vec![7, 7]);
    }

    #[test]
    fn text_without_obj_statements_is_not_an_obj_file() {
        let e = read(b"# notes\n\nshopping list\nmilk, eggs\n").err().unwrap();
        assert_eq!(e.to_string(), "OBJ: not an OBJ file: no line begins with an OBJ statement (v, f, ...); line 3 begins 'shopping'");
        // One OBJ statement among unknown ones is an OBJ file (unknown statements are skipped).
        assert!(read(b"frobnicate 1 2\nv 0 0 0\n").is_ok());
        // No lines at all: an empty OBJ file (the mesh then has no vertices).
        assert!(read(b"# nothing\n").is_ok());
    }

    #[test]
    fn garbage_names_the_line() {
        let e = read(b"v 0 0 0\nv 1 x 0\n").err().unwrap();
        assert_eq!(e.to_string(), "OBJ line 2: 'x' is not a number");
        let e = read(b"v 0 0 nan\n").err().unwrap();
        assert!(e.to_string().contains("line 1"), "{e}");
    }
}
