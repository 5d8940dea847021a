//! Cross fields and the automatic coarse quad layout made from them (issue 22;
//! method-notes §11).
//!
//! [`compute_field`] finds the smoothest 4-direction field on the surface (Knöppel, Crane,
//! Pinkall, Schröder 2013), aligned to principal curvature directions where the surface is
//! clearly anisotropic, with sharp feature edges and the boundary as hard constraints, and its
//! singularities. [`propose`] builds the layout proposal on it.

pub mod arcs;
pub mod cells;
pub mod complex;
pub mod corners;
pub mod cross;
pub mod curvature;
pub mod faces;
pub mod features;
pub mod frames;
pub mod graph;
pub mod judge;
pub mod propose;
pub mod seamless;
pub mod separatrix;
pub mod singularities;
pub mod slivers;
pub mod trace;
pub mod waypoints;

pub use complex::Complex;
pub use features::{find_features, Features};
pub use frames::Frames;
pub use judge::Judged;
pub use propose::{pick, propose_layout, with_corners_chosen, Candidate, LayoutOptions, Proposal, ProposeError, Tracings};
pub use singularities::{singularities, Singularity};

use crate::geom::{norm, sub};
use crate::mesh::geometry::bounding_box;
use crate::mesh::Mesh;
use crate::solve::SolveError;

/// The default feature angle in degrees (cli.md, `--feature-angle`).
pub const DEFAULT_FEATURE_ANGLE: f64 = 35.0;

/// A cross field on a mesh with what it was made from.
#[derive(Debug, Clone)]
pub struct CrossField {
    pub frames: Frames,
    /// `e^{4iθ}` per vertex in its frame (zero for isolated vertices).
    pub z: Vec<Complex>,
    pub features: Features,
    pub singularities: Vec<Singularity>,
    /// Iso-lines of a seamless parameterization of the field ([`seamless::iso_lines`]) for
    /// traces to follow instead of the field; empty (the field itself) unless the automatic
    /// layout sets them.
    pub iso: seamless::IsoLines,
}

impl CrossField {
    /// The direction angle `θ` of one of the cross's four arms at `v`, in `v`'s frame.
    pub fn angle(&self, v: u32) -> f64 {
        self.z[v as usize].arg() / 4.0
    }

    /// The four unit arms of the cross at `v`, in space, counter-clockwise.
    pub fn arms(&self, v: u32) -> [[f64; 3]; 4] {
        let t = self.angle(v);
        std::array::from_fn(|k| self.frames.direction(v, t + k as f64 * std::f64::consts::FRAC_PI_2))
    }
}

/// The field for drawing (the page's field view): one arm of the cross per vertex and the
/// singularities with their valence.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FieldView {
    /// Per vertex, xyz of a unit arm of its cross (the other arms: turn it by 90° about the
    /// normal); zeros for isolated vertices.
    pub directions: Vec<f32>,
    /// Per singularity, xyz of the centroid of its triangle.
    pub singularity_positions: Vec<f32>,
    /// Per singularity, its valence (3, 5, ...).
    pub singularity_valences: Vec<i32>,
}

impl CrossField {
    /// The field as flat arrays for drawing.
    pub fn view(&self, mesh: &Mesh) -> FieldView {
        let directions = (0..mesh.n_vertices() as u32)
            .flat_map(|v| if mesh.is_isolated(v) { [0.0; 3] } else { self.arms(v)[0] }.map(|x| x as f32))
            .collect();
        let singularity_positions = self
            .singularities
            .iter()
            .flat_map(|s| {
                let p = mesh.triangles()[s.triangle as usize].map(|v| mesh.position(v));
                [0, 1, 2].map(|k| ((p[0][k] + p[1][k] + p[2][k]) / 3.0) as f32)
            })
            .collect();
        let singularity_valences = self.singularities.iter().map(Singularity::valence).collect();
        FieldView { directions, singularity_positions, singularity_valences }
    }
}

/// The cross at a vertex on feature lines or the boundary: the mean of its lines' directions
/// (to the fourth power), if they agree enough to define one (not at a corner where three
/// lines meet at 120°).
fn line_constraints(mesh: &Mesh, frames: &Frames, features: &Features) -> Vec<Option<Complex>> {
    (0..mesh.n_vertices() as u32)
        .map(|v| {
            if mesh.is_isolated(v) {
                return None;
            }
            let mut s = Complex::ZERO;
            let mut count = 0;
            for h in mesh.outgoing(v) {
                let e = mesh.edge(h);
                if features.sharp[e as usize] || mesh.is_boundary_edge(e) {
                    let d = sub(mesh.position(mesh.to_vertex(h)), mesh.position(v));
                    s = s + Complex::polar(1.0, 4.0 * frames.angle(v, d));
                    count += 1;
                }
            }
            (count > 0 && s.abs() > 0.5 * count as f64).then(|| s.unit())
        })
        .collect()
}

/// The length of the bounding-box diagonal.
pub fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = bounding_box(mesh);
    norm(sub(hi, lo))
}

/// The cross field of `mesh` with sharp edges above `feature_angle_deg` (and the boundary)
/// as constraints, and its singularities.
///
/// # Errors
/// [`SolveError`] if the sparse factorization fails (a degenerate mesh).
pub fn compute_field(mesh: &Mesh, feature_angle_deg: f64) -> Result<CrossField, SolveError> {
    field_in(mesh, Frames::new(mesh), find_features(mesh, feature_angle_deg), Guide::Curvature)
}

/// The smoothest cross field with `features` (its own, found once) and the boundary as its
/// only constraints: [`compute_field`] without the principal-curvature guide. Where the
/// curvature directions are noise at the scale of the quads (a scan's bumps, the wavy blend
/// of a CAD part), the guided field bends with them and its layout with it.
///
/// # Errors
/// [`SolveError`] if the sparse factorization fails (a degenerate mesh).
pub fn compute_unguided_field(mesh: &Mesh, features: Features) -> Result<CrossField, SolveError> {
    field_in(mesh, Frames::new(mesh), features, Guide::None)
}

/// [`compute_field`] with `features` (its own, found once) in frames whose normals are
/// diffused over `smoothing` times the bounding-box diagonal first, but not across the sharp
/// edges ([`Frames::smoothed`]): its singularities are where the smoothed surface turns, not
/// where each vertex of a noisy tessellation does.
///
/// # Errors
/// [`SolveError`] if a sparse factorization fails (a degenerate mesh).
pub fn compute_smoothed_field(mesh: &Mesh, features: Features, smoothing: f64) -> Result<CrossField, SolveError> {
    field_in(mesh, Frames::smoothed(mesh, smoothing * diagonal(mesh), &features.sharp)?, features, Guide::Curvature)
}

/// What steers a cross field besides its constraints.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Guide {
    /// Principal curvature directions where the surface is clearly anisotropic.
    Curvature,
    /// Nothing: the smoothest field.
    None,
}

/// The cross field in `frames` with `features` as constraints, steered by `guide`.
fn field_in(mesh: &Mesh, frames: Frames, features: Features, guide: Guide) -> Result<CrossField, SolveError> {
    let diag = diagonal(mesh);
    let guide = match guide {
        Guide::Curvature => curvature::curvature_guide(mesh, &frames, diag),
        Guide::None => vec![Complex::ZERO; mesh.n_vertices()],
    };
    let fixed = line_constraints(mesh, &frames, &features);
    let z = cross::cross_field(mesh, &frames, &guide, &fixed, diag)?;
    let singularities = singularities(mesh, &frames, &z);
    Ok(CrossField { frames, z, features, singularities, iso: seamless::IsoLines::default() })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::primitives::parallelepiped;
    use crate::mesh::{build_mesh, TriangleSoup};

    /// A cube's surface (n×n per side) pushed onto the unit sphere.
    pub fn sphere(n: u32) -> Mesh {
        let (cube, _) = parallelepiped([2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0], n);
        let positions = cube.positions().iter().map(|p| crate::geom::unit(sub(*p, [1.0, 1.0, 1.0]))).collect();
        build_mesh(TriangleSoup { positions, triangles: cube.triangles().to_vec(), ..Default::default() }).unwrap().mesh
    }

    /// A torus of revolution (radii `big`, `small`) as an n×m grid.
    pub fn torus(n: u32, m: u32, big: f64, small: f64) -> Mesh {
        let mut positions = Vec::new();
        for j in 0..m {
            for i in 0..n {
                let (u, v) = (i as f64 / n as f64 * std::f64::consts::TAU, j as f64 / m as f64 * std::f64::consts::TAU);
                let r = big + small * v.cos();
                positions.push([r * u.cos(), r * u.sin(), small * v.sin()]);
            }
        }
        let id = |i: u32, j: u32| (j % m) * n + (i % n);
        let mut triangles = Vec::new();
        for j in 0..m {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
        build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).unwrap().mesh
    }

    #[test]
    fn sphere_has_eight_valence_three_singularities() {
        let m = sphere(10);
        let f = compute_field(&m, DEFAULT_FEATURE_ANGLE).unwrap();
        let valences: Vec<i32> = f.singularities.iter().map(|s| s.valence()).collect();
        assert_eq!(valences, vec![3; 8], "{:?}", f.singularities);
        let view = f.view(&m);
        assert_eq!(view.directions.len(), 3 * m.n_vertices());
        assert_eq!((view.singularity_positions.len(), view.singularity_valences), (24, vec![3; 8]));
        // Each singularity sits on the unit sphere.
        for p in view.singularity_positions.chunks(3) {
            let r = p.iter().map(|&x| (x as f64).powi(2)).sum::<f64>().sqrt();
            assert!((r - 1.0).abs() < 0.05, "{p:?}");
        }
    }

    /// A saddle `z = c x y` over the square [-1, 1]², an n×n grid: its sides are straight,
    /// its principal directions at the centre are the diagonals x = ±y.
    fn saddle(n: u32, c: f64) -> Mesh {
        let at = |k: u32| 2.0 * k as f64 / n as f64 - 1.0;
        let positions = (0..=n).flat_map(|j| (0..=n).map(move |i| [at(i), at(j), c * at(i) * at(j)])).collect();
        let triangles = crate::mesh::primitives::grid_triangles(n);
        build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).unwrap().mesh
    }

    /// How far (degrees) the cross at `v` turns from the x and y axes, seen from above.
    fn off_axes(f: &CrossField, v: u32) -> f64 {
        let [x, y, _] = f.arms(v)[0];
        let a = y.atan2(x).to_degrees().rem_euclid(90.0);
        a.min(90.0 - a)
    }

    /// The guided field turns toward a saddle's principal directions in its middle; the
    /// smoothest field keeps to the directions of its sides. (On a torus the smoothest field
    /// is not the principal one, which turns against parallel transport along the parallels:
    /// it has 12 singularities on `torus(48, 16, 1.0, 0.35)`.)
    #[test]
    fn the_unguided_field_follows_the_boundary_where_the_guided_one_follows_the_curvature() {
        let n = 24;
        let m = saddle(n, 1.0);
        let centre = (n / 2) * (n + 1) + n / 2;
        let guided = compute_field(&m, DEFAULT_FEATURE_ANGLE).unwrap();
        let smoothest = compute_unguided_field(&m, find_features(&m, DEFAULT_FEATURE_ANGLE)).unwrap();
        let (g, u) = (off_axes(&guided, centre), off_axes(&smoothest, centre));
        assert!(g > 40.0 && u < 1.0, "guided {g:.1}°, smoothest {u:.1}° off the axes");
        // The guided field pays for its turn with singularities (8 here); the smoothest has none.
        assert!(!guided.singularities.is_empty());
        assert!(smoothest.singularities.is_empty(), "{:?}", smoothest.singularities);
    }

    #[test]
    fn torus_has_no_singularity() {
        let m = torus(48, 16, 1.0, 0.35);
        let f = compute_field(&m, DEFAULT_FEATURE_ANGLE).unwrap();
        assert!(f.singularities.is_empty(), "{:?}", f.singularities);
        // No sharp edges on a smooth torus.
        assert!(f.features.lines.is_empty());
    }
}
