//! Merging vertices with exactly the same coordinates: STL stores none shared, and glTF
//! exporters split vertices along UV and normal seams. Exact equality cannot change the
//! surface; nearby-but-different vertices are left alone.

use std::collections::HashMap;

/// Returns the welded positions and, for every input vertex, its new index.
pub(crate) fn weld(positions: &[[f64; 3]]) -> (Vec<[f64; 3]>, Vec<u32>) {
    let mut index: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    let mut out = Vec::with_capacity(positions.len() / 2);
    let remap = positions
        .iter()
        .map(|p| {
            // +0.0 folds -0.0 into 0.0, so the two zeros weld.
            let key = p.map(|c| (c + 0.0).to_bits());
            *index.entry(key).or_insert_with(|| {
                out.push(*p);
                (out.len() - 1) as u32
            })
        })
        .collect();
    (out, remap)
}

/// Welds the vertices of a triangle list and drops triangles that collapse (two corners on
/// one point: zero area). Returns positions, triangles, their origins, and the counts of
/// merged vertices and dropped triangles.
pub(crate) fn weld_triangles(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    origin: &[u32],
) -> WeldedSoup {
    let (welded, remap) = weld(positions);
    let mut tris = Vec::with_capacity(triangles.len());
    let mut kept_origin = Vec::with_capacity(triangles.len());
    let mut collapsed = 0;
    for (t, &o) in triangles.iter().zip(origin) {
        let w = t.map(|v| remap[v as usize]);
        if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] {
            collapsed += 1;
        } else {
            tris.push(w);
            kept_origin.push(o);
        }
    }
    WeldedSoup {
        merged: positions.len() - welded.len(),
        positions: welded,
        triangles: tris,
        origin: kept_origin,
        collapsed,
    }
}

pub(crate) struct WeldedSoup {
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub origin: Vec<u32>,
    pub merged: usize,
    pub collapsed: usize,
}

impl WeldedSoup {
    pub(crate) fn into_read_soup(self) -> super::ReadSoup {
        let repairs = crate::mesh::Repairs {
            welded_vertices: self.merged,
            removed_zero_area_faces: self.collapsed,
            ..Default::default()
        };
        super::ReadSoup {
            soup: crate::mesh::TriangleSoup {
                positions: self.positions,
                triangles: self.triangles,
                repairs,
            },
            origin: self.origin,
        }
    }
}
