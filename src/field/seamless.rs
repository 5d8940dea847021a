//! The cross field made integrable: a seamless parameterization `(u, v)` whose gradients follow
//! the field as closely as a gradient can (method-notes §11; the field-aligned global
//! parameterization of Kälberer, Nieser, Polthier 2007 and Bommes, Zimmer, Kobbelt 2009, *Mixed-
//! Integer Quadrangulation*, without the integer part), and the directions of its iso-lines.
//!
//! Why: traces that follow the smoothest cross field spiral where the field has curl, so the
//! two traces bounding a strip of quads part in one place and close in another, and a face's
//! opposite sides end up two to five times different in length; the sample counts, equal on
//! opposite sides, then stretch the quads of one side by as much. Iso-lines of one
//! parameterization do not: every face they bound is a rectangle in `(u, v)`, its opposite
//! sides equally long there (Myles, Pietroni, Zorin 2014 trace their motorcycle graph so).
//!
//! 1. Each triangle gets the mean of its corners' crosses; a spanning tree of the dual graph
//!    picks one arm per triangle so that the arms agree across the tree's edges, and across
//!    every other edge the arms differ by a quarter turn `k` (the matching).
//! 2. The cut: the edges off the tree, pruned of branches that end at a vertex where the
//!    matchings around add up to a whole turn (no cone there). What is left joins the cones,
//!    the handles and the boundary loops.
//! 3. `(u, v)` per wedge (the corners of a vertex between two cuts) minimizes
//!    `Σ_t A_t (|∇u − a_t|² + |∇v − b_t|²)`, `(a_t, b_t)` the triangle's arm and the arm a quarter
//!    turn on; across a cut edge the two sides' differences along it must agree up to the
//!    rotation by `k` (a heavy penalty: seamless up to a translation per cut).
//! 4. Per triangle, the directions in which `v` and `u` stay constant.
//!
//! A second parameterization solves again with each triangle's arms as long as the gradients
//! of the solve before (the same factor, a new right-hand side): its seams and shear fall
//! elsewhere. Neither wins everywhere; [`super::judge`] keeps the better layout.

use super::frames::wrap;
use super::{Complex, CrossField};
use crate::geom::{add, cross, dot, norm, scale, sub, unit, Vec3};
use crate::mesh::{Mesh, NONE};
use crate::solve::{sum_duplicates, SolveError, SpdSolver};
use std::f64::consts::FRAC_PI_2;

/// Weight of a seam equation against the field's fit (dimensionless; both are lengths squared
/// per unit area): large, so the two sides of a cut agree to a small fraction of an edge.
const SEAM_WEIGHT: f64 = 1e4;
/// Relative ridge on the diagonal: pins the free translation of each component.
const RIDGE: f64 = 1e-9;

/// The parameterization's iso-lines and cones.
#[derive(Debug, Clone, Default)]
pub struct IsoLines {
    /// Per triangle: the unit directions along which `v` and along which `u` stay constant (the
    /// parameterization's `u` and `v` axes on the surface); `None` where the parameterization
    /// folds or the triangle is degenerate.
    pub arms: Vec<Option<[Vec3; 2]>>,
    /// Per vertex: whether the parameterization has a cone there (a singularity of the
    /// triangles' field).
    pub cone: Vec<bool>,
}

/// A triangle's frame: unit normal and an orthonormal tangent basis.
struct FaceFrame {
    n: Vec3,
    x: Vec3,
    y: Vec3,
}

impl FaceFrame {
    fn new(p: [Vec3; 3]) -> Option<FaceFrame> {
        let n = unit(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        let x = unit(sub(p[1], p[0]));
        (n != [0.0; 3] && x != [0.0; 3]).then(|| FaceFrame { n, x, y: cross(n, x) })
    }
    fn angle(&self, a: Vec3) -> f64 {
        dot(a, self.y).atan2(dot(a, self.x))
    }
    fn direction(&self, theta: f64) -> Vec3 {
        add(scale(theta.cos(), self.x), scale(theta.sin(), self.y))
    }
}

/// Solves of the second parameterization, each asking for the scale the one before took.
const SCALE_ROUNDS: usize = 3;

/// The iso-line directions of the field's seamless parameterization (see the module
/// documentation), and of the second one that asks for the scale the first took: one cut, one
/// factorization.
///
/// # Errors
/// [`SolveError`] if the sparse factorization fails (a degenerate mesh).
pub fn iso_lines(mesh: &Mesh, field: &CrossField) -> Result<[IsoLines; 2], SolveError> {
    let frames: Vec<Option<FaceFrame>> = (0..mesh.n_faces()).map(|f| FaceFrame::new(corners(mesh, f))).collect();
    let hats: Vec<Option<Hats>> = frames.iter().enumerate().map(|(f, fr)| fr.as_ref().map(|fr| Hats::new(fr, corners(mesh, f)))).collect();
    let matched = match_arms(mesh, field, &frames);
    let (cut, cone) = cut_graph(mesh, &matched);
    let (wedge, wedges) = wedges(mesh, &cut);
    let [unit_scale, scaled] = solve(mesh, &frames, &hats, &matched, &cut, &wedge, wedges)?;
    let lines = |x: &[f64]| -> Vec<Option<[Vec3; 2]>> {
        (0..mesh.n_faces())
            .map(|f| {
                let (fr, h) = (frames[f].as_ref()?, hats[f].as_ref()?);
                let (gu, gv) = gradient_of(x, &wedge, f, &h.g);
                // Folded (or flat) where the gradients turn the wrong way round.
                (dot(cross(gu, gv), fr.n) > 0.0).then(|| [unit(cross(gv, fr.n)), unit(cross(fr.n, gu))])
            })
            .collect()
    };
    Ok([IsoLines { arms: lines(&unit_scale), cone: cone.clone() }, IsoLines { arms: lines(&scaled), cone }])
}

/// A triangle's area and the gradients of its three hat functions (corner `i`: 1 at `p[i]`,
/// 0 at the others), in its plane.
struct Hats {
    area: f64,
    g: [Vec3; 3],
}

impl Hats {
    fn new(fr: &FaceFrame, p: [Vec3; 3]) -> Hats {
        let area2 = norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        Hats { area: area2 / 2.0, g: std::array::from_fn(|i| scale(1.0 / area2, cross(fr.n, sub(p[(i + 2) % 3], p[(i + 1) % 3])))) }
    }
}

/// The positions of triangle `f`'s corners.
fn corners(mesh: &Mesh, f: usize) -> [Vec3; 3] {
    mesh.triangles()[f].map(|v| mesh.position(v))
}

/// One arm per triangle, agreeing across the dual spanning tree's edges, and the matching
/// across the others.
struct Matched {
    /// Per triangle: the angle of its arm in its frame.
    arm: Vec<f64>,
    /// Per edge: crossed by the dual spanning tree.
    tree: Vec<bool>,
    /// Per edge: the quarter turns from the arm of face(2e), carried over the edge, to the arm
    /// of face(2e + 1); 0 on the tree and the boundary.
    matching: Vec<i32>,
}

fn match_arms(mesh: &Mesh, field: &CrossField, frames: &[Option<FaceFrame>]) -> Matched {
    let nf = mesh.n_faces();
    // The mean of the corners' crosses (as e^{4iθ}), as the angle of one arm.
    let mean: Vec<f64> = (0..nf)
        .map(|f| {
            let Some(fr) = &frames[f] else { return 0.0 };
            let s = mesh.triangles()[f].iter().fold(Complex::ZERO, |s, &v| s + Complex::polar(1.0, 4.0 * fr.angle(field.arms(v)[0])));
            s.arg() / 4.0
        })
        .collect();
    // Across halfedge h: the arm of face(h) at angle a, carried over the shared edge (its angle
    // to the edge kept) into the frame of the face beyond.
    let carry = |h: u32, a: f64| -> f64 {
        let (f, g) = (mesh.face(h) as usize, mesh.face(h ^ 1) as usize);
        let e = sub(mesh.position(mesh.to_vertex(h)), mesh.position(mesh.from_vertex(h)));
        match (&frames[f], &frames[g]) {
            (Some(ff), Some(fg)) => fg.angle(e) + (a - ff.angle(e)),
            _ => a,
        }
    };
    let mut arm = vec![f64::NAN; nf];
    let mut tree = vec![false; mesh.n_edges()];
    let mut stack = Vec::new();
    for root in 0..nf {
        if !arm[root].is_nan() {
            continue;
        }
        arm[root] = mean[root];
        stack.push(root as u32);
        while let Some(f) = stack.pop() {
            for k in 0..3 {
                let h = mesh.face_halfedge(f, k);
                let g = mesh.face(h ^ 1);
                if g == NONE || !arm[g as usize].is_nan() {
                    continue;
                }
                let quarters = (wrap(carry(h, arm[f as usize]) - mean[g as usize]) / FRAC_PI_2).round();
                arm[g as usize] = mean[g as usize] + quarters * FRAC_PI_2;
                tree[mesh.edge(h) as usize] = true;
                stack.push(g);
            }
        }
    }
    let matching = (0..mesh.n_edges() as u32)
        .map(|e| {
            if mesh.is_boundary_edge(e) || tree[e as usize] {
                return 0;
            }
            let (f, g) = (mesh.face(2 * e) as usize, mesh.face(2 * e + 1) as usize);
            (wrap(arm[g] - carry(2 * e, arm[f])) / FRAC_PI_2).round() as i32
        })
        .collect();
    Matched { arm, tree, matching }
}

/// The cut (per edge) and the cones (per vertex): the edges off the tree, pruned of branches
/// that end at a vertex round which the matchings add up to whole turns.
fn cut_graph(mesh: &Mesh, m: &Matched) -> (Vec<bool>, Vec<bool>) {
    let nv = mesh.n_vertices();
    // Round a vertex, every crossing from the face left of an outgoing halfedge to the face
    // right of it: the same way round for all.
    let crossing = |h: u32| if h.is_multiple_of(2) { m.matching[mesh.edge(h) as usize] } else { -m.matching[mesh.edge(h) as usize] };
    let cone: Vec<bool> = (0..nv as u32)
        .map(|v| !mesh.is_isolated(v) && !mesh.is_boundary_vertex(v) && mesh.outgoing(v).map(crossing).sum::<i32>().rem_euclid(4) != 0)
        .collect();
    let mut cut: Vec<bool> = (0..mesh.n_edges() as u32).map(|e| !mesh.is_boundary_edge(e) && !m.tree[e as usize]).collect();
    // The boundary counts towards a vertex's degree: cuts between boundary loops stay.
    let mut degree = vec![0u32; nv];
    for e in 0..mesh.n_edges() as u32 {
        if cut[e as usize] || mesh.is_boundary_edge(e) {
            degree[mesh.from_vertex(2 * e) as usize] += 1;
            degree[mesh.to_vertex(2 * e) as usize] += 1;
        }
    }
    let mut leaves: Vec<u32> = (0..nv as u32).filter(|&v| degree[v as usize] == 1 && !cone[v as usize]).collect();
    while let Some(v) = leaves.pop() {
        let Some(h) = mesh.outgoing(v).find(|&h| cut[mesh.edge(h) as usize]) else { continue };
        cut[mesh.edge(h) as usize] = false;
        degree[v as usize] -= 1;
        let w = mesh.to_vertex(h);
        degree[w as usize] -= 1;
        if degree[w as usize] == 1 && !cone[w as usize] {
            leaves.push(w);
        }
    }
    (cut, cone)
}

/// The corner `3f + k` of vertex `v` in triangle `f`.
fn corner(mesh: &Mesh, f: u32, v: u32) -> usize {
    3 * f as usize + mesh.triangles()[f as usize].iter().position(|&x| x == v).unwrap_or(0)
}

/// Per corner its wedge (the corners of one vertex joined across edges not cut), and how many
/// wedges there are.
fn wedges(mesh: &Mesh, cut: &[bool]) -> (Vec<u32>, usize) {
    let nc = 3 * mesh.n_faces();
    let mut parent: Vec<usize> = (0..nc).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for e in 0..mesh.n_edges() as u32 {
        if cut[e as usize] || mesh.is_boundary_edge(e) {
            continue;
        }
        let (f, g) = (mesh.face(2 * e), mesh.face(2 * e + 1));
        for v in [mesh.from_vertex(2 * e), mesh.to_vertex(2 * e)] {
            let (a, b) = (root(&mut parent, corner(mesh, f, v)), root(&mut parent, corner(mesh, g, v)));
            parent[a] = b;
        }
    }
    let mut number = vec![NONE; nc];
    let mut wedge = vec![0u32; nc];
    let mut count = 0;
    for c in 0..nc {
        let r = root(&mut parent, c);
        if number[r] == NONE {
            number[r] = count as u32;
            count += 1;
        }
        wedge[c] = number[r];
    }
    (wedge, count)
}

/// `(u, v)` of every wedge (unknowns `2w`, `2w + 1`): the least-squares fit of the gradients to
/// the arms, with the seams as heavy penalties; after one solve, and after [`SCALE_ROUNDS`].
fn solve(
    mesh: &Mesh,
    frames: &[Option<FaceFrame>],
    hats: &[Option<Hats>],
    m: &Matched,
    cut: &[bool],
    wedge: &[u32],
    wedges: usize,
) -> Result<[Vec<f64>; 2], SolveError> {
    let n = 2 * wedges;
    let mut entries: Vec<(u32, u32)> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut add = |i: usize, j: usize, value: f64| {
        entries.push((i.max(j) as u32, i.min(j) as u32));
        values.push(value);
    };
    for (f, h) in hats.iter().enumerate() {
        let Some(Hats { area, g }) = h else { continue };
        for i in 0..3 {
            let wi = wedge[3 * f + i] as usize;
            for j in 0..=i {
                let wj = wedge[3 * f + j] as usize;
                // Two corners in one wedge (a degenerate fan): their product counts twice.
                let value = if i != j && wi == wj { 2.0 } else { 1.0 } * area * dot(g[i], g[j]);
                add(2 * wi, 2 * wj, value);
                add(2 * wi + 1, 2 * wj + 1, value);
            }
        }
    }
    // Seams: (X_g(b) − X_g(a)) − R(−k·90°) (X_f(b) − X_f(a)) = 0 along every cut edge a → b,
    // f = face(2e), g = face(2e + 1), X = (u, v).
    for e in (0..mesh.n_edges() as u32).filter(|&e| cut[e as usize]) {
        let (f, g) = (mesh.face(2 * e), mesh.face(2 * e + 1));
        let (a, b) = (mesh.from_vertex(2 * e), mesh.to_vertex(2 * e));
        let w = |face: u32, v: u32| wedge[corner(mesh, face, v)] as usize;
        let rot: [[f64; 2]; 2] = match m.matching[e as usize].rem_euclid(4) {
            0 => [[1.0, 0.0], [0.0, 1.0]],
            1 => [[0.0, 1.0], [-1.0, 0.0]],
            2 => [[-1.0, 0.0], [0.0, -1.0]],
            _ => [[0.0, -1.0], [1.0, 0.0]],
        };
        for c in 0..2 {
            let mut terms: Vec<(usize, f64)> = vec![(2 * w(g, b) + c, 1.0), (2 * w(g, a) + c, -1.0)];
            for d in 0..2 {
                if rot[c][d] != 0.0 {
                    terms.push((2 * w(f, b) + d, -rot[c][d]));
                    terms.push((2 * w(f, a) + d, rot[c][d]));
                }
            }
            // One coefficient per unknown (at a cut's end both sides are one wedge).
            sum_duplicates(&mut terms);
            for (k, &(i, ci)) in terms.iter().enumerate() {
                for &(j, cj) in &terms[..=k] {
                    add(i, j, SEAM_WEIGHT * ci * cj);
                }
            }
        }
    }
    // A ridge pins each component's free translation.
    let (sum, count) = entries.iter().zip(&values).filter(|(e, _)| e.0 == e.1).fold((0.0, 0), |(s, c), (_, &v)| (s + v, c + 1));
    let ridge = RIDGE * if count > 0 { sum / count as f64 } else { 1.0 };
    for i in 0..n {
        entries.push((i as u32, i as u32));
        values.push(ridge);
    }
    let mut solver = SpdSolver::new(n, &entries)?;
    solver.factor(&values)?;
    // Per triangle, the scale asked for: 1 at first, then the scale the solve before took.
    let mut scales = vec![1.0; hats.len()];
    let mut first = Vec::new();
    let mut x = vec![0.0; n];
    for round in 0..SCALE_ROUNDS {
        x.iter_mut().for_each(|v| *v = 0.0);
        for (f, (fr, h)) in frames.iter().zip(hats).enumerate() {
            let (Some(fr), Some(Hats { area, g })) = (fr, h) else { continue };
            let weight = area * scales[f];
            let a = fr.direction(m.arm[f]);
            let b = cross(fr.n, a);
            for i in 0..3 {
                let wi = wedge[3 * f + i] as usize;
                x[2 * wi] += weight * dot(g[i], a);
                x[2 * wi + 1] += weight * dot(g[i], b);
            }
        }
        solver.solve_in_place(&mut x)?;
        if round == 0 {
            first = x.clone();
        }
        if round + 1 == SCALE_ROUNDS {
            break;
        }
        for (f, h) in hats.iter().enumerate() {
            let Some(h) = h else { continue };
            let (gu, gv) = gradient_of(&x, wedge, f, &h.g);
            let scale = (norm(gu) * norm(gv)).sqrt();
            if scale.is_finite() && scale > 0.0 {
                scales[f] = scale;
            }
        }
    }
    Ok([first, x])
}

/// The gradients of `u` and `v` in triangle `f`, `g` its hat functions' gradients.
fn gradient_of(x: &[f64], wedge: &[u32], f: usize, g: &[Vec3; 3]) -> (Vec3, Vec3) {
    let (mut gu, mut gv) = ([0.0; 3], [0.0; 3]);
    for i in 0..3 {
        let w = wedge[3 * f + i] as usize;
        gu = add(gu, scale(x[2 * w], g[i]));
        gv = add(gv, scale(x[2 * w + 1], g[i]));
    }
    (gu, gv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::compute_field;
    use crate::field::tests::{sphere, torus};
    use crate::mesh::primitives::quad_grid;

    /// The largest deviation from a right angle between a triangle's two iso-line directions,
    /// in degrees, and how many triangles have none.
    fn worst_shear(iso: &IsoLines) -> (f64, usize) {
        let worst = iso.arms.iter().flatten().map(|[u, v]| (crate::geom::angle(*u, *v).to_degrees() - 90.0).abs()).fold(0.0, f64::max);
        (worst, iso.arms.iter().filter(|a| a.is_none()).count())
    }


    /// On a plane the field is constant (aligned to the boundary), and so is the gradient that
    /// fits it: the iso-lines are the field's own lines, at right angles, with no cone.
    #[test]
    fn a_flat_grid_has_straight_iso_lines_along_its_boundary() {
        let mesh = quad_grid([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]], 12);
        let field = compute_field(&mesh, 35.0).unwrap();
        let [iso, _] = &iso_lines(&mesh, &field).unwrap();
        assert!(iso.cone.iter().all(|&c| !c));
        let (shear, folded) = worst_shear(iso);
        assert_eq!(folded, 0);
        assert!(shear < 1e-6, "{shear}");
        for [u, v] in iso.arms.iter().flatten() {
            // Each direction along x or y.
            for d in [u, v] {
                assert!(d[0].abs().max(d[1].abs()) > 1.0 - 1e-9 && d[2].abs() < 1e-12, "{d:?}");
            }
        }
    }

    /// A sphere's parameterization has the field's eight valence-3 singularities as cones
    /// (quarter turns that add up to χ = 2), and folds nowhere.
    #[test]
    fn a_sphere_has_eight_cones() {
        let mesh = sphere(10);
        let field = compute_field(&mesh, 35.0).unwrap();
        let [iso, _] = &iso_lines(&mesh, &field).unwrap();
        assert_eq!(iso.cone.iter().filter(|&&c| c).count(), 8);
        assert_eq!(worst_shear(iso).1, 0);
    }

    /// A torus of revolution needs no cone. Its field follows the parallels and meridians, but
    /// at unit length it is not a gradient (a parallel's length changes round the tube), so
    /// the fit shears a little, with or without the scale of the solve before.
    #[test]
    fn a_torus_has_no_cone_and_nearly_right_angles() {
        let mesh = torus(48, 16, 1.0, 0.35);
        let field = compute_field(&mesh, 35.0).unwrap();
        for iso in iso_lines(&mesh, &field).unwrap() {
            assert!(iso.cone.iter().all(|&c| !c));
            let (shear, folded) = worst_shear(&iso);
            assert_eq!(folded, 0);
            assert!(shear < 5.0, "{shear}");
        }
    }
}
