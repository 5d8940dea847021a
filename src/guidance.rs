//! Where a layout needs a node: per layout face, the Gaussian curvature it encloses, its
//! distortion after solving, and for a face that holds too much curvature, a mesh vertex
//! where a new node would take it.
//!
//! Why curvature: by Gauss–Bonnet a face bounded by geodesic curves with corner angles αᵢ
//! encloses K = Σαᵢ − 2π, while every flat quadrilateral chart has Σαᵢ = 2π. A face's chart
//! must absorb K in its corners' angles and in stretch; the paper's charts are flat, so K is
//! the distortion no chart optimization can remove. In a quad mesh, curvature can sit only at
//! irregular vertices: an interior vertex of valence k holds (4 − k)·π/2 (±90° for valence 3
//! or 5). A face enclosing K therefore "wants" round(K / 90°) irregular vertices inside it;
//! that number is non-zero once |K| > 45° ([`NEEDS_NODE`]). The layout has no node there, so
//! the face's quads carry it as distortion instead: the layout needs a node (a new corner of
//! three or five faces) where the curvature concentrates.

use crate::layout::SurfaceLayout;
use crate::geom::{cross, dot, dot2, norm, sub, sub2, Vec3};
use crate::mesh::geometry::corner_angles;
use crate::mesh::{Mesh, NONE};
use crate::param::ParamSession;
use serde::Serialize;
use std::f64::consts::{FRAC_PI_4, TAU};

/// A face enclosing more Gaussian curvature than this (in radians, either sign) needs a node
/// inside: half the ±90° one irregular vertex of a quad mesh holds (see the module
/// documentation).
pub const NEEDS_NODE: f64 = FRAC_PI_4;

/// A suggested place for a new layout node.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Suggestion {
    /// The mesh vertex (the file's numbering) for the node.
    pub vertex: u32,
    /// Its position.
    pub at: Vec3,
    /// What concentrates there: `"curvature"` or `"distortion"`.
    pub reason: &'static str,
}

/// What a user should know about one layout face.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaceGuidance {
    /// Index of the face (the order of the report's and the summary's face lists).
    pub face: usize,
    /// Its four corner nodes, counter-clockwise.
    pub corners: [u32; 4],
    /// Its surface area, in the mesh's units squared.
    pub area: f64,
    /// Gaussian curvature it encloses (the angle defects of its interior mesh vertices), in
    /// degrees: 90 is what a cube's corner holds.
    pub curvature_deg: f64,
    /// Whether it encloses more than [`NEEDS_NODE`].
    pub needs_node: bool,
    /// Area-weighted mean of ‖JᵀJ − I‖²_F over its triangles, once solved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distortion: Option<f64>,
    /// Typical relative length error of its triangles once solved (see [`length_error`]):
    /// 0.05 means lengths on the surface and in the chart differ by about 5 %.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_error: Option<f64>,
    /// Where a new node would help most, for a face that needs one (or, once solved, a face
    /// far more distorted than the others; see [`crate::verdict`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub suggestion: Option<Suggestion>,
}

/// The angle defect 2π − Σ(corner angles) of every interior mesh vertex, 0 on the boundary
/// and at unused vertices: the discrete Gaussian curvature each vertex holds.
pub fn angle_defects(mesh: &Mesh) -> Vec<f64> {
    let mut sum = vec![0.0; mesh.n_vertices()];
    for (t, angles) in mesh.triangles().iter().zip(corner_angles(mesh)) {
        for k in 0..3 {
            sum[t[k] as usize] += angles[k];
        }
    }
    (0..mesh.n_vertices() as u32)
        .map(|v| if mesh.is_isolated(v) || mesh.is_boundary_vertex(v) { 0.0 } else { TAU - sum[v as usize] })
        .collect()
}

/// The face's vertex nearest to `target` that is away from its curves (every neighbour in
/// the face too), else its nearest vertex at all: a node there leaves room for the new
/// curves.
pub fn nearest_vertex(mesh: &Mesh, layout: &SurfaceLayout, face: u32, target: Vec3) -> Option<u32> {
    let in_face = |v: u32| layout.vertex_face.get(v as usize) == Some(&face);
    let d2 = |v: u32| {
        let d = sub(mesh.position(v), target);
        dot(d, d)
    };
    let nearest = |inner: bool| {
        (0..mesh.n_vertices() as u32)
            .filter(|&v| in_face(v) && !mesh.is_isolated(v))
            .filter(|&v| !inner || (!mesh.is_boundary_vertex(v) && mesh.neighbors(v).all(in_face)))
            .min_by(|&a, &b| d2(a).total_cmp(&d2(b)))
    };
    nearest(true).or_else(|| nearest(false))
}

/// The weighted centroid of `points`, `None` when the weights sum to nothing.
fn centroid(points: impl Iterator<Item = (Vec3, f64)>) -> Option<Vec3> {
    let (mut sum, mut weight) = ([0.0; 3], 0.0);
    for (p, w) in points {
        for k in 0..3 {
            sum[k] += w * p[k];
        }
        weight += w;
    }
    (weight > 0.0 && weight.is_finite()).then(|| sum.map(|x| x / weight))
}

/// Per face: area, enclosed curvature and, where it needs a node, the suggested vertex: the
/// face's vertex nearest to the centroid of its curvature of K's sign (on a cap, the cap's
/// top; between two bumps, a point between them). Needs the layout only.
pub fn face_guidance(mesh: &Mesh, layout: &SurfaceLayout) -> Vec<FaceGuidance> {
    let defects = angle_defects(mesh);
    let n = layout.faces.len();
    let mut curvature = vec![0.0; n];
    for (v, &f) in layout.vertex_face.iter().enumerate() {
        if f != NONE {
            curvature[f as usize] += defects[v];
        }
    }
    let mut area = vec![0.0; n];
    for (t, &f) in mesh.triangles().iter().zip(&layout.triangle_face) {
        let p = t.map(|v| mesh.position(v));
        if let Some(a) = area.get_mut(f as usize) {
            *a += 0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        }
    }
    layout
        .faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let k = curvature[f];
            let needs_node = k.abs() > NEEDS_NODE;
            let suggestion = needs_node
                .then(|| {
                    let mass = (0..mesh.n_vertices())
                        .filter(|&v| layout.vertex_face[v] == f as u32)
                        .map(|v| (mesh.position(v as u32), (k.signum() * defects[v]).max(0.0)));
                    let vertex = nearest_vertex(mesh, layout, f as u32, centroid(mass)?)?;
                    Some(Suggestion { vertex, at: mesh.position(vertex), reason: "curvature" })
                })
                .flatten();
            FaceGuidance {
                face: f,
                corners: face.corner_nodes(),
                area: area[f],
                curvature_deg: k.to_degrees(),
                needs_node,
                distortion: None,
                length_error: None,
                suggestion,
            }
        })
        .collect()
}

/// The singular values σ₁ ≥ σ₂ of the map from the triangle `p` (3D) to `u` (its chart
/// corners): the square roots of the eigenvalues of G⁻¹H, with G and H the Gram matrices of
/// the two edge vectors in 3D and in the chart. `None` for a degenerate triangle.
pub fn stretches(p: [Vec3; 3], u: [[f64; 2]; 3]) -> Option<[f64; 2]> {
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let (d1, d2) = (sub2(u[1], u[0]), sub2(u[2], u[0]));
    let g = [dot(e1, e1), dot(e1, e2), dot(e2, e2)];
    let h = [dot2(d1, d1), dot2(d1, d2), dot2(d2, d2)];
    // det(H − λG) = a λ² − b λ + c.
    let a = g[0] * g[2] - g[1] * g[1];
    let b = g[0] * h[2] + g[2] * h[0] - 2.0 * g[1] * h[1];
    let c = h[0] * h[2] - h[1] * h[1];
    if !(a > 0.0 && a.is_finite() && b.is_finite() && c.is_finite()) {
        return None;
    }
    let root = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let (hi, lo) = ((b + root) / (2.0 * a), (b - root) / (2.0 * a));
    Some([hi.max(0.0).sqrt(), lo.max(0.0).sqrt()])
}

/// The relative length error of a map with singular values `sigma`: the root mean square of
/// σ − 1 over the two principal directions (0.1: lengths off by about 10 %). Near an isometry
/// the paper's ‖JᵀJ − I‖²_F is about 8 times its square.
pub fn length_error(sigma: [f64; 2]) -> f64 {
    (((sigma[0] - 1.0).powi(2) + (sigma[1] - 1.0).powi(2)) / 2.0).sqrt()
}

/// The area-weighted median of `(value, area)` pairs: half the area has a value at most this
/// (0 for no area).
fn weighted_median(mut pairs: Vec<(f64, f64)>) -> f64 {
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = 0.5 * pairs.iter().map(|p| p.1).sum::<f64>();
    let mut below = 0.0;
    for (v, a) in &pairs {
        below += a;
        if below >= half && below > 0.0 {
            return *v;
        }
    }
    0.0
}

/// Distortion of a solved parameterization per layout face and over all of it.
///
/// The length errors are measured with each face's chart scaled to the face's surface area
/// (by √(surface area / chart area)), as the quads are sized ([`crate::quad::density`]): a
/// chart that is uniformly smaller than its surface (the isometry energy keeps charts small
/// where the surface bulges, and unit charts have one common size) makes quads of the right
/// size all the same, so only what varies within a face (stretch in one direction against the
/// other, or from one part of the face to another) counts as error.
pub struct FaceDistortion {
    /// Per face: area-weighted mean of ‖JᵀJ − I‖²_F.
    pub distortion: Vec<f64>,
    /// Per face: the area-weighted median of its triangles' length errors (half its area has
    /// lengths off by less).
    pub length_error: Vec<f64>,
    /// The same over every triangle.
    pub length_error_all: f64,
    /// Per face: the area- and distortion-weighted centroid of its triangles (where its
    /// distortion concentrates).
    pub worst_at: Vec<Option<Vec3>>,
}

/// Measures the latest solution of `param` per face (see [`FaceDistortion`]).
pub fn face_distortion(param: &ParamSession, faces: usize) -> FaceDistortion {
    let cut = param.cut();
    let per_triangle = param.triangle_distortion();
    let surface = crate::quad::density::face_areas(cut, faces);
    let scale: Vec<f64> = (0..faces)
        .map(|f| {
            let s = (surface[f] / param.charts()[f].area()).sqrt();
            if s.is_finite() && s > 0.0 { s } else { 1.0 }
        })
        .collect();
    let mut area = vec![0.0; faces];
    let mut dist = vec![0.0; faces];
    let mut errors: Vec<Vec<(f64, f64)>> = vec![Vec::new(); faces];
    let mut mass: Vec<Vec<(Vec3, f64)>> = vec![Vec::new(); faces];
    for (t, uv) in param.solution().corner_uv.iter().enumerate() {
        let f = cut.triangle_face[t] as usize;
        let p = cut.triangles[t].map(|v| cut.positions[v as usize]);
        let a = 0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        let (Some(sigma), true) = (stretches(p, *uv), a > 0.0 && f < faces) else { continue };
        let e = length_error(sigma.map(|x| x * scale[f]));
        area[f] += a;
        dist[f] += a * per_triangle[t];
        errors[f].push((e, a));
        let middle = std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
        mass[f].push((middle, a * per_triangle[t]));
    }
    let mean = |sum: f64, a: f64| if a > 0.0 { sum / a } else { 0.0 };
    FaceDistortion {
        distortion: (0..faces).map(|f| mean(dist[f], area[f])).collect(),
        length_error: errors.iter().map(|e| weighted_median(e.clone())).collect(),
        length_error_all: weighted_median(errors.into_iter().flatten().collect()),
        worst_at: mass.into_iter().map(|m| centroid(m.into_iter())).collect(),
    }
}

/// [`face_guidance`] with each face's distortion after solving filled in; `distorted` lists
/// the faces the verdict finds far more distorted than the others: those without a curvature
/// suggestion get one where their distortion concentrates.
pub fn solved_face_guidance(
    mesh: &Mesh,
    layout: &SurfaceLayout,
    measured: &FaceDistortion,
    distorted: &[usize],
) -> Vec<FaceGuidance> {
    let mut faces = face_guidance(mesh, layout);
    for g in &mut faces {
        g.distortion = Some(measured.distortion[g.face]);
        g.length_error = Some(measured.length_error[g.face]);
        if g.suggestion.is_none() && distorted.contains(&g.face) {
            g.suggestion = measured.worst_at[g.face]
                .and_then(|at| nearest_vertex(mesh, layout, g.face as u32, at))
                .map(|vertex| Suggestion { vertex, at: mesh.position(vertex), reason: "distortion" });
        }
    }
    faces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::{parallelepiped, quad_grid};

    #[test]
    fn a_closed_surface_holds_four_pi_and_a_cube_corner_ninety_degrees() {
        let (cube, ids) = parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], 3);
        let d = angle_defects(&cube);
        // Gauss–Bonnet: 2πχ = 4π on a sphere-like surface.
        assert!((d.iter().sum::<f64>() - 2.0 * TAU).abs() < 1e-9);
        assert!((d[ids[&[0, 0, 0]] as usize] - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!(d[ids[&[1, 0, 0]] as usize].abs() < 1e-12, "a cube's edge is flat");
        // The boundary of a plane grid holds nothing, nor does its inside.
        assert!(angle_defects(&quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 3)).iter().all(|x| x.abs() < 1e-12));
    }

    #[test]
    fn stretches_of_known_maps() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0]];
        // An isometric unfolding: the second edge has length √2.
        let u = [[0.0, 0.0], [1.0, 0.0], [0.0, 2f64.sqrt()]];
        let s = stretches(p, u).unwrap();
        assert!((s[0] - 1.0).abs() < 1e-12 && (s[1] - 1.0).abs() < 1e-12, "{s:?}");
        // Stretched by 2 along the first edge, squeezed to 1/2 along the second.
        let u = [[0.0, 0.0], [2.0, 0.0], [0.0, 0.5 * 2f64.sqrt()]];
        let s = stretches(p, u).unwrap();
        assert!((s[0] - 2.0).abs() < 1e-12 && (s[1] - 0.5).abs() < 1e-12, "{s:?}");
        assert!((length_error(s) - (0.625f64).sqrt()).abs() < 1e-12);
        // A reflected image stretches alike; a degenerate triangle has none.
        assert_eq!(stretches(p, [[0.0, 0.0], [0.0, 1.0], [2f64.sqrt(), 0.0]]).map(|s| s.map(|x| (x * 1e9).round())), Some([1e9, 1e9]));
        assert_eq!(stretches([[0.0; 3]; 3], u), None);
    }
}
