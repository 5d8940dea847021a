//! STL, ASCII and binary. STL shares no vertices between facets, so exactly coincident
//! corners are welded (and facets that collapse in doing so are dropped); both repairs are
//! counted in the mesh's [`Repairs`](crate::mesh::Repairs).

use super::text::{lines, point};
use super::weld::weld_triangles;
use super::{Format, ReadError, ReadSoup};
use crate::quote::quoted;

const F: Format = Format::Stl;

pub(crate) fn read(bytes: &[u8]) -> Result<ReadSoup, ReadError> {
    // A binary STL's size is fixed by its triangle count; its 80-byte header may well start
    // with "solid", so the size decides first.
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        // In u64: on wasm32, 50 * n in usize wraps and a crafted count would pass.
        if bytes.len() as u64 == 84 + 50 * n {
            return read_binary(bytes, n as usize);
        }
    }
    let text_start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    if bytes[text_start..].starts_with(b"solid") {
        return read_ascii(bytes);
    }
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        let message = format!(
            "binary STL declares {n} triangles ({} bytes) but the file has {} bytes",
            84 + 50 * n,
            bytes.len()
        );
        return Err(ReadError::Invalid { format: F, message });
    }
    let message = "neither an ASCII STL (starting with 'solid') nor a binary STL (84 bytes or more)";
    Err(ReadError::Invalid { format: F, message: message.into() })
}

fn read_binary(bytes: &[u8], n: usize) -> Result<ReadSoup, ReadError> {
    let mut positions = Vec::with_capacity(3 * n);
    for i in 0..n {
        let rec = &bytes[84 + 50 * i..84 + 50 * (i + 1)];
        for k in 0..3 {
            let p: [f64; 3] = std::array::from_fn(|c| {
                let o = 12 + 12 * k + 4 * c;
                f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64
            });
            if p.iter().any(|c| !c.is_finite()) {
                let message = format!("facet {i} has a coordinate that is not a finite number");
                return Err(ReadError::Invalid { format: F, message });
            }
            positions.push(p);
        }
    }
    Ok(soup_of_facets(positions))
}

fn read_ascii(bytes: &[u8]) -> Result<ReadSoup, ReadError> {
    let mut positions = Vec::new();
    let mut in_facet = 0; // vertices read in the open facet
    let mut open_facet_line = 0; // 0: no facet open
    for item in lines(bytes, F) {
        let (line, text) = item?;
        let mut t = text.split_ascii_whitespace();
        let err = |message: String| ReadError::Syntax { format: F, line, message };
        match t.next() {
            Some("vertex") => {
                if open_facet_line == 0 || in_facet == 3 {
                    return Err(err("'vertex' outside a facet, or a facet with more than 3".into()));
                }
                positions.push(point(&mut t, F, line)?);
                in_facet += 1;
            }
            Some("facet") => {
                if open_facet_line != 0 {
                    return Err(err(format!("facet begun before the facet of line {open_facet_line} ended")));
                }
                open_facet_line = line;
                in_facet = 0;
            }
            Some("endfacet") => {
                if in_facet != 3 {
                    return Err(err(format!("facet has {in_facet} vertices; 3 needed")));
                }
                open_facet_line = 0;
            }
            Some("solid") | Some("outer") | Some("endloop") | Some("endsolid") | None => {}
            Some(other) => return Err(err(format!("unexpected {}", quoted(other)))),
        }
    }
    if open_facet_line != 0 {
        let message = format!("the file ends inside the facet of line {open_facet_line}");
        return Err(ReadError::Invalid { format: F, message });
    }
    Ok(soup_of_facets(positions))
}

fn soup_of_facets(corners: Vec<[f64; 3]>) -> ReadSoup {
    let n = corners.len() / 3;
    let triangles: Vec<[u32; 3]> =
        (0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let origin: Vec<u32> = (0..n as u32).collect();
    weld_triangles(&corners, &triangles, &origin).into_read_soup()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_square_welds() {
        let s = "solid sq\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n\
                 endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\n\
                 vertex 0 1 0\nendloop\nendfacet\nendsolid sq\n";
        let r = read(s.as_bytes()).unwrap();
        assert_eq!(r.soup.positions.len(), 4);
        assert_eq!(r.soup.repairs.welded_vertices, 2);
        assert_eq!(r.soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn binary_triangle() {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&[0u8; 12]);
        for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
            b.extend_from_slice(&c.to_le_bytes());
        }
        b.extend_from_slice(&[0, 0]);
        let r = read(&b).unwrap();
        assert_eq!(r.soup.triangles, vec![[0, 1, 2]]);
        let e = read(&b[..b.len() - 1]).err().unwrap();
        assert!(e.to_string().contains("declares 1 triangles"), "{e}");
    }
}
