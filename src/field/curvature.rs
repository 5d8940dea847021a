//! The alignment guide of the cross field: principal curvature directions where the surface
//! is clearly anisotropic (Knöppel et al. 2013, Section 7.1; method-notes §11).
//!
//! The curvature tensor at a vertex is estimated from the edges around it as in Cohen-Steiner
//! and Morvan 2003: `Σ β_e ℓ_e ē ēᵀ` with `β_e` the signed dihedral angle, `ℓ_e` the length and
//! `ē` the unit direction of edge `e`. In the tangent frame its trace-free part is the complex
//! number `S = Σ β_e ℓ_e e^{2iα_e}`: `arg S / 2` is a principal direction, and `|S|` the
//! difference of the two principal curvatures (times area). A cross aligned to one principal
//! direction is aligned to both, so the guide is `S⁴ / |S|⁴`, weighted by how anisotropic
//! and how curved the surface is at the vertex.

use super::frames::Frames;
use super::Complex;
use crate::geom::{cross, dot, norm, sub, unit};
use crate::mesh::geometry::{face_normals, vertex_areas};
use crate::mesh::Mesh;

/// Anisotropy `|λ1 − λ2| / (|λ1| + |λ2|)` below this gives no guide; it reaches full weight
/// at [`ANISOTROPY_FULL`].
const ANISOTROPY_MIN: f64 = 0.2;
const ANISOTROPY_FULL: f64 = 0.6;
/// Curvature (times the bounding-box diagonal) at which a vertex counts as fully curved:
/// flatter regions get a weaker guide, as their principal directions are noise.
const CURVED: f64 = 6.0;

/// The guide per vertex, as a complex number of modulus in [0, 1] (0: no preference).
pub fn curvature_guide(mesh: &Mesh, frames: &Frames, diagonal: f64) -> Vec<Complex> {
    let normals = face_normals(mesh);
    // Signed dihedral angle times length of every edge.
    let bend: Vec<f64> = (0..mesh.n_edges() as u32)
        .map(|e| {
            let h = 2 * e;
            if mesh.is_boundary_edge(e) {
                return 0.0;
            }
            let (n1, n2) = (normals[mesh.face(h) as usize], normals[mesh.face(h ^ 1) as usize]);
            let d = sub(mesh.position(mesh.to_vertex(h)), mesh.position(mesh.from_vertex(h)));
            let beta = dot(cross(n1, n2), unit(d)).atan2(dot(n1, n2));
            beta * norm(d)
        })
        .collect();
    let vertex_area = vertex_areas(mesh);
    (0..mesh.n_vertices() as u32)
        .map(|v| {
            if mesh.is_isolated(v) {
                return Complex::ZERO;
            }
            let (mut s, mut total) = (Complex::ZERO, 0.0);
            let mut add_edge = |e: u32| {
                let h = 2 * e;
                let d = sub(mesh.position(mesh.to_vertex(h)), mesh.position(mesh.from_vertex(h)));
                let a = 2.0 * frames.angle(v, d);
                s = s + Complex::polar(bend[e as usize], a);
                total += bend[e as usize].abs();
            };
            for h in mesh.outgoing(v) {
                add_edge(mesh.edge(h));
                if !mesh.is_boundary_halfedge(h) {
                    add_edge(mesh.edge(mesh.next(h)));
                }
            }
            let m = s.abs();
            if m < 1e-300 || total < 1e-300 {
                return Complex::ZERO;
            }
            let anisotropy = m / total;
            let curved = total / (3.0 * vertex_area[v as usize]).max(1e-300) * diagonal;
            let w = ((anisotropy - ANISOTROPY_MIN) / (ANISOTROPY_FULL - ANISOTROPY_MIN)).clamp(0.0, 1.0)
                * (curved / CURVED).clamp(0.0, 1.0);
            let d = s * (1.0 / m);
            d * d * w
        })
        .collect()
}
