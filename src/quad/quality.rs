//! Quality of a quad mesh against the surface it remeshes, in the terms of the paper's
//! introduction (Section 1): *regularity* (irregular vertices), *sizing* (edge-length
//! variation), element shape (corner angles, scaled Jacobians), orientation (quads flipped
//! against the input) and, for the results of Section 5, how far the quads stray from the
//! input (two-sided Hausdorff distance).
//!
//! Everything is measured on the quad mesh as it is: the scaled Jacobian follows Verdict
//! (Stimpson et al., *The Verdict Geometric Quality Library*, 2007) for non-planar quads, and
//! distances are exact point-to-triangle distances found through a [`TriangleTree`].
//!
//! # Degenerate input
//! [`measure`] never panics on a quad mesh, whatever it holds. A quad with a vertex index out
//! of range is left out of everything but `faces` and `flipped_quads`; a quad with a
//! non-finite corner is left out of the geometric measures the same way, and so are
//! vertices and edges with a non-finite position. Values that overflow (coordinates beyond
//! about 1e150) are left out too. Means and maxima over nothing are 0, so an empty quad mesh
//! measures all zeros (check `faces`), and every number is finite.

use super::closest::{closest_point_on_triangle, Hit, TriangleTree};
use super::QuadMesh;
use crate::geom::{self, add, cross, dot, norm, scale, sub, unit, Vec3};
use crate::mesh::geometry::bounding_box;
use crate::mesh::{Mesh, NONE};

/// Quality measures of a quad mesh; see [`measure`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Quality {
    /// Vertices of the quad mesh (all of them, used or not).
    pub vertices: usize,
    /// Quads.
    pub faces: usize,
    /// Vertices used by quads whose valence (number of distinct edges) is not the regular
    /// one: 4 inside, 3 on the boundary (a vertex of an edge used by exactly one quad).
    pub irregular_vertices: usize,
    /// The irregular vertices, sorted (for display; not serialized).
    #[serde(skip)]
    pub irregular: Vec<u32>,
    /// Mean over all quad corners of |corner angle − 90°|, in degrees; the angle is the 3D
    /// angle between the corner's two edges.
    pub angle_deviation_mean_deg: f64,
    /// Largest |corner angle − 90°| in degrees.
    pub angle_deviation_max_deg: f64,
    /// Standard deviation over mean of the lengths of the distinct edges (population
    /// standard deviation): 0 for edges of equal length.
    pub edge_length_cv: f64,
    /// Smallest per-quad scaled Jacobian (1 for a rectangle, sin α for a parallelogram with
    /// angle α, ≤ 0 for a folded or inverted corner).
    pub scaled_jacobian_min: f64,
    /// Mean over quads of the per-quad scaled Jacobian.
    pub scaled_jacobian_mean: f64,
    /// Quads whose normal (cross product of the diagonals) points against the normal of the
    /// input triangle nearest to the quad's centroid, plus degenerate quads (zero normal,
    /// non-finite corner or vertex index out of range).
    pub flipped_quads: usize,
    /// The flipped or degenerate quads, in order (for warnings; not serialized).
    #[serde(skip)]
    pub flipped: Vec<u32>,
    /// One-sided Hausdorff distance from the quad mesh to the input surface, divided by the
    /// diagonal of the input's bounding box.
    pub hausdorff_to_input: f64,
    /// One-sided Hausdorff distance from the input surface to the quad mesh, divided by the
    /// diagonal of the input's bounding box.
    pub hausdorff_from_input: f64,
    /// The larger of the two one-sided distances: the Hausdorff distance.
    pub hausdorff: f64,
    /// Where the quads miss the input by [`hausdorff`](Self::hausdorff): a point on the input
    /// surface (the input sample farthest from the quads, or the input's point nearest to the
    /// quad sample farthest from it). The origin when nothing was measured.
    pub hausdorff_at: Vec3,
}

/// Measures `quads` against the surface `input` it was made from.
///
/// The Hausdorff distances are sampled. The quad mesh is sampled at its used vertices, the
/// midpoints of its edges and a 3×3 lattice of bilinear points inside each quad (parameters
/// ¼, ½, ¾); the input at its non-isolated vertices and its triangle centroids. Each quad
/// counts as the two triangles on either side of its diagonal 0–2; distances to either
/// surface are exact.
///
/// Never panics; see the module documentation for degenerate quad meshes.
pub fn measure(input: &Mesh, quads: &QuadMesh) -> Quality {
    let n_vertices = quads.positions.len();
    let in_range: Vec<Option<[u32; 4]>> = quads
        .quads
        .iter()
        .map(|q| q.iter().all(|&v| (v as usize) < n_vertices).then_some(*q))
        .collect();
    let corners: Vec<Option<[Vec3; 4]>> = in_range
        .iter()
        .map(|q| {
            let p = q.as_ref()?.map(|v| quads.positions[v as usize]);
            p.iter().all(|&x| is_finite(x)).then_some(p)
        })
        .collect();
    let edges = EdgeTable::new(n_vertices, in_range.iter().flatten());
    let irregular = edges.irregular_vertices();

    let angles = Summary::of(corners.iter().flatten().flat_map(corner_angle_deviations));
    let jacobians = Summary::of(corners.iter().flatten().map(scaled_jacobian));
    let lengths: Vec<f64> = edges
        .edges
        .iter()
        .filter_map(|e| edges.segment(&quads.positions, e))
        .map(|[a, b]| norm(sub(b, a)))
        .filter(|l| l.is_finite())
        .collect();

    let input_tree = TriangleTree::new(
        input
            .triangles()
            .iter()
            .map(|t| t.map(|v| input.position(v))),
    );
    let flipped: Vec<u32> = (0..corners.len() as u32)
        .filter(|&q| is_flipped(input, &input_tree, corners[q as usize].as_ref()))
        .collect();

    let (hausdorff_to_input, hausdorff_from_input, hausdorff_at) = {
        let (lo, hi) = bounding_box(input);
        let diagonal = norm(sub(hi, lo));
        let relative = |d: f64| if diagonal > 0.0 { d / diagonal } else { 0.0 };
        let quad_tree = TriangleTree::new(
            corners
                .iter()
                .flatten()
                .flat_map(|&q| quad_triangles(q)),
        );
        let (to, to_at) = farthest(&input_tree, quad_samples(quads, &edges, &corners));
        let (from, from_at) = farthest(&quad_tree, input_samples(input));
        // A quad sample is off the surface: show the surface point nearest to it.
        let on_input = |p: Vec3| input_tree.closest(p).map_or(p, |hit| hit.point);
        let at = if from >= to { from_at } else { on_input(to_at) };
        (relative(to), relative(from), at)
    };

    Quality {
        vertices: n_vertices,
        faces: quads.quads.len(),
        irregular_vertices: irregular.len(),
        irregular,
        angle_deviation_mean_deg: angles.mean(),
        angle_deviation_max_deg: angles.max(),
        edge_length_cv: coefficient_of_variation(&lengths),
        scaled_jacobian_min: jacobians.min(),
        scaled_jacobian_mean: jacobians.mean(),
        flipped_quads: flipped.len(),
        flipped,
        hausdorff_to_input,
        hausdorff_from_input,
        hausdorff: hausdorff_to_input.max(hausdorff_from_input),
        hausdorff_at,
    }
}

fn is_finite(p: Vec3) -> bool {
    p.iter().all(|x| x.is_finite())
}

/// Per vertex of `quads` (below `n_vertices`), whether it is on the boundary: on an edge of
/// one quad only ([`EdgeTable`]).
pub(super) fn boundary_vertices(n_vertices: usize, quads: &[[u32; 4]]) -> Vec<bool> {
    EdgeTable::new(n_vertices, quads.iter()).on_boundary
}

/// The distinct edges of a quad mesh with the number of quads using each, and the valence
/// and boundary status of each vertex derived from them.
struct EdgeTable {
    /// `[a, b]` with `a < b`, sorted.
    edges: Vec<[u32; 2]>,
    valence: Vec<u32>,
    on_boundary: Vec<bool>,
}

impl EdgeTable {
    /// Precondition: every index in `quads` is below `n_vertices`.
    fn new<'a>(n_vertices: usize, quads: impl Iterator<Item = &'a [u32; 4]>) -> Self {
        let mut sides: Vec<[u32; 2]> = quads
            .flat_map(|q| (0..4).map(move |k| [q[k], q[(k + 1) % 4]]))
            // A repeated corner makes a side of no length, not an edge.
            .filter(|[a, b]| a != b)
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        sides.sort_unstable();
        let mut edges = Vec::with_capacity(sides.len() / 2 + 1);
        let mut valence = vec![0u32; n_vertices];
        let mut on_boundary = vec![false; n_vertices];
        for run in sides.chunk_by(|x, y| x == y) {
            let e = run[0];
            for v in e {
                valence[v as usize] += 1;
                on_boundary[v as usize] |= run.len() == 1;
            }
            edges.push(e);
        }
        EdgeTable {
            edges,
            valence,
            on_boundary,
        }
    }

    /// Used vertices whose valence differs from 4 (interior) or 3 (boundary), sorted.
    fn irregular_vertices(&self) -> Vec<u32> {
        (0..self.valence.len())
            .filter(|&v| {
                let regular = if self.on_boundary[v] { 3 } else { 4 };
                self.valence[v] != 0 && self.valence[v] != regular
            })
            .map(|v| v as u32)
            .collect()
    }

    /// The end points of `edge`, if both are finite.
    fn segment(&self, positions: &[Vec3], edge: &[u32; 2]) -> Option<[Vec3; 2]> {
        let ends = edge.map(|v| positions[v as usize]);
        ends.iter().all(|&p| is_finite(p)).then_some(ends)
    }
}

/// Count, sum, minimum and maximum of a sequence of values.
struct Summary {
    count: usize,
    sum: f64,
    min: f64,
    max: f64,
}

impl Summary {
    /// Non-finite values (only from coordinates so large that products overflow) are left
    /// out.
    fn of(values: impl Iterator<Item = f64>) -> Self {
        values.filter(|x| x.is_finite()).fold(
            Summary {
                count: 0,
                sum: 0.0,
                min: f64::INFINITY,
                max: f64::NEG_INFINITY,
            },
            |s, x| Summary {
                count: s.count + 1,
                sum: s.sum + x,
                min: s.min.min(x),
                max: s.max.max(x),
            },
        )
    }
    /// 0 for an empty sequence, like the other statistics, so that reports stay finite.
    fn mean(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.sum / self.count as f64
        }
    }
    fn min(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.min
        }
    }
    fn max(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.max
        }
    }
}

/// Standard deviation over mean, 0 for no values or a zero mean. Two passes: the one-pass
/// formula (mean of squares minus squared mean) loses all digits when the lengths are
/// nearly equal, which is exactly the case worth measuring.
fn coefficient_of_variation(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    // Zero, or infinite after an overflow: no scale to relate the deviation to.
    if !mean.is_normal() {
        return 0.0;
    }
    let variance = values.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    variance.sqrt() / mean
}

/// The two edge vectors leaving corner `k` of a quad: to the next and the previous corner.
fn corner_edges(q: &[Vec3; 4], k: usize) -> (Vec3, Vec3) {
    (sub(q[(k + 1) % 4], q[k]), sub(q[(k + 3) % 4], q[k]))
}

/// |angle − 90°| in degrees at each corner.
pub(super) fn corner_angle_deviations(q: &[Vec3; 4]) -> [f64; 4] {
    std::array::from_fn(|k| {
        let (u, v) = corner_edges(q, k);
        // atan2 stays accurate near 0° and 180°, unlike acos of the normalized dot product.
        (norm(cross(u, v)).atan2(dot(u, v)).to_degrees() - 90.0).abs()
    })
}

/// The quad's normal direction, unnormalized: the cross product of its diagonals, which is
/// twice the quad's vector area also when it is not planar. It points the same way as the
/// sum of the four corner cross products and as Verdict's "center normal" (the cross
/// product of the two lines joining opposite edge midpoints).
pub(super) fn quad_normal(q: &[Vec3; 4]) -> Vec3 {
    cross(sub(q[2], q[0]), sub(q[3], q[1]))
}

/// The two triangles of a quad on either side of its diagonal 0–2, as its distances to the
/// input are measured (and as the readers split it).
pub(super) fn quad_triangles([a, b, c, d]: [Vec3; 4]) -> [[Vec3; 3]; 2] {
    [[a, b, c], [a, c, d]]
}

/// The mean of the quad's corners.
pub(super) fn quad_centre(q: &[Vec3; 4]) -> Vec3 {
    scale(0.25, q.iter().fold([0.0; 3], |s, &x| add(s, x)))
}

/// Verdict's quad scaled Jacobian: the minimum over corners of `(e1 × e2) · n / (|e1| |e2|)`
/// with `n` the unit [`quad_normal`]. 0 for a quad with a zero-length edge or a zero normal
/// (Verdict also returns 0 for zero-length edges).
pub(super) fn scaled_jacobian(q: &[Vec3; 4]) -> f64 {
    let n = quad_normal(q);
    let n_len = norm(n);
    // Zero for a degenerate quad, infinite when huge coordinates overflow.
    if !n_len.is_normal() {
        return 0.0;
    }
    (0..4)
        .map(|k| {
            let (u, v) = corner_edges(q, k);
            let scale = norm(u) * norm(v) * n_len;
            if scale > 0.0 {
                dot(cross(u, v), n) / scale
            } else {
                0.0
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether a quad (`None`: index out of range or non-finite corner) is degenerate or faces
/// away from the input's surface at the point nearest to its centroid.
fn is_flipped(input: &Mesh, tree: &TriangleTree, quad: Option<&[Vec3; 4]>) -> bool {
    let Some(q) = quad else { return true };
    let n = quad_normal(q);
    if !norm(n).is_normal() {
        return true;
    }
    let centroid: Vec3 = std::array::from_fn(|k| q.iter().map(|p| p[k]).sum::<f64>() / 4.0);
    let Some(hit) = tree.closest(centroid) else {
        return false;
    };
    let corners = |t: u32| input.triangles()[t as usize].map(|v| input.position(v));
    let around = || {
        let corners = input.triangles()[hit.triangle as usize];
        corners.iter().flat_map(|&v| input.outgoing(v).map(|h| input.face(h))).filter(|&t| t != NONE).collect()
    };
    dot(n, pseudo_normal(corners, around, centroid, &hit)) < 0.0
}

/// The distance from `p` to the segment from `a` to `b`.
fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let (ab, ap) = (sub(b, a), sub(p, a));
    let t = (dot(ab, ap) / dot(ab, ab)).clamp(0.0, 1.0);
    let t = if t.is_finite() { t } else { 0.0 };
    norm(sub(ap, ab.map(|x| x * t)))
}

/// The surface's normal at the point nearest to `p` (`hit`), as Bærentzen and Aanæs define
/// it to tell the sides of a surface apart (*Signed distance computation using the angle
/// weighted pseudonormal*, 2005): a triangle's normal inside it, the sum of the two normals on
/// an edge, the sum weighted by the angles at a vertex. On an edge or a vertex the triangles
/// round it are as near as the one the search returned, and which of them it returns is
/// chance: a quad spanning a sharp edge of fandisk, facing along one side, counted as folded
/// when the other side came first. `corners` gives a triangle's corners, `around` the
/// triangles that share a vertex with the nearest one (asked only where the point lies on its
/// border).
pub(super) fn pseudo_normal(corners: impl Fn(u32) -> [Vec3; 3], around: impl FnOnce() -> Vec<u32>, p: Vec3, hit: &Hit) -> Vec3 {
    let (nearest, distance) = (hit.triangle, hit.distance_squared.sqrt());
    let [a, b, c] = corners(nearest);
    let size = norm(sub(b, a)).max(norm(sub(c, a))).max(norm(sub(c, b)));
    let tie = 1e-9 * (distance + size);
    // Inside its triangle (as a rule) the point has that triangle's normal alone.
    if [(a, b), (b, c), (c, a)].iter().all(|&(x, y)| segment_distance(hit.point, x, y) > tie) {
        return cross(sub(b, a), sub(c, a));
    }
    let mut around = around();
    around.sort_unstable();
    around.dedup();
    let mut sum = [0.0; 3];
    for t in around {
        let [a, b, c] = corners(t);
        let at = closest_point_on_triangle(p, a, b, c);
        if t != nearest && norm(sub(at, p)) > distance + tie {
            continue;
        }
        // The angle of the triangle at the point: at one of its corners, that corner's; on an
        // edge or inside, the same for every triangle there.
        let angle = [(a, b, c), (b, c, a), (c, a, b)]
            .iter()
            .find(|(x, _, _)| norm(sub(*x, at)) <= tie)
            .map_or(std::f64::consts::PI, |&(x, y, z)| geom::angle(sub(y, x), sub(z, x)));
        sum = add(sum, scale(angle, unit(cross(sub(b, a), sub(c, a)))));
    }
    sum
}

/// Largest distance from any of `samples` to the triangles of `tree` and the sample that has
/// it (0 and the origin if none is found).
fn farthest(tree: &TriangleTree, samples: impl Iterator<Item = Vec3>) -> (f64, Vec3) {
    let mut leaf = 0;
    let (d2, at) = samples.fold((0.0, [0.0; 3]), |(farthest, at): (f64, Vec3), p| {
        match tree.distance_squared_beyond(p, farthest, &mut leaf) {
            Some(d) if d.is_finite() && d > farthest => (d, p),
            _ => (farthest, at),
        }
    });
    (d2.sqrt(), at)
}

/// Bilinear parameters of the samples inside each quad.
const INTERIOR: [f64; 3] = [0.25, 0.5, 0.75];

/// The quad mesh's samples: used vertices, edge midpoints, 3×3 bilinear points per quad.
/// Non-finite ones are dropped by the tree query.
fn quad_samples<'a>(
    quads: &'a QuadMesh,
    edges: &'a EdgeTable,
    corners: &'a [Option<[Vec3; 4]>],
) -> impl Iterator<Item = Vec3> + 'a {
    let vertices = (0..quads.positions.len())
        .filter(|&v| edges.valence[v] > 0)
        .map(|v| quads.positions[v]);
    let midpoints = edges.edges.iter().map(|&[a, b]| {
        let (p, q) = (quads.positions[a as usize], quads.positions[b as usize]);
        std::array::from_fn(|k| 0.5 * (p[k] + q[k]))
    });
    let interior = corners.iter().flatten().flat_map(|q| {
        INTERIOR.into_iter().flat_map(move |t| {
            INTERIOR.into_iter().map(move |s| {
                let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
                std::array::from_fn(|k| (0..4).map(|i| w[i] * q[i][k]).sum())
            })
        })
    });
    vertices.chain(midpoints).chain(interior)
}

/// The input's samples: vertices that belong to faces and triangle centroids.
fn input_samples(input: &Mesh) -> impl Iterator<Item = Vec3> + '_ {
    let vertices = (0..input.n_vertices() as u32)
        .filter(|&v| !input.is_isolated(v))
        .map(|v| input.position(v));
    let centroids = input.triangles().iter().map(|t| {
        let p = t.map(|v| input.position(v));
        std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0)
    });
    vertices.chain(centroids)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::{parallelepiped, quad_grid};
    use crate::mesh::{build_mesh, TriangleSoup};
    use std::collections::HashMap;

    const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];

    /// The quads of an n×n grid whose vertex (i, j) is `j (n + 1) + i`, counter-clockwise.
    fn grid_quads(n: u32) -> Vec<[u32; 4]> {
        let id = |i: u32, j: u32| j * (n + 1) + i;
        (0..n)
            .flat_map(|j| {
                (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            })
            .collect()
    }

    /// An n×n quad grid over the planar quadrilateral `corners`, vertices as in
    /// [`quad_grid`].
    fn grid(corners: [[f64; 2]; 4], n: u32) -> QuadMesh {
        let positions = quad_grid(corners, n).positions().to_vec();
        QuadMesh {
            vertex_node: vec![crate::mesh::NONE; positions.len()],
            positions,
            quads: grid_quads(n),
        }
    }

    /// The unit cube's surface as n×n quads per face on the vertices of
    /// `parallelepiped(unit axes, n)`, facing outwards like its triangles, with that mesh.
    fn cube(n: u32) -> (Mesh, QuadMesh) {
        let (mesh, ids) = parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], n);
        (
            mesh.clone(),
            QuadMesh {
                positions: mesh.positions().to_vec(),
                quads: cube_quads(n, &ids),
                vertex_node: vec![],
            },
        )
    }

    /// Quads over the lattice of `parallelepiped`, oriented as its faces: on each side the
    /// in-plane axes (u, v) are ordered so that u × v points outwards.
    fn cube_quads(n: u32, ids: &HashMap<[u32; 3], u32>) -> Vec<[u32; 4]> {
        let mut quads = Vec::new();
        for axis in 0..3 {
            for high in [false, true] {
                let (u, v) = if high {
                    ((axis + 1) % 3, (axis + 2) % 3)
                } else {
                    ((axis + 2) % 3, (axis + 1) % 3)
                };
                let vertex = |i: u32, j: u32| {
                    let mut g = [0u32; 3];
                    g[axis] = if high { n } else { 0 };
                    g[u] = i;
                    g[v] = j;
                    ids[&g]
                };
                for j in 0..n {
                    for i in 0..n {
                        quads.push([
                            vertex(i, j),
                            vertex(i + 1, j),
                            vertex(i + 1, j + 1),
                            vertex(i, j + 1),
                        ]);
                    }
                }
            }
        }
        quads
    }

    fn assert_close(actual: f64, expected: f64, tolerance: f64, what: &str) {
        assert!(
            (actual - expected).abs() <= tolerance,
            "{what}: {actual} instead of {expected}"
        );
    }

    #[test]
    fn a_square_grid_on_its_own_plane_is_perfect_but_for_its_corners() {
        let n = 5;
        // A different triangulation of the same square: the surfaces coincide, the vertices do not.
        let q = measure(&quad_grid(SQUARE, 7), &grid(SQUARE, n));
        assert_eq!((q.vertices, q.faces, q.flipped_quads), (36, 25, 0));
        assert_eq!(q.irregular, vec![0, n, n * (n + 1), (n + 1) * (n + 1) - 1]);
        assert_eq!(q.irregular_vertices, 4);
        assert_close(
            q.angle_deviation_mean_deg,
            0.0,
            1e-12,
            "mean angle deviation",
        );
        assert_close(q.angle_deviation_max_deg, 0.0, 1e-12, "max angle deviation");
        assert_close(q.edge_length_cv, 0.0, 1e-12, "edge-length cv");
        assert_close(q.scaled_jacobian_min, 1.0, 1e-12, "min scaled Jacobian");
        assert_close(q.scaled_jacobian_mean, 1.0, 1e-12, "mean scaled Jacobian");
        assert_close(q.hausdorff, 0.0, 1e-12, "Hausdorff");
    }

    #[test]
    fn a_rhombus_grid_deviates_by_its_angle_and_has_jacobian_sin_angle() {
        let angle = 60f64.to_radians();
        let (c, s) = (angle.cos(), angle.sin());
        let rhombus = [[0.0, 0.0], [1.0, 0.0], [1.0 + c, s], [c, s]];
        let q = measure(&quad_grid(rhombus, 4), &grid(rhombus, 6));
        // Corners alternate 60° and 120°: 30° off either way.
        assert_close(
            q.angle_deviation_mean_deg,
            30.0,
            1e-10,
            "mean angle deviation",
        );
        assert_close(
            q.angle_deviation_max_deg,
            30.0,
            1e-10,
            "max angle deviation",
        );
        assert_close(q.scaled_jacobian_min, s, 1e-12, "min scaled Jacobian");
        assert_close(q.scaled_jacobian_mean, s, 1e-12, "mean scaled Jacobian");
        // All sides of a rhombus have the same length, and so do those of its grid.
        assert_close(q.edge_length_cv, 0.0, 1e-12, "edge-length cv");
        assert_close(q.hausdorff, 0.0, 1e-12, "Hausdorff");
        assert_eq!((q.irregular_vertices, q.flipped_quads), (4, 0));
    }

    #[test]
    fn a_rectangle_grid_has_the_edge_length_variation_of_its_two_lengths() {
        // Edges of length 1 (5·4 of them) and 2 (4·5 of them): mean 1.5, deviation 0.5.
        let rectangle = [[0.0, 0.0], [4.0, 0.0], [4.0, 8.0], [0.0, 8.0]];
        let q = measure(&quad_grid(rectangle, 3), &grid(rectangle, 4));
        assert_close(q.edge_length_cv, 1.0 / 3.0, 1e-12, "edge-length cv");
        assert_close(q.scaled_jacobian_min, 1.0, 1e-12, "min scaled Jacobian");
    }

    #[test]
    fn a_grid_lifted_off_its_plane_is_as_far_as_the_lift_both_ways() {
        let h = 0.125;
        let mut quads = grid(SQUARE, 4);
        for p in &mut quads.positions {
            p[2] += h;
        }
        let q = measure(&quad_grid(SQUARE, 6), &quads);
        let diagonal = 8f64.sqrt();
        assert_close(q.hausdorff_to_input, h / diagonal, 1e-14, "quads to input");
        assert_close(
            q.hausdorff_from_input,
            h / diagonal,
            1e-14,
            "input to quads",
        );
        assert_close(q.hausdorff, h / diagonal, 1e-14, "Hausdorff");
        // The lift is a translation: shape and orientation are untouched.
        assert_eq!(q.flipped_quads, 0);
    }

    #[test]
    fn a_grid_missing_part_of_the_surface_is_far_from_it_one_way_only() {
        // The quads cover [0, 2] × [0, 1] of the square [0, 2]²: the input's points at y = 2
        // are 1 away from the quads, while every quad lies on the input.
        let q = measure(
            &quad_grid(SQUARE, 8),
            &grid([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]], 4),
        );
        assert_close(q.hausdorff_to_input, 0.0, 1e-12, "quads to input");
        assert_close(
            q.hausdorff_from_input,
            1.0 / 8f64.sqrt(),
            1e-12,
            "input to quads",
        );
        assert_eq!(q.hausdorff, q.hausdorff_from_input);
    }

    #[test]
    fn a_cube_of_quads_lies_on_the_cube_with_eight_corners_of_valence_three() {
        let n = 3;
        let (input, quads) = cube(n);
        let q = measure(&input, &quads);
        assert_eq!((q.faces, q.flipped_quads), (6 * 9, 0));
        let (_, ids) = parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], n);
        let mut corners: Vec<u32> = (0..8)
            .map(|k: u32| ids[&[k & 1, (k >> 1) & 1, k >> 2].map(|x| x * n)])
            .collect();
        corners.sort_unstable();
        assert_eq!(q.irregular, corners);
        assert_close(q.hausdorff, 0.0, 1e-12, "Hausdorff");
        assert_close(q.scaled_jacobian_min, 1.0, 1e-12, "min scaled Jacobian");
        assert_close(q.edge_length_cv, 0.0, 1e-12, "edge-length cv");
    }

    #[test]
    fn a_reversed_quad_is_flipped_and_keeps_the_valences() {
        let (input, mut quads) = cube(2);
        quads.quads[5].reverse();
        let q = measure(&input, &quads);
        assert_eq!((q.flipped_quads, q.irregular_vertices), (1, 8));
        // Each quad is measured against its own normal: a reversed one is still a square.
        assert_close(q.scaled_jacobian_min, 1.0, 1e-12, "min scaled Jacobian");

        let mut quads = grid(SQUARE, 3);
        quads.quads[4].reverse();
        quads.quads[7].reverse();
        assert_eq!(measure(&quad_grid(SQUARE, 3), &quads).flipped_quads, 2);
    }

    #[test]
    fn a_quad_over_a_sharp_edge_is_judged_by_both_sides() {
        // Two unit squares meeting at a right angle along the z axis (normals +y and +x), and
        // a quad tilted a little from the first's plane over the edge: its centre is as near
        // to both, and it faces the surface the way the two sides do together, whichever
        // triangle the search meets first.
        let e = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        let positions = vec![e[0], e[1], [-1.0, 0.0, 0.0], [-1.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.0, -1.0, 1.0]];
        let side_y = [[2, 3, 1], [2, 1, 0]];
        let side_x = [[0, 1, 5], [0, 5, 4]];
        let (c, u, v) = ([0.1, 0.1, 0.5], [0.2, 0.02, 0.0], [0.0, 0.0, 0.2]);
        let at = |a: f64, b: f64| std::array::from_fn(|k| c[k] + a * u[k] + b * v[k]);
        let quad = QuadMesh { positions: vec![at(-1.0, -1.0), at(-1.0, 1.0), at(1.0, 1.0), at(1.0, -1.0)], quads: vec![[0, 1, 2, 3]], vertex_node: vec![] };
        let mut reversed = quad.clone();
        reversed.quads[0].reverse();
        for triangles in [[side_y, side_x].concat(), [side_x, side_y].concat()] {
            let input = build_mesh(TriangleSoup { positions: positions.clone(), triangles, ..Default::default() }).unwrap().mesh;
            assert_eq!(measure(&input, &quad).flipped_quads, 0);
            assert_eq!(measure(&input, &reversed).flipped_quads, 1);
        }
    }

    #[test]
    fn a_folded_quad_has_a_negative_jacobian_and_a_crossed_one_counts_as_flipped() {
        let input = quad_grid(SQUARE, 2);
        // A dart: corner 2 pushed past the diagonal 1–3 is a reflex corner.
        let dart = QuadMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.5, 0.5, 0.0],
                [0.0, 2.0, 0.0],
            ],
            quads: vec![[0, 1, 2, 3]],
            vertex_node: vec![],
        };
        let q = measure(&input, &dart);
        assert!(q.scaled_jacobian_min < 0.0, "{q:?}");
        assert_eq!(q.flipped_quads, 0);
        // A bow tie: its diagonals are parallel, so it has no normal.
        let mut bow_tie = grid(SQUARE, 1);
        bow_tie.quads = vec![[0, 1, 2, 3].map(|k| bow_tie.quads[0][[0, 1, 3, 2][k]])];
        let q = measure(&input, &bow_tie);
        assert_eq!((q.flipped_quads, q.scaled_jacobian_min), (1, 0.0));
    }

    #[test]
    fn isolated_input_vertices_are_not_sampled() {
        let mut soup = TriangleSoup {
            positions: quad_grid(SQUARE, 2).positions().to_vec(),
            triangles: crate::mesh::primitives::grid_triangles(2),
            ..Default::default()
        };
        // Far away, but part of no face: not part of the surface.
        soup.positions.push([1.0, 1.0, 50.0]);
        let input = build_mesh(soup).unwrap().mesh;
        let q = measure(&input, &grid(SQUARE, 2));
        assert_close(q.hausdorff, 0.0, 1e-12, "Hausdorff");
    }

    fn assert_all_finite(q: &Quality) {
        let values = [
            q.angle_deviation_mean_deg,
            q.angle_deviation_max_deg,
            q.edge_length_cv,
            q.scaled_jacobian_min,
            q.scaled_jacobian_mean,
            q.hausdorff_to_input,
            q.hausdorff_from_input,
            q.hausdorff,
        ];
        assert!(values.iter().all(|x| x.is_finite()), "{q:?}");
    }

    #[test]
    fn degenerate_quad_meshes_measure_finite_numbers() {
        let input = quad_grid(SQUARE, 2);
        let empty = measure(&input, &QuadMesh::default());
        assert_eq!(
            empty,
            Quality {
                vertices: 0,
                faces: 0,
                irregular_vertices: 0,
                irregular: vec![],
                angle_deviation_mean_deg: 0.0,
                angle_deviation_max_deg: 0.0,
                edge_length_cv: 0.0,
                scaled_jacobian_min: 0.0,
                scaled_jacobian_mean: 0.0,
                flipped_quads: 0,
                flipped: vec![],
                hausdorff_to_input: 0.0,
                hausdorff_from_input: 0.0,
                hausdorff: 0.0,
                hausdorff_at: [0.0; 3],
            }
        );

        let mut broken = grid(SQUARE, 3);
        broken.positions[5] = [f64::NAN, 0.0, f64::INFINITY];
        broken.quads.push([0, 1, 99, 2]);
        broken.quads.push([3, 3, 3, 3]);
        let q = measure(&input, &broken);
        assert_all_finite(&q);
        let mut huge = broken.clone();
        huge.positions[10] = [1e200, -1e300, 1e250];
        assert_all_finite(&measure(&input, &huge));
        // The four quads at vertex 5 have a non-finite corner, the last two are degenerate.
        assert_eq!((q.faces, q.flipped_quads), (11, 6));
        assert_eq!(q.flipped, vec![0, 1, 3, 4, 9, 10]);
        // The remaining quads still lie on the surface.
        assert_close(q.hausdorff_to_input, 0.0, 1e-12, "quads to input");
        assert_close(q.scaled_jacobian_min, 0.0, 0.0, "the point quad's Jacobian");
    }

    #[test]
    fn the_worst_miss_is_placed_on_the_input() {
        // A 4×4 grid over the 2×2 square with its vertex (1, 2) lifted by 0.5: the quads miss
        // the plane most there, and the point shown is the plane's point below it.
        let input = quad_grid(SQUARE, 2);
        let mut lifted = grid(SQUARE, 4);
        let v = 2 * 5 + 1;
        lifted.positions[v][2] = 0.5;
        let q = measure(&input, &lifted);
        assert_close(q.hausdorff, 0.5 / 8f64.sqrt(), 1e-12, "Hausdorff over the diagonal");
        let [x, y, _] = lifted.positions[v];
        assert_eq!(q.hausdorff_at, [x, y, 0.0]);
        // A quad mesh that leaves out part of the input: the input's farthest sample.
        let mut part = grid(SQUARE, 4);
        part.quads.truncate(8);
        let q = measure(&input, &part);
        assert!(q.hausdorff_from_input > q.hausdorff_to_input);
        assert!(q.hausdorff_at[1] > 1.9, "the far side of the square: {:?}", q.hausdorff_at);
    }

    #[test]
    fn serialized_quality_leaves_out_the_vertex_list() {
        let q = measure(&quad_grid(SQUARE, 2), &grid(SQUARE, 2));
        let json = serde_json::to_value(&q).unwrap();
        assert!(json.get("irregular").is_none());
        assert_eq!(json["irregular_vertices"], 4);
        assert_eq!(json["faces"], 4);
    }

    /// Speed on a sphere: 55 488 input triangles against 4 056 quads (8 112 triangles) and
    /// 8 214 quads. Run with
    /// `cargo test --release --lib quad::quality::tests::speed -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn speed() {
        let sphere = |n: u32| {
            let (mesh, ids) = parallelepiped([2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0], n);
            let positions: Vec<Vec3> = mesh
                .positions()
                .iter()
                .map(|p| {
                    let d = p.map(|x| x - 1.0);
                    d.map(|x| x / norm(d))
                })
                .collect();
            (positions, mesh.triangles().to_vec(), ids)
        };
        let (positions, triangles, _) = sphere(68);
        let input = build_mesh(TriangleSoup {
            positions,
            triangles,
            ..Default::default()
        })
        .unwrap()
        .mesh;
        for n in [26, 37] {
            let (positions, _, ids) = sphere(n);
            let quads = QuadMesh {
                positions,
                quads: cube_quads(n, &ids),
                vertex_node: vec![],
            };
            let start = std::time::Instant::now();
            let q = measure(&input, &quads);
            let seconds = start.elapsed().as_secs_f64();
            println!(
                "{} input triangles, {} quads: {seconds:.3} s, Hausdorff {:.2e}",
                input.n_faces(),
                q.faces,
                q.hausdorff
            );
            assert_eq!((q.flipped_quads, q.irregular_vertices), (0, 8));
            assert!(q.hausdorff < 1e-2, "{q:?}");
        }
    }
}
