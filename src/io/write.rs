//! Writers: OBJ (triangles or quads, optional per-corner texture coordinates), binary PLY,
//! and GLB (triangles; quads are split in two).

/// A polygon mesh whose faces all have `arity` corners (3 or 4), as flat index lists.
#[derive(Debug, Clone, Copy)]
pub struct Polygons<'a> {
    pub positions: &'a [[f64; 3]],
    pub faces: &'a [u32],
    pub arity: usize,
}

impl Polygons<'_> {
    fn faces(&self) -> impl Iterator<Item = &[u32]> {
        self.faces.chunks_exact(self.arity)
    }
    /// Triangles, quads split along their diagonal 0–2.
    fn triangles(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.faces.len() / self.arity * 3 * (self.arity - 2));
        for f in self.faces() {
            for k in 1..f.len() - 1 {
                out.extend_from_slice(&[f[0], f[k], f[k + 1]]);
            }
        }
        out
    }
}

/// OBJ text. With `corner_uv` (one per face corner, in face order) every corner gets its
/// own `vt`, so a triangle can carry coordinates of its own chart.
pub fn write_obj(mesh: Polygons, corner_uv: Option<&[[f64; 2]]>) -> Vec<u8> {
    use std::fmt::Write;
    let mut s = String::with_capacity(mesh.positions.len() * 40 + mesh.faces.len() * 12);
    s.push_str("# written by quadlay\n");
    for p in mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    if let Some(uv) = corner_uv {
        for t in uv {
            let _ = writeln!(s, "vt {} {}", t[0], t[1]);
        }
    }
    for (fi, f) in mesh.faces().enumerate() {
        s.push('f');
        for (k, v) in f.iter().enumerate() {
            match corner_uv {
                Some(_) => write!(s, " {}/{}", v + 1, fi * mesh.arity + k + 1),
                None => write!(s, " {}", v + 1),
            }
            .ok();
        }
        s.push('\n');
    }
    s.into_bytes()
}

/// Binary little-endian PLY with double coordinates and one index list per face.
pub fn write_ply(mesh: Polygons) -> Vec<u8> {
    let n_faces = mesh.faces.len() / mesh.arity;
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by quadlay\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar uint vertex_indices\nend_header\n",
        mesh.positions.len(),
        n_faces
    )
    .into_bytes();
    for p in mesh.positions {
        for c in p {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    for f in mesh.faces() {
        out.push(f.len() as u8);
        for v in f {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// GLB (binary glTF 2.0): one mesh, one triangle primitive, float positions, u32 indices.
pub fn write_glb(mesh: Polygons) -> Vec<u8> {
    let (json, bin) = gltf_parts(mesh);
    let mut json = serde_json::to_vec(&json).unwrap_or_default();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// glTF 2.0 as one JSON file, its buffer embedded as a base64 data URI (same content as
/// [`write_glb`]).
pub fn write_gltf(mesh: Polygons) -> Vec<u8> {
    use base64::Engine;
    let (mut json, bin) = gltf_parts(mesh);
    let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    json["buffers"][0]["uri"] = serde_json::Value::String(uri);
    serde_json::to_vec_pretty(&json).unwrap_or_default()
}

/// The glTF document and its binary buffer (positions, then triangle indices).
fn gltf_parts(mesh: Polygons) -> (serde_json::Value, Vec<u8>) {
    let tris = mesh.triangles();
    let mut bin = Vec::with_capacity(mesh.positions.len() * 12 + tris.len() * 4);
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in mesh.positions {
        for k in 0..3 {
            let c = p[k] as f32;
            lo[k] = lo[k].min(c);
            hi[k] = hi[k].max(c);
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let pos_len = bin.len();
    for i in &tris {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let idx_len = bin.len() - pos_len;
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let json = serde_json::json!({
        "asset": { "version": "2.0", "generator": "quadlay" },
        "scene": 0,
        "scenes": [ { "nodes": [0] } ],
        "nodes": [ { "mesh": 0 } ],
        "meshes": [ { "primitives": [ { "attributes": { "POSITION": 0 }, "indices": 1, "mode": 4 } ] } ],
        "buffers": [ { "byteLength": bin.len() } ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": pos_len, "target": 34962 },
            { "buffer": 0, "byteOffset": pos_len, "byteLength": idx_len, "target": 34963 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": mesh.positions.len(), "type": "VEC3",
              "min": lo, "max": hi },
            { "bufferView": 1, "componentType": 5125, "count": tris.len(), "type": "SCALAR" }
        ]
    });
    (json, bin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::read_mesh;

    const POS: [[f64; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.5],
        [2.0, 1.0, 0.0],
    ];
    const QUADS: [u32; 8] = [0, 1, 4, 3, 1, 2, 5, 4];

    fn quads() -> Polygons<'static> {
        Polygons { positions: &POS, faces: &QUADS, arity: 4 }
    }

    #[test]
    fn every_writer_reads_back() {
        let obj = write_obj(quads(), None);
        let ply = write_ply(quads());
        let glb = write_glb(quads());
        let gltf = write_gltf(quads());
        for (bytes, name) in [(obj, "a.obj"), (ply, "a.ply"), (glb, "a.glb"), (gltf, "a.gltf")] {
            let m = read_mesh(&bytes, name).unwrap().mesh;
            assert_eq!((m.n_vertices(), m.n_faces()), (6, 4), "{name}");
            assert_eq!(m.position(4)[2], 0.5, "{name}");
        }
    }

    #[test]
    fn obj_corner_uvs() {
        let uv: Vec<[f64; 2]> = (0..8).map(|i| [i as f64, 0.0]).collect();
        let text = String::from_utf8(write_obj(quads(), Some(&uv))).unwrap();
        assert!(text.contains("f 2/5 3/6 6/7 5/8\n"), "{text}");
        assert_eq!(text.matches("vt ").count(), 8);
    }
}
