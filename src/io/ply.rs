//! Stanford PLY, ASCII and binary (either byte order). Reads `x y z` of the `vertex`
//! element and the index list (`vertex_indices` or `vertex_index`) of the `face` element;
//! other elements and properties are parsed and skipped. Polygons are fan-triangulated.

use super::{Format, ReadError, ReadSoup};
use crate::mesh::TriangleSoup;
use crate::quote::quoted;

/// An element's name as messages show it: the common ones plain (`face 3`), any other
/// quoted, since a header may name an element anything.
fn printable_name(name: &str) -> String {
    match name {
        "vertex" | "face" | "edge" => name.to_string(),
        _ => quoted(name),
    }
}

const F: Format = Format::Ply;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar { name: String, ty: Scalar },
    List { name: String, count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

fn invalid(message: impl Into<String>) -> ReadError {
    ReadError::Invalid { format: F, message: message.into() }
}

fn syntax(line: usize, message: impl Into<String>) -> ReadError {
    ReadError::Syntax { format: F, line, message: message.into() }
}

/// Parses the header; returns the encoding, the elements and the byte offset of the data.
fn header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, usize, usize), ReadError> {
    if !bytes.starts_with(b"ply") {
        return Err(invalid("not a PLY file (it does not start with 'ply')"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut pos = 0;
    let mut line = 0;
    loop {
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .ok_or_else(|| invalid("the header has no 'end_header' line"))?;
        let raw = &bytes[pos..pos + end];
        pos += end + 1;
        line += 1;
        let text = std::str::from_utf8(raw).map_err(|_| syntax(line, "header line is not text"))?;
        let mut t = text.trim_end_matches('\r').split_ascii_whitespace();
        match t.next() {
            Some("ply") if line == 1 => {}
            Some("format") => {
                encoding = Some(match t.next() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::Little,
                    Some("binary_big_endian") => Encoding::Big,
                    Some(other) => return Err(syntax(line, format!("unknown format {}", quoted(other)))),
                    None => return Err(syntax(line, "format without a name")),
                });
            }
            Some("comment") | Some("obj_info") | None => {}
            Some("element") => {
                let name = t.next().ok_or_else(|| syntax(line, "element without a name"))?;
                let count = t
                    .next()
                    .and_then(|c| c.parse::<usize>().ok())
                    .ok_or_else(|| syntax(line, format!("element {} has no valid count", quoted(name))))?;
                elements.push(Element { name: name.to_string(), count, properties: Vec::new() });
            }
            Some("property") => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| syntax(line, "property before any element"))?;
                let ty = t.next().unwrap_or("");
                let scalar = |s: Option<&str>| {
                    s.and_then(Scalar::parse)
                        .ok_or_else(|| syntax(line, format!("unknown property type {}", quoted(s.unwrap_or("")))))
                };
                let prop = if ty == "list" {
                    let count = scalar(t.next())?;
                    let item = scalar(t.next())?;
                    let name = t.next().ok_or_else(|| syntax(line, "list property without a name"))?;
                    Property::List { name: name.to_string(), count, item }
                } else {
                    let ty = scalar(Some(ty))?;
                    let name = t.next().ok_or_else(|| syntax(line, "property without a name"))?;
                    Property::Scalar { name: name.to_string(), ty }
                };
                el.properties.push(prop);
            }
            Some("end_header") => break,
            Some(other) => return Err(syntax(line, format!("unknown header keyword {}", quoted(other)))),
        }
    }
    let encoding = encoding.ok_or_else(|| invalid("the header has no 'format' line"))?;
    Ok((encoding, elements, pos, line))
}

/// Sequential access to the values of the body, ASCII or binary.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    encoding: Encoding,
    /// ASCII: the current line number.
    line: usize,
    tokens: std::str::SplitAsciiWhitespace<'a>,
}

impl<'a> Body<'a> {
    fn value(&mut self, ty: Scalar, what: &dyn Fn() -> String) -> Result<f64, ReadError> {
        if self.encoding == Encoding::Ascii {
            return self.ascii_value(what);
        }
        let n = ty.size();
        let raw = self
            .bytes
            .get(self.pos..self.pos + n)
            .ok_or_else(|| invalid(format!("the file ends inside {}", what())))?;
        self.pos += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.encoding == Encoding::Big {
            b[..n].reverse();
        }
        Ok(match ty {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn ascii_value(&mut self, what: &dyn Fn() -> String) -> Result<f64, ReadError> {
        loop {
            if let Some(tok) = self.tokens.next() {
                return tok
                    .parse::<f64>()
                    .map_err(|_| syntax(self.line, format!("{} is not a number ({})", quoted(tok), what())));
            }
            if self.pos >= self.bytes.len() {
                return Err(invalid(format!("the file ends inside {}", what())));
            }
            let rest = &self.bytes[self.pos..];
            let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            self.line += 1;
            self.pos += end + 1;
            let text = std::str::from_utf8(&rest[..end])
                .map_err(|_| syntax(self.line, "not a text line in an ASCII PLY"))?;
            self.tokens = text.split_ascii_whitespace();
        }
    }
}

pub(crate) fn read(bytes: &[u8]) -> Result<ReadSoup, ReadError> {
    let (encoding, elements, start, header_lines) = header(bytes)?;
    let vertex = elements.iter().position(|e| e.name == "vertex");
    let vertex = vertex.ok_or_else(|| invalid("no 'vertex' element"))?;
    let xyz: Vec<usize> = ["x", "y", "z"]
        .iter()
        .map(|axis| {
            elements[vertex]
                .properties
                .iter()
                .position(|p| matches!(p, Property::Scalar { name, .. } if name == axis))
                .ok_or_else(|| invalid(format!("the vertex element has no '{axis}' property")))
        })
        .collect::<Result<_, _>>()?;
    let face_list = |e: &Element| {
        e.properties.iter().position(|p| {
            matches!(p, Property::List { name, .. } if name == "vertex_indices" || name == "vertex_index")
        })
    };
    // Refuse counts the file cannot hold before allocating for them.
    let min_size = |e: &Element| match encoding {
        Encoding::Ascii => e.properties.len().max(1) * 2 - 1,
        _ => e
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar { ty, .. } => ty.size(),
                Property::List { count, .. } => count.size(),
            })
            .sum::<usize>(),
    };
    for e in &elements {
        if e.count.saturating_mul(min_size(e)) > bytes.len() - start {
            return Err(invalid(format!(
                "the header declares {} {} elements, more than the file can hold",
                e.count, e.name
            )));
        }
    }

    let mut body = Body { bytes, pos: start, encoding, line: header_lines, tokens: "".split_ascii_whitespace() };
    let mut soup = TriangleSoup::default();
    let mut origin = Vec::new();
    let mut polygon = Vec::new();
    for (ei, el) in elements.iter().enumerate() {
        let list = if el.name == "face" { face_list(el) } else { None };
        if el.name == "face" && list.is_none() {
            return Err(invalid("the face element has no 'vertex_indices' list"));
        }
        if el.properties.is_empty() {
            continue; // holds no bytes, so its count is unbounded: do not loop over it
        }
        if ei == vertex {
            soup.positions.reserve(el.count);
        }
        for i in 0..el.count {
            let what = || format!("{} {i}", printable_name(&el.name));
            let mut p = [0.0; 3];
            for (pi, prop) in el.properties.iter().enumerate() {
                match prop {
                    Property::Scalar { ty, .. } => {
                        let x = body.value(*ty, &what)?;
                        if ei == vertex {
                            if let Some(axis) = xyz.iter().position(|&a| a == pi) {
                                p[axis] = x;
                            }
                        }
                    }
                    Property::List { count, item, .. } => {
                        let n = body.value(*count, &what)?;
                        if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                            return Err(invalid(format!("{} has a list length of {n}", what())));
                        }
                        let is_faces = Some(pi) == list;
                        polygon.clear();
                        for _ in 0..n as usize {
                            let v = body.value(*item, &what)?;
                            if is_faces {
                                if v < 0.0 || v.fract() != 0.0 || v >= u32::MAX as f64 {
                                    return Err(invalid(format!("{} has the vertex index {v}", what())));
                                }
                                polygon.push(v as u32);
                            }
                        }
                        if is_faces {
                            if polygon.len() < 3 {
                                let message = format!("{} has {} vertices; 3 or more needed", what(), polygon.len());
                                return Err(invalid(message));
                            }
                            for k in 1..polygon.len() - 1 {
                                soup.triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                                origin.push(i as u32);
                            }
                        }
                    }
                }
            }
            if ei == vertex {
                if p.iter().any(|c| !c.is_finite()) {
                    return Err(invalid(format!("vertex {i} has a coordinate that is not a finite number")));
                }
                soup.positions.push(p);
            }
        }
    }
    Ok(ReadSoup { soup, origin })
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\n\
        property float y\nproperty float z\nproperty uchar red\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n4 0 1 2 3\n";

    #[test]
    fn ascii_quad() {
        let r = read(ASCII.as_bytes()).unwrap();
        assert_eq!(r.soup.positions.len(), 4);
        assert_eq!(r.soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn binary_big_endian() {
        let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n\
            property double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
            .to_vec();
        for p in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                b.extend_from_slice(&c.to_be_bytes());
            }
        }
        b.push(3);
        for i in [0u32, 1, 2] {
            b.extend_from_slice(&i.to_be_bytes());
        }
        let r = read(&b).unwrap();
        assert_eq!(r.soup.positions[1], [1.0, 0.0, 0.0]);
        assert_eq!(r.soup.triangles, vec![[0, 1, 2]]);
        let e = read(&b[..b.len() - 2]).err().unwrap();
        assert_eq!(e.to_string(), "PLY: the file ends inside face 0");
    }
}
