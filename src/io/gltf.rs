//! glTF 2.0 (`.gltf` with embedded or resolvable buffers, and binary `.glb`), through the
//! `gltf` crate. All triangle primitives (lists, strips, fans) of the default scene, with
//! node transforms applied; vertices that exporters split along seams are welded back when
//! they coincide exactly.

use super::weld::weld_triangles;
use super::{Format, ReadError, ReadSoup};
use crate::quote::quoted;
use base64::Engine;
use gltf::accessor::{DataType, Dimensions};
use gltf::json::mesh::Semantic;
use gltf::json::validation::Checked;
use gltf::mesh::Mode;

const F: Format = Format::Gltf;

fn invalid(message: impl Into<String>) -> ReadError {
    ReadError::Invalid { format: F, message: message.into() }
}

type Mat4 = [[f64; 4]; 4];

pub(crate) fn read(
    bytes: &[u8],
    resource: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<ReadSoup, ReadError> {
    // The `gltf` crate subtracts the header size from the declared length unchecked.
    if bytes.starts_with(b"glTF") && bytes.len() >= 12 {
        let declared = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
        if declared < 12 || declared > bytes.len() {
            return Err(invalid(format!("GLB declares {declared} bytes but the file has {}", bytes.len())));
        }
    }
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| invalid(e.to_string()))?;
    // gltf-json's validation indexes the POSITION accessor unchecked (a panic): check first.
    let root = unchecked.document.as_json();
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            let position = prim.attributes.get(&Checked::Valid(Semantic::Positions));
            if let Some(a) = position.filter(|a| a.value() >= root.accessors.len()) {
                let message = format!("mesh {mi} primitive {pi}: POSITION accessor {} does not exist", a.value());
                return Err(invalid(message));
            }
        }
    }
    let document = gltf::Document::from_json(unchecked.document.into_json()).map_err(|e| invalid(e.to_string()))?;
    let gltf = gltf::Gltf { document, blob: unchecked.blob };
    let buffers = load_buffers(&gltf, resource)?;
    let doc = &gltf.document;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| invalid("the file has no scene"))?;

    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut visited = vec![false; doc.nodes().count()];
    let identity: Mat4 = std::array::from_fn(|i| std::array::from_fn(|j| (i == j) as u8 as f64));
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, identity)).collect();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(invalid(format!("node {} is reached twice (a cycle?)", node.index())));
        }
        let local = node.transform().matrix().map(|c| c.map(|x| x as f64));
        let world = mul(&parent, &local);
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let what = format!("mesh {} primitive {}", mesh.index(), prim.index());
                read_primitive(&prim, &buffers, &world, &what, &mut positions, &mut triangles)?;
            }
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    if triangles.is_empty() {
        return Err(invalid("the default scene has no triangles"));
    }
    let origin: Vec<u32> = (0..triangles.len() as u32).collect();
    Ok(weld_triangles(&positions, &triangles, &origin).into_read_soup())
}

fn load_buffers(
    gltf: &gltf::Gltf,
    resource: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, ReadError> {
    gltf.document
        .buffers()
        .map(|b| {
            let data = match b.source() {
                gltf::buffer::Source::Bin => gltf
                    .blob
                    .clone()
                    .ok_or_else(|| invalid(format!("buffer {} refers to a missing GLB chunk", b.index())))?,
                gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                    let payload = uri
                        .split_once(";base64,")
                        .ok_or_else(|| invalid(format!("buffer {}: data URI is not base64", b.index())))?
                        .1;
                    base64::engine::general_purpose::STANDARD
                        .decode(payload)
                        .map_err(|e| invalid(format!("buffer {}: bad base64 ({e})", b.index())))?
                }
                gltf::buffer::Source::Uri(uri) => resource(uri).ok_or_else(|| {
                    invalid(format!(
                        "buffer {} is the external file {}, which cannot be read here (use .glb)",
                        b.index(),
                        quoted(uri)
                    ))
                })?,
            };
            if data.len() < b.length() {
                return Err(invalid(format!(
                    "buffer {} has {} bytes, fewer than the {} it declares",
                    b.index(),
                    data.len(),
                    b.length()
                )));
            }
            Ok(data)
        })
        .collect()
}

/// Refuses accessors whose bytes lie outside their buffer: the `gltf` reader would panic.
fn check_accessor(acc: &gltf::Accessor, buffers: &[Vec<u8>], what: &str) -> Result<(), ReadError> {
    if acc.sparse().is_some() {
        return Err(invalid(format!("{what}: sparse accessors are not supported")));
    }
    let view = acc.view().ok_or_else(|| invalid(format!("{what}: accessor {} has no buffer view", acc.index())))?;
    let size = acc.size();
    let stride = view.stride().unwrap_or(size);
    // The `gltf` reader computes `count - 1` and reads `size` bytes at every stride.
    if acc.count() == 0 {
        return Err(invalid(format!("{what}: accessor {} has no elements", acc.index())));
    }
    if stride < size {
        return Err(invalid(format!(
            "{what}: accessor {} has a stride of {stride} bytes, less than its {size}-byte elements",
            acc.index()
        )));
    }
    let view_end = view.offset().checked_add(view.length());
    let needed = (acc.count() - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(acc.offset()))
        .and_then(|x| x.checked_add(size));
    let buffer_len = buffers[view.buffer().index()].len();
    match (view_end, needed) {
        (Some(end), Some(need)) if end <= buffer_len && need <= view.length() => Ok(()),
        _ => Err(invalid(format!(
            "{what}: accessor {} reaches outside its buffer",
            acc.index()
        ))),
    }
}

fn read_primitive(
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: &Mat4,
    what: &str,
    positions: &mut Vec<[f64; 3]>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<(), ReadError> {
    if !matches!(prim.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(()); // points and lines carry no surface
    }
    let pos_acc = prim
        .get(&gltf::Semantic::Positions)
        .ok_or_else(|| invalid(format!("{what} has no POSITION attribute")))?;
    // The `gltf` reader assumes these types (it asserts or hits `unreachable!` otherwise).
    if pos_acc.dimensions() != Dimensions::Vec3 || pos_acc.data_type() != DataType::F32 {
        return Err(invalid(format!("{what}: POSITION accessor {} is not VEC3 of FLOAT", pos_acc.index())));
    }
    check_accessor(&pos_acc, buffers, what)?;
    if let Some(idx) = prim.indices() {
        let unsigned = matches!(idx.data_type(), DataType::U8 | DataType::U16 | DataType::U32);
        if idx.dimensions() != Dimensions::Scalar || !unsigned {
            return Err(invalid(format!(
                "{what}: index accessor {} is not SCALAR of unsigned integers",
                idx.index()
            )));
        }
        check_accessor(&idx, buffers, what)?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| d.as_slice()));
    let base = positions.len() as u32;
    let local: Vec<[f64; 3]> = reader
        .read_positions()
        .ok_or_else(|| invalid(format!("{what}: positions cannot be read")))?
        .map(|p| transform(world, p))
        .collect();
    if let Some(i) = local.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(invalid(format!("{what}: vertex {i} is not finite")));
    }
    let n = local.len() as u32;
    positions.extend(local);
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..n).collect(),
    };
    if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
        return Err(invalid(format!("{what}: index {bad} is out of range ({n} vertices)")));
    }
    // A mirroring transform turns the winding around.
    let flip = det3(world) < 0.0;
    let mut push = |a: u32, b: u32, c: u32| {
        let t = if flip { [a, c, b] } else { [a, b, c] };
        triangles.push(t.map(|i| base + i));
    };
    match prim.mode() {
        Mode::Triangles => indices.chunks_exact(3).for_each(|t| push(t[0], t[1], t[2])),
        Mode::TriangleStrip => (2..indices.len()).for_each(|k| {
            let (a, b, c) = (indices[k - 2], indices[k - 1], indices[k]);
            if k % 2 == 0 { push(a, b, c) } else { push(b, a, c) }
        }),
        _ => (2..indices.len()).for_each(|k| push(indices[0], indices[k - 1], indices[k])),
    }
    Ok(())
}

/// Column-major 4×4 product, as glTF stores matrices.
fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|col| std::array::from_fn(|row| (0..4).map(|k| a[k][row] * b[col][k]).sum()))
}

fn transform(m: &Mat4, p: [f32; 3]) -> [f64; 3] {
    let p = p.map(|x| x as f64);
    std::array::from_fn(|row| m[0][row] * p[0] + m[1][row] * p[1] + m[2][row] * p[2] + m[3][row])
}

fn det3(m: &Mat4) -> f64 {
    let a = |r: usize, c: usize| m[c][r];
    a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0))
        + a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0))
}
