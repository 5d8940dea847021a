//! Relaxation of an extracted quad mesh on the surface. First a few global steps move all
//! free vertices at once toward where every quad is a rectangle ([`super::rectify`]), which
//! undoes a shear as wide as a chart; then, a few rounds, each free vertex moves toward the
//! mean of its edge neighbours, toward where its quads would be parallelograms, or down the
//! slope of its quads' skew ([`steepest_descent`]), within the surface's tangent plane, and is
//! put back on the surface at the nearest point, a few rounds. Of the moves tried, the one
//! that leaves the fewest quads folded and then the least skew is kept; next to a folded quad,
//! whole steps are tried as well as half ones, and a move that unfolds quads may leave a
//! neighbour not convex (never folded) when the quads around come out sounder on the whole
//! ([`badness`]).
//!
//! The steps down the skew are what squares the corners: the mean and the parallelograms even
//! out grid lines, and most of their moves (on bunny_1k8, 4 in 5) raised the skew and were
//! refused. At --quads 4000 on the seven shared meshes' automatic layouts the mean angle
//! deviation falls from 3.5–31.9° unrelaxed to 2.7–16.6° (bunny_28k 13.7 → 7.4°, bunny_1k8
//! 17.1 → 9.6°), where ten rounds of the mean and the parallelograms alone reached 3.1–28.0°
//! (11.0°, 14.4°).
//!
//! Why: the grid of Section 4 is straight in each chart, but the charts meet with kinks
//! where a layout edge is not tagged (its pieces are straight in both charts, not across
//! them), at T-vertices, and where the harmonic map shears a chart. Those kinks are the skew
//! corners a user sees; the surface does not need them. Vertices on tagged curves (the edge
//! loops the user asked for, the boundary, sharp features) stay on them, sliding along them
//! only ([`super::rails`]), and the layout's nodes stay where they are, so every promise of
//! the layout is kept. Vertices on creases of the quads stay too. A move that
//! would fold a quad is taken back, and so is one that turns a corner inside out unless it
//! unfolds quads.

use super::closest::TriangleTree;
use super::cover::nearest_quad;
use super::rails::{Rails, Slides};
use super::rectify::Rectify;
use super::quality::{corner_angle_deviations, pseudo_normal, quad_centre, quad_normal, scaled_jacobian};
use super::QuadMesh;
use crate::geom::{add, cross, dot, norm, scale, sub, tangent_basis, unit, Vec3};
use crate::mesh::build::corners_by_vertex;

/// Rounds of relaxation: enough to straighten grid lines across a kink a few quads wide,
/// few enough not to drift over the surface. The steps down the skew keep finding a little
/// long after ten rounds: at --quads 4000 on the automatic layouts, bunny_28k's mean angle
/// deviation is 5.58° after 15 rounds, 5.25° after 25, 5.19° after 30 and 5.08° after 40
/// (nefertiti 6.87, 6.23, 6.05, 5.81°; fandisk 6.49, 6.14, 6.05, 5.94°), with the Hausdorff
/// distance within 0.02 % of the diagonal. Each round costs about as much as the first
/// fifteen did on average: bunny_28k's meshing stage 0.9 s with 15, 1.7 s with 30.
pub const ROUNDS: usize = 30;
/// Global steps toward rectangles before the rounds ([`Rectify`]): at --quads 4000 on the
/// seven shared meshes' automatic layouts, 30 lower the mean angle deviation by 0.1–1.8°
/// (nefertiti 6.05 → 4.25°, bunny_28k 5.19 → 4.70°); 60 and 100 gain at most 0.3° more
/// (nefertiti), each step costing about as much as a twentieth of a round.
pub const STEPS: usize = 30;
/// Quads meeting at a vertex at more than this angle (degrees) make it a crease vertex, which
/// stays: the default sharp-feature angle of the automatic layout.
const CREASE: f64 = crate::field::DEFAULT_FEATURE_ANGLE;
/// The share of the way to its target (its neighbours' mean, or where its quads would be
/// parallelograms) a vertex moves in one round.
const DAMPING: f64 = 0.5;

/// Shares of a vertex's mean edge length it is moved along the steepest descent of its quads'
/// skew, each tried: long enough to square a corner a neighbour's move left skewed, and
/// shorter where the skew turns up again within the longer step.
const DESCENT_STEPS: [f64; 3] = [0.2, 0.07, 0.02];
/// Half the span of the central differences of the skew's slope, as a share of the mean edge
/// length: far below the steps.
const SLOPE_SPAN: f64 = 1e-3;

/// The unit direction in the tangent plane at `p` (normal `n`) in which `energy` falls
/// fastest, from central differences `span` either side; `None` where it is flat.
fn steepest_descent(p: Vec3, n: Vec3, span: f64, mut energy: impl FnMut(Vec3) -> f64) -> Option<Vec3> {
    let [t1, t2] = tangent_basis(n);
    let mut slope = |t: Vec3| (energy(add(p, scale(span, t))) - energy(sub(p, scale(span, t)))) / (2.0 * span);
    let (g1, g2) = (slope(t1), slope(t2));
    let g = g1.hypot(g2);
    (g > 0.0 && g.is_finite()).then(|| add(scale(-g1 / g, t1), scale(-g2 / g, t2)))
}

/// The surface the quads are relaxed on: its triangles, a tree over them, and the triangles
/// round each vertex.
pub struct Surface {
    triangles: Vec<[Vec3; 3]>,
    indices: Vec<[u32; 3]>,
    /// The corners of triangles at vertex `v` are `round[start[v]..start[v + 1]]`
    /// ([`corners_by_vertex`]).
    start: Vec<u32>,
    round: Vec<u32>,
    tree: TriangleTree,
}

impl Surface {
    /// The triangles `indices` over `positions`.
    pub fn new(positions: &[Vec3], indices: Vec<[u32; 3]>) -> Surface {
        let triangles: Vec<[Vec3; 3]> = indices.iter().map(|t| t.map(|v| positions[v as usize])).collect();
        let tree = TriangleTree::new(triangles.iter().copied());
        let (start, round) = corners_by_vertex(positions.len(), &indices);
        Surface { triangles, indices, start, round, tree }
    }

    /// The surface's pseudo-normal at the point nearest to `p` (as [`super::quality`] counts
    /// folded quads); `leaf` as [`TriangleTree::closest_from`] takes it.
    pub(super) fn facing(&self, p: Vec3, leaf: &mut u32) -> Option<Vec3> {
        let hit = self.tree.closest_from(p, leaf)?;
        let round = |v: u32| &self.round[self.start[v as usize] as usize..self.start[v as usize + 1] as usize];
        let around = || self.indices[hit.triangle as usize].iter().flat_map(|&v| round(v).iter().map(|&c| c / 3)).collect();
        Some(pseudo_normal(|t| self.triangles[t as usize], around, p, &hit))
    }

    /// Whether the surface is sharp near `p`: the triangle nearest it and one sharing a
    /// corner with it meet at more than [`CREASE`] (their normals do); `leaf` as
    /// [`TriangleTree::closest_from`] takes it.
    fn sharp_near(&self, p: Vec3, leaf: &mut u32) -> bool {
        let Some(hit) = self.tree.closest_from(p, leaf) else { return false };
        let normal = |t: usize| {
            let [a, b, c] = self.triangles[t];
            unit(cross(sub(b, a), sub(c, a)))
        };
        let here = normal(hit.triangle as usize);
        let cos = CREASE.to_radians().cos();
        self.indices[hit.triangle as usize].iter().any(|&v| {
            self.round[self.start[v as usize] as usize..self.start[v as usize + 1] as usize].iter().any(|&c| dot(normal(c as usize / 3), here) < cos)
        })
    }

    /// Points of the surface as the quality measures its distance from the quads: its
    /// vertices and its triangles' centroids.
    pub(super) fn samples(&self) -> Vec<Vec3> {
        let n = self.start.len() - 1;
        let mut vertex = vec![None; n];
        for (t, c) in self.indices.iter().zip(&self.triangles) {
            t.iter().zip(c).for_each(|(&v, &p)| vertex[v as usize] = Some(p));
        }
        let centroids = self.triangles.iter().map(|[a, b, c]| std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0));
        vertex.into_iter().flatten().chain(centroids).collect()
    }

    /// The nearest surface point to `p` and the unit normal of its triangle; `leaf` as
    /// [`TriangleTree::closest_from`] takes it.
    pub(super) fn project(&self, p: Vec3, leaf: &mut u32) -> Option<(Vec3, Vec3)> {
        let hit = self.tree.closest_from(p, leaf)?;
        let [a, b, c] = self.triangles[hit.triangle as usize];
        let n = cross(sub(b, a), sub(c, a));
        let l = norm(n);
        (l > 0.0).then(|| (hit.point, n.map(|x| x / l)))
    }
}

/// What the relaxation must not make worse in a quad.
#[derive(Debug, Clone, Copy)]
pub(super) struct QuadState {
    /// Every corner turns the same way as the surface (convex seen from outside).
    convex: bool,
    /// The quad's normal (the cross product of its diagonals) points against the surface's
    /// nearest to its centre (as [`super::quality`] counts folded quads).
    flipped: bool,
}

/// The shape of quad `q` at positions `p`: `normals` are the surface normals at its corners,
/// `surface` finds the one nearest its centre (starting in `leaf`).
pub(super) fn shape(p: &[Vec3], q: [u32; 4], normals: &[Vec3], surface: &Surface, leaf: &mut u32) -> QuadState {
    let c = q.map(|v| p[v as usize]);
    let convex = (0..4).all(|k| {
        let (a, b, d) = (c[(k + 3) % 4], c[k], c[(k + 1) % 4]);
        dot(cross(sub(d, b), sub(a, b)), normals[q[k] as usize]) > 0.0
    });
    let centre = quad_centre(&c);
    let normal = surface.facing(centre, leaf).unwrap_or([0.0; 3]);
    let flipped = dot(quad_normal(&c), normal) <= 0.0;
    QuadState { convex, flipped }
}

/// The points of a quad whose distance from the surface stands for the quad's: its centre and
/// its edge midpoints.
pub(super) fn probes(p: &[Vec3], q: [u32; 4]) -> [Vec3; 5] {
    let c = q.map(|v| p[v as usize]);
    let mid = |a: Vec3, b: Vec3| scale(0.5, add(a, b));
    [mid(mid(c[0], c[2]), mid(c[1], c[3])), mid(c[0], c[1]), mid(c[1], c[2]), mid(c[2], c[3]), mid(c[3], c[0])]
}

/// The sum over the corners of quad `q` of |corner angle − 90°| to the power `power`, in
/// degrees.
pub(super) fn skew(p: &[Vec3], q: [u32; 4], power: f64) -> f64 {
    corner_angle_deviations(&q.map(|v| p[v as usize])).iter().map(|&d| to_power(d, power)).sum()
}

/// `d` (not negative) to the power `power`: the squares and the 1.5th powers that [`skew`]
/// takes by a product and a square root, which `powf` took a sixteenth of a remesh's time for.
fn to_power(d: f64, power: f64) -> f64 {
    if power == 2.0 {
        d * d
    } else if power == 1.5 {
        d * d.sqrt()
    } else {
        d.powf(power)
    }
}

/// The powers of the corners' deviations that [`skew`] sums: squares in the first
/// [`SQUARED_SHARE`] of the rounds, then [`SKEW_POWER`].
///
/// Above 1: the sum of absolute deviations (what the quality reports) has a kink wherever a
/// corner is right, and a vertex whose one quad is a rectangle stays there however skewed the
/// others are; a power above 1 spreads the skew over the corners, and its slope leads
/// somewhere (squares gave a mean deviation 0.1–1.7° lower than absolute deviations on the
/// shared meshes). Squares all along let the few corners far off drive the moves, and skew
/// many corners a little to mend one; but a power of 1.5 from the start is nearly as sticky
/// as the absolute deviations where a quad is square (in the 2 × 2 grid of the test
/// `a_vertex_goes_where_its_corners_are_squarest_not_to_its_neighbours_mean` the vertex did
/// not move). At --quads 4000 on the
/// automatic layouts of the seven shared meshes and CGAL's homer and lion-head: squares all
/// along 9.85° on the mean, 1.5 all along 9.67°, squares for 40 % of the rounds 9.56° (for
/// 67 %, 9.58°); nefertiti 7.38 → 6.87°, fandisk 6.87 → 6.49°, lion-head 12.03 → 11.82°.
const SKEW_POWER: f64 = 1.5;
const SQUARED_SHARE: f64 = 0.4;

/// The mean length of a quad's edges.
pub(super) fn size(p: &[Vec3], q: [u32; 4]) -> f64 {
    (0..4).map(|k| norm(sub(p[q[(k + 1) % 4] as usize], p[q[k] as usize]))).sum::<f64>() / 4.0
}

/// How far a relaxed quad may stray from the surface beyond where extraction put it, as a
/// fraction of its edge length: far below the chord error of a quad mesh a user would keep.
const STRAY: f64 = 0.1;

/// Whether a quad keeps the shape it had `before`.
pub(super) fn keeps(before: &QuadState, now: &QuadState) -> bool {
    (now.convex || !before.convex) && (!now.flipped || before.flipped)
}

/// A vertex's move that was judged sound: its (folded quads, skew) around, where it ends on
/// the surface and the normal there, and the shapes of its quads after it.
struct Move {
    score: (usize, f64),
    at: Vec3,
    normal: Vec3,
    /// Its arc length along its curve, for a vertex that slides on one.
    arc: f64,
    shapes: Vec<QuadState>,
}

/// How far quads are from sound: a folded quad counts twice, one that is not convex once.
fn badness(shapes: &[QuadState]) -> usize {
    shapes.iter().map(|s| 2 * usize::from(s.flipped) + usize::from(!s.convex)).sum()
}

/// Whether quad `q` at `positions` is farther from the surface than `reach` at one of its
/// [`probes`] (`leaves`: where each was last found in the surface's tree).
fn strays(surface: &Surface, positions: &[Vec3], q: [u32; 4], reach: f64, leaves: &mut [u32; 5]) -> bool {
    probes(positions, q).iter().zip(leaves.iter_mut()).any(|(&x, leaf)| surface.tree.distance_squared_beyond(x, reach * reach, leaf).is_some())
}

/// How much farther from where a vertex moving round a bend was its quads may pass than the
/// quads as they were pass from where it is, as a share of their edge length ([`covers`]):
/// far below what a user sees. Fandisk's gallery layout at --quads 4400 misses the surface by
/// 0.83 % of the diagonal (0.81 % with those vertices held); with 0.1, by 0.94 %.
const COVER: f64 = 0.02;

/// The distance from `x` to the nearest of the quads `around` at `positions`, and their mean
/// edge length.
fn miss(positions: &[Vec3], quads: &[[u32; 4]], around: &[u32], x: Vec3) -> (f64, f64) {
    let mean = around.iter().fold(0.0, |m, &i| m + size(positions, quads[i as usize]) / around.len() as f64);
    (nearest_quad(positions, quads, around.iter().copied(), x).0, mean)
}

/// Whether vertex `v`'s quads `around` at `positions` still cover where it was (`anchor`):
/// they pass no farther from there than the quads as they were from where it is now, and
/// [`COVER`] of an edge length. Round a limb that holds for a move either way; off a fillet
/// or a rim onto a flat side it does not (the quads as they were cover the flat side, and
/// the quads now cut the fillet).
fn covers(positions: &[Vec3], anchor: &[Vec3], quads: &[[u32; 4]], around: &[u32], v: usize) -> bool {
    let (now, size) = miss(positions, quads, around, anchor[v]);
    let (was, _) = miss(anchor, quads, around, positions[v]);
    now <= was + COVER * size
}

/// A global step may not leave a quad's corner flatter than this (the sine of its angle,
/// Verdict's scaled Jacobian), or flatter than it was: the rectangles are fitted in the
/// least-squares sense, and a corner may give way to its neighbours' until it is nearly
/// straight (on nefertiti, a corner of 179.8°).
const FLAT: f64 = 0.1;

/// Queues the quads `around` a vertex that moved to be checked, each once.
fn recheck(around: &[u32], queued: &mut [bool], pending: &mut Vec<u32>) {
    for &i in around {
        if !std::mem::replace(&mut queued[i as usize], true) {
            pending.push(i);
        }
    }
}

/// `steps` global steps of the free vertices toward rectangles ([`Rectify`]), each vertex put
/// back on the surface; a quad that would fold, turn a corner inside out or stray from the
/// surface beyond its `reach` takes back the moves of its corners, until none does.
#[allow(clippy::too_many_arguments)]
fn rectify_steps(
    quads: &mut QuadMesh,
    surface: &Surface,
    pinned: &[bool],
    squared: &[bool],
    bent: &[bool],
    anchor: &[Vec3],
    neighbours: &[Vec<u32>],
    incident: &[Vec<u32>],
    before: &[QuadState],
    now: &mut [QuadState],
    normals: &mut [Vec3],
    reach: &[f64],
    vertex_leaf: &mut [u32],
    quad_leaf: &mut [[u32; 5]],
    steps: usize,
) {
    let n = quads.positions.len();
    // The corners of quads folded or not convex stay for the rounds, which judge each move
    // by the folds it leaves: the rectangles' pull knows nothing of folds, and moved them
    // where fewer came undone (over 26 meshes' automatic layouts at --quads 4000 the folded
    // quads went from 81 to 88 with those corners in the steps, 83 without).
    let unsound = |v: usize| incident[v].iter().any(|&q| before[q as usize].flipped || !before[q as usize].convex);
    let free: Vec<bool> = (0..n).map(|v| !pinned[v] && squared[v] && !neighbours[v].is_empty() && !unsound(v)).collect();
    let Ok(mut rectify) = Rectify::new(&quads.quads, &free, normals) else { return };
    let mut centre_leaf = 0;
    for _ in 0..steps {
        let Ok(goal) = rectify.step(&quads.positions, normals) else { return };
        let (old, old_normals) = (quads.positions.clone(), normals.to_vec());
        let mut pending: Vec<u32> = Vec::new();
        let mut queued = vec![false; quads.quads.len()];
        for v in (0..n).filter(|&v| free[v]) {
            let step = norm(sub(goal[v], old[v]));
            if let Some((q, nq)) = surface.project(goal[v], &mut vertex_leaf[v]).filter(|(q, _)| norm(sub(*q, goal[v])) <= step) {
                quads.positions[v] = q;
                normals[v] = nq;
                recheck(&incident[v], &mut queued, &mut pending);
            }
        }
        for v in 0..n {
            if bent[v] && quads.positions[v] != old[v] && !covers(&quads.positions, anchor, &quads.quads, &incident[v], v) {
                quads.positions[v] = old[v];
                normals[v] = old_normals[v];
            }
        }
        while let Some(i) = pending.pop() {
            queued[i as usize] = false;
            let q = quads.quads[i as usize];
            let state = shape(&quads.positions, q, normals, surface, &mut centre_leaf);
            let corners = q.map(|v| quads.positions[v as usize]);
            let was = scaled_jacobian(&q.map(|v| old[v as usize]));
            if keeps(&before[i as usize], &state) && scaled_jacobian(&corners) >= was.min(FLAT) && !strays(surface, &quads.positions, q, reach[i as usize], &mut quad_leaf[i as usize]) {
                now[i as usize] = state;
                continue;
            }
            for &v in &q {
                let v = v as usize;
                if quads.positions[v] != old[v] {
                    quads.positions[v] = old[v];
                    normals[v] = old_normals[v];
                    recheck(&incident[v], &mut queued, &mut pending);
                }
            }
        }
    }
}

/// Relaxes the vertices of `quads` not `pinned` on `surface`: `steps` global steps toward
/// rectangles ([`STEPS`] in a remesh), then `rounds` rounds one vertex at a time ([`ROUNDS`]),
/// in which the pinned vertices on `rails` slide along them;
/// only those that may be `squared` move in the steps and take steps down the skew in the
/// rounds (the others' quads keep the angles of their chart). Returns the number of vertices
/// that moved.
pub fn relax(quads: &mut QuadMesh, surface: &Surface, pinned: &[bool], rails: &Rails, squared: &[bool], steps: usize, rounds: usize) -> usize {
    let n = quads.positions.len();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut incident: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, q) in quads.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            if !neighbours[a as usize].contains(&b) {
                neighbours[a as usize].push(b);
                neighbours[b as usize].push(a);
            }
            incident[a as usize].push(i as u32);
        }
    }
    // The tree's leaf each vertex and each quad was last found in.
    let mut vertex_leaf = vec![0u32; n];
    let mut quad_leaf = vec![[0u32; 5]; quads.quads.len()];
    let mut normals: Vec<Vec3> =
        (0..n).map(|v| surface.project(quads.positions[v], &mut vertex_leaf[v]).map_or([0.0; 3], |(_, n)| n)).collect();
    let before: Vec<QuadState> =
        (0..quads.quads.len()).map(|i| shape(&quads.positions, quads.quads[i], &normals, surface, &mut quad_leaf[i][0])).collect();
    // Vertices on a crease of the quads where the surface is sharp too (a sharp edge no tag
    // holds) stay: a move to the neighbours' mean would round it off. (Quads folded against
    // the surface make no crease: they are what the relaxation may mend.) Where only the
    // quads bend, round a limb a few quads across or a fillet, the moves stay on the surface,
    // which has no edge to round: holding those vertices left the limbs' quads as skewed as
    // extraction made them (elephant's legs, trunk and tusks: 64 % of its summed corner
    // deviation at --quads 4000 was in the quads round such vertices). They move, but only
    // while their quads still cover where they were ([`covers`]): along a fillet or a rim,
    // not off it, which the quads would cut (fandisk's Hausdorff distance with its gallery
    // layout rose from 0.81 to 1.02 % without that). Over 26 meshes' automatic layouts at
    // --quads 4000, the mean deviation fell from 10.82 to 10.03° and the Hausdorff distance
    // from 1.80 to 1.75 % (geometric mean); elephant's angle from 9.98 to 7.40°.
    let unit: Vec<Vec3> = quads.quads.iter().map(|q| unit(quad_normal(&q.map(|v| quads.positions[v as usize])))).collect();
    let crease = CREASE.to_radians().cos();
    let on_crease = |v: usize| {
        let around = &incident[v];
        let fair = |q: &&u32| !before[**q as usize].flipped;
        around.iter().filter(fair).any(|&a| around.iter().filter(fair).any(|&b| dot(unit[a as usize], unit[b as usize]) < crease))
    };
    // But a corner of a folded quad may move whatever crease its quads make: the fold is the
    // defect, and the quads round it are bent by it (on elephant's automatic layout at --quads
    // 4000, every corner of each of its three folded quads was held so, and none unfolded).
    let folded_corner = |v: usize| incident[v].iter().any(|&q| before[q as usize].flipped);
    let bent: Vec<bool> = (0..n).map(|v| !pinned[v] && on_crease(v) && !folded_corner(v)).collect();
    let pinned: Vec<bool> = (0..n).map(|v| pinned[v] || (bent[v] && surface.sharp_near(quads.positions[v], &mut vertex_leaf[v]))).collect();
    let bent: Vec<bool> = (0..n).map(|v| bent[v] && !pinned[v]).collect();
    // Where the vertices free to move round a bend were: their quads must still pass near it.
    let anchor = quads.positions.clone();
    // How far from the surface each quad may be: as far as extraction put it, and a little.
    let reach: Vec<f64> = (0..quads.quads.len())
        .map(|i| {
            let q = quads.quads[i];
            let far = probes(&quads.positions, q)
                .iter()
                .zip(&mut quad_leaf[i])
                .filter_map(|(&x, leaf)| surface.tree.closest_from(x, leaf))
                .map(|hit| hit.distance_squared.sqrt())
                .fold(0.0, f64::max);
            far + STRAY * size(&quads.positions, q)
        })
        .collect();
    // The quads' shapes as they are: a quad's changes only when one of its corners moves.
    let mut now = before.clone();
    // The global steps first; then one vertex at a time mends what they left: folds, and the
    // corners that the rectangles' least squares traded off. (With a global step at the start
    // of each round instead, each undid the rounds' squaring: bunny_28k's mean deviation came
    // out 5.9° rather than 4.7°.)
    rectify_steps(quads, surface, &pinned, squared, &bent, &anchor, &neighbours, &incident, &before, &mut now, &mut normals, &reach, &mut vertex_leaf, &mut quad_leaf, steps);
    // One vertex at a time (Gauss–Seidel), each move kept only if fewer of its quads are
    // folded, or as many and their corners come nearer right angles, and none of them folds
    // or strays from the surface beyond what extraction left; a corner may turn inside out
    // only in a move that unfolds quads and leaves them sounder on the whole.
    let mut centre_leaf = 0;
    // Moves so far; the count after each vertex's latest move (0: it never moved), and when a
    // vertex's latest look found no move. A vertex none of whose quads changed since then would be refused
    // again (its moves and their judgement are the same): it is not looked at.
    let mut moves = 0u64;
    let mut moved_at = vec![0u64; n];
    let mut refused_at: Vec<Option<u64>> = vec![None; n];
    // The pinned samples of tagged curves that slide along them.
    let mut slides = Slides::new(rails, n);
    for round in 0..rounds {
        let power = if (round as f64) < SQUARED_SHARE * rounds as f64 { 2.0 } else { SKEW_POWER };
        for v in 0..n {
            let rail = slides.slides(v);
            if (pinned[v] && !rail) || neighbours[v].is_empty() {
                continue;
            }
            let around = &incident[v];
            if let Some(t) = refused_at[v] {
                if around.iter().flat_map(|&i| quads.quads[i as usize]).all(|w| moved_at[w as usize] <= t) {
                    continue;
                }
            }
            let p = quads.positions[v];
            let k = neighbours[v].len() as f64;
            let mean = scale(1.0 / k, neighbours[v].iter().fold([0.0; 3], |s, &w| add(s, quads.positions[w as usize])));
            let nv = normals[v];
            // Where the move goes, within the tangent plane.
            let toward = |goal: Vec3, share: f64| -> Vec3 {
                let d = sub(goal, p);
                add(p, scale(share, sub(d, scale(dot(d, nv), nv))))
            };
            let skew_around = |p: &[Vec3]| around.iter().map(|&i| skew(p, quads.quads[i as usize], power)).sum::<f64>();
            let mut shapes_around =
                |p: &[Vec3], normals: &[Vec3]| -> Vec<QuadState> { around.iter().map(|&i| shape(p, quads.quads[i as usize], normals, surface, &mut centre_leaf)).collect() };
            let folded = |shapes: &[QuadState]| shapes.iter().filter(|s| s.flipped).count();
            let shapes_before: Vec<QuadState> = around.iter().map(|&i| now[i as usize]).collect();
            let (skew_before, folded_before) = (skew_around(&quads.positions), folded(&shapes_before));
            // Where each quad would be a parallelogram: the mean of its neighbours straightens
            // grid lines but pulls a vertex off a border of the grid (and may lie inside a fold).
            let parallelogram = scale(
                1.0 / around.len() as f64,
                around.iter().fold([0.0; 3], |s, &q| {
                    let q = quads.quads[q as usize];
                    let at = q.iter().position(|&x| x as usize == v).unwrap_or(0);
                    let x = |j: usize| quads.positions[q[(at + j) % 4] as usize];
                    add(s, sub(add(x(1), x(3)), x(2)))
                }),
            );
            let mut tried = vec![toward(mean, DAMPING), toward(parallelogram, DAMPING)];
            // Next to a fold, half a step may not get out of it: whole steps are tried too.
            if folded_before > 0 {
                tried.extend([toward(mean, 1.0), toward(parallelogram, 1.0)]);
            }
            // The mean and the parallelograms even out the grid lines, which is not the same
            // as squaring the corners: steps down the skew itself are tried as well.
            let length = neighbours[v].iter().map(|&w| norm(sub(quads.positions[w as usize], p))).sum::<f64>() / k;
            let skew_at = |x: Vec3, positions: &mut [Vec3]| {
                positions[v] = x;
                let s = skew_around(positions);
                positions[v] = p;
                s
            };
            if let (Some(t), true) = (slides.tangent(v), squared[v]) {
                // Along the curve, both ways: one direction, so no slope to find.
                tried.extend(DESCENT_STEPS.iter().flat_map(|&share| [add(p, scale(share * length, t)), sub(p, scale(share * length, t))]));
            } else if squared[v] && !rail {
                if let Some(down) = steepest_descent(p, nv, SLOPE_SPAN * length, |x| skew_at(x, &mut quads.positions)) {
                    tried.extend(DESCENT_STEPS.map(|share| add(p, scale(share * length, down))));
                }
            }
            // A vertex on a curve lands on it, keeping its normal ([`Slides::land`]); its quads'
            // edges along the curve are chords, which may cut a bend of it only as deep as they
            // did, and [`COVER`] of an edge more. Another lands on the surface at the nearest
            // point (a nearest point far from the step's end is another sheet of the surface).
            let missed = slides.arc(v).map_or(0.0, |s| slides.chord_miss(v, s));
            let cuts_no_bend = |arc: f64| !rail || slides.chord_miss(v, arc) <= missed + COVER * length;
            let mut land = |target: Vec3| -> Option<(Vec3, Vec3, f64)> {
                if rail {
                    return slides.land(v, target).map(|(q, arc)| (q, nv, arc));
                }
                let step = norm(sub(target, p));
                surface.project(target, &mut vertex_leaf[v]).filter(|(q, _)| norm(sub(*q, target)) <= step).map(|(q, n)| (q, n, 0.0))
            };
            // The sound move that leaves the fewest folded quads, then the least skew.
            let mut best: Option<Move> = None;
            // Each move's end, and its skew.
            let mut landed: Vec<(f64, Vec3, Vec3, f64)> = tried
                .into_iter()
                .filter_map(|target| {
                    let (q, nq, arc) = land(target)?;
                    Some((skew_at(q, &mut quads.positions), q, nq, arc))
                })
                .collect();
            // With none of its quads folded, the sound move of least skew wins, and only one
            // that lowers the skew can: those are judged from the least skew up and the first
            // sound one is taken (judging costs a projection per quad).
            if folded_before == 0 {
                landed.retain(|l| l.0 < skew_before);
                landed.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            for (skew_now, q, nq, arc) in landed {
                if folded_before == 0 && best.is_some() {
                    break;
                }
                let old_normal = normals[v];
                quads.positions[v] = q;
                normals[v] = nq;
                let shapes = shapes_around(&quads.positions, &normals);
                let score = (folded(&shapes), skew_now);
                let unfolds = score.0 < folded_before && badness(&shapes) < badness(&shapes_before);
                let better = unfolds || (score.0 == folded_before && score.1 < skew_before);
                let sound = better
                    && best.as_ref().is_none_or(|b| score < b.score)
                    && (!bent[v] || covers(&quads.positions, &anchor, &quads.quads, around, v))
                    && cuts_no_bend(arc)
                    && around.iter().zip(&shapes).all(|(&i, now)| {
                        (keeps(&before[i as usize], now) || (unfolds && !now.flipped))
                            && !strays(surface, &quads.positions, quads.quads[i as usize], reach[i as usize], &mut quad_leaf[i as usize])
                    });
                if sound {
                    best = Some(Move { score, at: q, normal: nq, arc, shapes });
                }
                quads.positions[v] = p;
                normals[v] = old_normal;
            }
            if let Some(Move { at, normal, arc, shapes, .. }) = best {
                quads.positions[v] = at;
                normals[v] = normal;
                slides.moved(v, arc);
                for (&i, shape) in around.iter().zip(shapes) {
                    now[i as usize] = shape;
                }
                moves += 1;
                moved_at[v] = moves;
                refused_at[v] = None;
            } else {
                refused_at[v] = Some(moves);
            }
        }
    }
    moved_at.iter().filter(|&&t| t > 0).count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NONE;
    use crate::quad::rails::Polyline;

    /// The powers taken without `powf` are the powers.
    #[test]
    fn to_power_is_the_power() {
        for d in [0.0, 0.3, 1.0, 7.5, 89.9] {
            for power in [2.0, 1.5, 1.3] {
                let (got, want) = (to_power(d, power), f64::powf(d, power));
                assert!((got - want).abs() <= 1e-12 * want.max(1.0), "{d}^{power}: {got} vs {want}");
            }
        }
    }

    /// An n × n grid of quads on the unit square (z = 0), with `offset` added to each interior
    /// vertex at (i, j); the boundary vertices pinned.
    fn grid(n: usize, offset: impl Fn(usize, usize) -> [f64; 2]) -> (QuadMesh, Vec<bool>) {
        let mut positions = Vec::new();
        let mut pinned = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let boundary = i == 0 || j == 0 || i == n || j == n;
                let d = if boundary { [0.0; 2] } else { offset(i, j) };
                positions.push([i as f64 / n as f64 + d[0], j as f64 / n as f64 + d[1], 0.0]);
                pinned.push(boundary);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let quads = (0..n).flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])).collect();
        let vertex_node = vec![NONE; positions.len()];
        (QuadMesh { positions, quads, vertex_node }, pinned)
    }

    /// An n × n grid with every vertex pinned but `v`.
    fn grid_free_at(n: usize, v: usize) -> (QuadMesh, Vec<bool>) {
        let (m, _) = grid(n, |_, _| [0.0; 2]);
        let pinned = (0..m.positions.len()).map(|w| w != v).collect();
        (m, pinned)
    }

    fn plane() -> Surface {
        Surface::new(&[[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 2.0, 0.0], [-1.0, 2.0, 0.0]], vec![[0, 1, 2], [0, 2, 3]])
    }

    /// Mean |corner angle − 90°| in degrees.
    fn angle_deviation(m: &QuadMesh) -> f64 {
        let sum: f64 = m.quads.iter().flat_map(|&q| corner_angle_deviations(&q.map(|v| m.positions[v as usize]))).sum();
        sum / (4 * m.quads.len()) as f64
    }

    /// The quads of a grid on [`plane`] folded against it.
    fn folded_quads(m: &QuadMesh) -> usize {
        let normals = vec![[0.0, 0.0, 1.0]; m.positions.len()];
        m.quads.iter().filter(|&&q| shape(&m.positions, q, &normals, &plane(), &mut 0).flipped).count()
    }

    /// A tube round the z axis of radius 1 and `sides` flat sides (z from −1 to 5), each side
    /// split in two triangles per unit of length: a prism, or nearly a cylinder when `sides`
    /// is large.
    fn tube(sides: usize) -> Surface {
        let ring = |z: f64| (0..sides).map(move |k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            [a.cos(), a.sin(), z]
        });
        let positions: Vec<Vec3> = (-1..=5).flat_map(|z| ring(z as f64)).collect();
        let id = |k: usize, z: usize| (z * sides + k % sides) as u32;
        let triangles = (0..6).flat_map(|z| (0..sides).flat_map(move |k| [[id(k, z), id(k + 1, z), id(k + 1, z + 1)], [id(k, z), id(k + 1, z + 1), id(k, z + 1)]])).collect();
        Surface::new(&positions, triangles)
    }

    /// Six quads round the tube and four along it (z from 0 to 4), the two end rings pinned,
    /// the vertex at angle 0 of the middle ring pushed 0.3 along the tube.
    fn quads_round_a_tube() -> (QuadMesh, Vec<bool>, usize) {
        let positions: Vec<Vec3> = (0..=4)
            .flat_map(|z| (0..6).map(move |k| {
                let a = std::f64::consts::TAU * k as f64 / 6.0;
                [a.cos(), a.sin(), z as f64 + if z == 2 && k == 0 { 0.3 } else { 0.0 }]
            }))
            .collect();
        let id = |k: usize, z: usize| (z * 6 + k % 6) as u32;
        let quads = (0..4).flat_map(|z| (0..6).map(move |k| [id(k, z), id(k + 1, z), id(k + 1, z + 1), id(k, z + 1)])).collect();
        let pinned = (0..positions.len()).map(|v| !(6..24).contains(&v)).collect();
        let vertex_node = vec![NONE; positions.len()];
        (QuadMesh { positions, quads, vertex_node }, pinned, 12)
    }

    /// Six quads round a tube meet at 60°, a crease of the quads. On a prism of six sides the
    /// surface has that edge too and the vertex on it stays; on a round tube only the quads
    /// bend, and the vertex pushed along it comes back between its neighbours.
    #[test]
    fn a_vertex_where_only_the_quads_bend_moves_and_one_on_a_sharp_edge_stays() {
        let (mut on_prism, pinned, v) = quads_round_a_tube();
        let squared = vec![true; pinned.len()];
        let pushed = on_prism.positions[v];
        relax(&mut on_prism, &tube(6), &pinned, &Rails::default(), &squared, STEPS, ROUNDS);
        assert_eq!(on_prism.positions[v], pushed);
        let (mut on_cylinder, _, _) = quads_round_a_tube();
        relax(&mut on_cylinder, &tube(96), &pinned, &Rails::default(), &squared, STEPS, ROUNDS);
        let z = on_cylinder.positions[v][2];
        assert!((z - 2.0).abs() < 0.1, "the vertex pushed to z = 2.3 is at z = {z}");
    }

    /// Two flat sides at right angles, z = 0 for x < 0 and x = 0 for z > 0, joined by a
    /// fillet of radius `r` (16 triangles across, 8° apart: no sharp edge), from y = −2 to 2.
    fn filleted_corner(r: f64) -> Surface {
        let arc = (0..=16).map(|k| {
            let t = std::f64::consts::FRAC_PI_2 * k as f64 / 16.0;
            [-r + r * t.sin(), r - r * t.cos()]
        });
        let profile: Vec<[f64; 2]> = [[-3.0, 0.0]].into_iter().chain(arc).chain([[0.0, 3.0]]).collect();
        let positions: Vec<Vec3> = [-2.0, 2.0].iter().flat_map(|&y| profile.iter().map(move |&[x, z]| [x, y, z])).collect();
        let m = profile.len() as u32;
        let triangles = (0..m - 1).flat_map(|i| [[i, i + 1, m + i + 1], [i, m + i + 1, m + i]]).collect();
        Surface::new(&positions, triangles)
    }

    /// A vertex on the fillet whose quads would be squarer with it on the bottom side (where
    /// the rows beside it have theirs) stays on the fillet: there its quads would cut the
    /// fillet off. Only the quads bend there, and no sharp edge holds it.
    #[test]
    fn a_vertex_on_a_fillet_is_not_moved_off_it() {
        let r = 0.3;
        let on_fillet = [-r + r * 0.5f64.sqrt(), r - r * 0.5f64.sqrt()];
        let row = |y: f64, middle: [f64; 2]| [[-2.0, 0.0], [-1.0, 0.0], middle, [0.0, 0.5], [0.0, 1.0]].map(|[x, z]| [x, y, z]);
        let positions: Vec<Vec3> = [row(-1.0, [-0.5, 0.0]), row(0.0, on_fillet), row(1.0, [-0.5, 0.0])].concat();
        let id = |i: usize, j: usize| (j * 5 + i) as u32;
        let quads = (0..2).flat_map(|j| (0..4).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])).collect();
        let v = id(2, 1) as usize;
        let pinned: Vec<bool> = (0..positions.len()).map(|w| w != v).collect();
        let mut m = QuadMesh { positions, quads, vertex_node: vec![NONE; 15] };
        relax(&mut m, &filleted_corner(r), &pinned, &Rails::default(), &[true; 15], STEPS, ROUNDS);
        let [x, _, z] = m.positions[v];
        assert!(x > -r && z > 0.02 * r, "moved off the fillet to {:?}", m.positions[v]);
    }

    /// The bottom side's samples bunched toward one end (as a harmonic map that stretches one
    /// end of a tagged side spaces them): pinned, the grid lines leave that side at a slant;
    /// sliding along it, they meet it square, and the samples stay on it, in order.
    #[test]
    fn samples_of_a_tagged_side_slide_along_it_until_the_grid_meets_it_square() {
        let n = 8;
        let bunched = |m: &mut QuadMesh| {
            for i in 1..n {
                let t = i as f64 / n as f64;
                m.positions[i][0] = t * t;
            }
        };
        let (mut pinned_only, pinned) = grid(n, |_, _| [0.0; 2]);
        bunched(&mut pinned_only);
        let skewed = angle_deviation(&pinned_only);
        let mut sliding = pinned_only.clone();
        relax(&mut pinned_only, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        let mut rails = Rails { curves: vec![Polyline::new(vec![[0.0; 3], [1.0, 0.0, 0.0]])], on: vec![None; sliding.positions.len()] };
        for i in 1..n {
            rails.place(i as u32, 0, sliding.positions[i]);
        }
        relax(&mut sliding, &plane(), &pinned, &rails, &vec![true; pinned.len()], STEPS, ROUNDS);
        let (held, slid) = (angle_deviation(&pinned_only), angle_deviation(&sliding));
        assert!(slid < 0.6 * held && held < skewed, "{skewed} -> pinned {held}, sliding {slid}");
        let bottom: Vec<Vec3> = (0..=n).map(|i| sliding.positions[i]).collect();
        assert!(bottom.iter().all(|p| p[1] == 0.0 && p[2] == 0.0), "{bottom:?}");
        assert!(bottom.windows(2).all(|w| w[0][0] < w[1][0]), "{bottom:?}");
        assert_eq!((bottom[0], bottom[n]), ([0.0; 3], [1.0, 0.0, 0.0]));
    }

    #[test]
    fn a_regular_grid_stays_as_it_is() {
        let (mut m, pinned) = grid(6, |_, _| [0.0; 2]);
        let before = m.positions.clone();
        relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        for (a, b) in m.positions.iter().zip(&before) {
            assert!(norm(sub(*a, *b)) < 1e-12, "{a:?} moved from {b:?}");
        }
    }

    #[test]
    fn a_skewed_grid_gets_straighter_on_the_surface_and_the_pinned_stay() {
        // Interior vertices pushed along a wave: skewed corners, none folded.
        let (mut m, pinned) = grid(8, |i, j| [0.04 * (j as f64).sin(), 0.04 * (i as f64 * 1.7).cos()]);
        let before = m.clone();
        let skew = angle_deviation(&m);
        let moved = relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        assert!(moved > 0);
        assert!(angle_deviation(&m) < 0.5 * skew, "{} -> {}", skew, angle_deviation(&m));
        for v in 0..m.positions.len() {
            assert!(m.positions[v][2].abs() < 1e-12, "left the plane");
            if pinned[v] {
                assert_eq!(m.positions[v], before.positions[v]);
            }
        }
        let normals = vec![[0.0, 0.0, 1.0]; m.positions.len()];
        for &q in &m.quads {
            let s = shape(&m.positions, q, &normals, &plane(), &mut 0);
            assert!(s.convex && !s.flipped);
        }
    }

    #[test]
    fn no_rounds_move_nothing() {
        let (mut m, pinned) = grid(8, |i, j| [0.04 * (j as f64).sin(), 0.04 * (i as f64 * 1.7).cos()]);
        let before = m.positions.clone();
        assert_eq!(relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], 0, 0), 0);
        assert_eq!(m.positions, before);
    }

    #[test]
    fn a_vertex_folded_over_its_neighbour_is_unfolded() {
        // The only free vertex sits beyond the corner of its diagonal neighbour: its quads
        // fold. Moves that unfold are allowed, and none may fold anything again.
        let v = 2 * 5 + 2;
        let (mut m, pinned) = grid_free_at(4, v);
        m.positions[v] = [0.8, 0.8, 0.0];
        assert!(folded_quads(&m) > 0);
        relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        assert_eq!(folded_quads(&m), 0);
        assert!(norm(sub(m.positions[v], [0.5, 0.5, 0.0])) < 0.01, "{:?}", m.positions[v]);
    }

    #[test]
    fn a_folded_corner_moves_though_its_quads_make_a_crease() {
        // As in the test above, but the neighbour on the left stands off the plane: the quads
        // round the free vertex meet at more than the crease angle, which would hold it where
        // it is. A corner of a folded quad is free to mend it.
        let v = 2 * 5 + 2;
        let (mut m, pinned) = grid_free_at(4, v);
        m.positions[v] = [0.8, 0.8, 0.0];
        m.positions[v - 1][2] = 0.3;
        assert!(folded_quads(&m) > 0);
        relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        assert_eq!(folded_quads(&m), 0);
    }

    #[test]
    fn a_vertex_goes_where_its_corners_are_squarest_not_to_its_neighbours_mean() {
        // The centre of a 2 × 2 grid, all else pinned, the right and top midpoints pulled
        // away from the middle: the neighbours' mean and the parallelograms are not where
        // the four quads' corners come nearest right angles, which a search of the square
        // finds (the skew's squares have one least there).
        let v = 4;
        let (mut m, pinned) = grid_free_at(2, v);
        m.positions[5] = [1.0, 0.8, 0.0];
        m.positions[7] = [0.8, 1.0, 0.0];
        let skew_at = |m: &QuadMesh, x: [f64; 2]| {
            let mut p = m.positions.clone();
            p[v] = [x[0], x[1], 0.0];
            m.quads.iter().map(|&q| skew(&p, q, 2.0)).sum::<f64>()
        };
        let search = (0..=300).flat_map(|i| (0..=300).map(move |j| [0.3 + 0.002 * i as f64, 0.3 + 0.002 * j as f64]));
        let least = search.map(|x| skew_at(&m, x)).fold(f64::INFINITY, f64::min);
        let mean = skew_at(&m, [0.575, 0.575]);
        assert!(mean > 1.5 * least, "the test needs a mean {mean} off the least skew {least}");
        relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        let p = m.positions[v];
        let relaxed = skew_at(&m, [p[0], p[1]]);
        assert!(relaxed < 1.001 * least, "relaxed to {p:?}: skew {relaxed}, the least {least}, the mean's {mean}");
    }

    #[test]
    fn a_free_border_vertex_folded_inwards_goes_back_to_where_its_quads_are_parallelograms() {
        // On the border, the vertex has three neighbours, whose mean lies inside the patch: the
        // parallelograms of its two quads put it back on the border.
        let v = 2;
        let (mut m, pinned) = grid_free_at(4, v);
        m.positions[v] = [0.5, 0.55, 0.0];
        assert_eq!(folded_quads(&m), 2);
        relax(&mut m, &plane(), &pinned, &Rails::default(), &vec![true; pinned.len()], STEPS, ROUNDS);
        assert_eq!(folded_quads(&m), 0);
        assert!(norm(sub(m.positions[v], [0.5, 0.0, 0.0])) < 0.02, "{:?}", m.positions[v]);
    }
}
