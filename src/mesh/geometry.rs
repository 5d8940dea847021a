//! Geometry of a [`Mesh`], kept apart from its connectivity: edge lengths, triangle areas,
//! corner angles and the cotangent weights of the paper's eq. 2.

use super::{Mesh, NONE};
use crate::geom::{angle, cotangent, cross, norm, sub, unit, Vec3};

/// Length of every edge, indexed by edge.
pub fn edge_lengths(mesh: &Mesh) -> Vec<f64> {
    (0..mesh.n_edges() as u32)
        .map(|e| {
            let h = mesh.edge_halfedge(e, 0);
            norm(sub(mesh.position(mesh.to_vertex(h)), mesh.position(mesh.from_vertex(h))))
        })
        .collect()
}

/// Area of every triangle, indexed by face.
pub fn triangle_areas(mesh: &Mesh) -> Vec<f64> {
    mesh.triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.position(v));
            0.5 * norm(cross(sub(b, a), sub(c, a)))
        })
        .collect()
}

/// The lumped mass of every vertex: a third of the area of each triangle round it.
pub fn vertex_areas(mesh: &Mesh) -> Vec<f64> {
    let areas = triangle_areas(mesh);
    let mut mass = vec![0.0; mesh.n_vertices()];
    for (f, t) in mesh.triangles().iter().enumerate() {
        for &v in t {
            mass[v as usize] += areas[f] / 3.0;
        }
    }
    mass
}

/// Unit normal of every triangle (by its orientation), indexed by face.
pub fn face_normals(mesh: &Mesh) -> Vec<Vec3> {
    mesh.triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.position(v));
            unit(cross(sub(b, a), sub(c, a)))
        })
        .collect()
}

/// Interior angle of every triangle at each of its corners, `[f][k]` at `triangles[f][k]`.
pub fn corner_angles(mesh: &Mesh) -> Vec<[f64; 3]> {
    mesh.triangles()
        .iter()
        .map(|t| {
            let p = t.map(|v| mesh.position(v));
            std::array::from_fn(|k| angle(sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k])))
        })
        .collect()
}

/// Angle of `face(h)` at the vertex `h` leaves.
pub fn corner_angle(mesh: &Mesh, h: u32) -> f64 {
    let o = mesh.position(mesh.from_vertex(h));
    angle(sub(mesh.position(mesh.to_vertex(h)), o), sub(mesh.position(mesh.from_vertex(mesh.prev(h))), o))
}

/// Cotangent of the angle opposite halfedge `h` in its face (0 for a boundary halfedge).
pub fn opposite_cotangent(mesh: &Mesh, h: u32) -> f64 {
    if mesh.face(h) == NONE {
        return 0.0;
    }
    let a = mesh.position(mesh.from_vertex(h));
    let b = mesh.position(mesh.to_vertex(h));
    cotangent(mesh.position(mesh.to_vertex(mesh.next(h))), a, b)
}

/// Cotangent weight of every edge, paper eq. 2: `w_ij = (cot α_ij + cot β_ij) / 2` with
/// α, β the angles opposite the edge; a boundary edge has one of them. Weights may be
/// negative (obtuse triangles); they are returned as they are.
///
/// Precondition: no zero-area faces (the mesh builder removes them).
pub fn cotangent_weights(mesh: &Mesh) -> Vec<f64> {
    (0..mesh.n_edges() as u32)
        .map(|e| {
            let h = mesh.edge_halfedge(e, 0);
            0.5 * (opposite_cotangent(mesh, h) + opposite_cotangent(mesh, mesh.twin(h)))
        })
        .collect()
}

/// Axis-aligned bounding box of the vertices that belong to faces, as (min, max).
pub fn bounding_box(mesh: &Mesh) -> (Vec3, Vec3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (v, p) in mesh.positions().iter().enumerate() {
        if mesh.is_isolated(v as u32) {
            continue;
        }
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{build_mesh, TriangleSoup};

    #[test]
    fn right_triangle_measures() {
        let soup = TriangleSoup {
            positions: vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            triangles: vec![[0, 1, 2]],
            ..Default::default()
        };
        let m = build_mesh(soup).unwrap().mesh;
        assert!((triangle_areas(&m)[0] - 1.0).abs() < 1e-15);
        let ang = corner_angles(&m)[0];
        assert!((ang[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((ang.iter().sum::<f64>() - std::f64::consts::PI).abs() < 1e-14);
        // Edge 0-1 is opposite the corner at vertex 2, whose angle has cot = 1/2.
        let e = m.edge(m.find_halfedge(0, 1).unwrap()) as usize;
        assert!((cotangent_weights(&m)[e] - 0.25).abs() < 1e-15);
        // The hypotenuse is opposite the right angle: cot = 0.
        let e = m.edge(m.find_halfedge(1, 2).unwrap()) as usize;
        assert!(cotangent_weights(&m)[e].abs() < 1e-15);
        assert!((edge_lengths(&m)[e] - 5f64.sqrt()).abs() < 1e-15);
    }
}
