//! The surface's points the quads miss most get a quad vertex on them. A grid spaced evenly
//! in the charts cuts across a tip of the surface (a bunny's ear, a tail, the bottom of a
//! well) that falls between its vertices, and the Hausdorff distance is that one miss: on
//! bunny_1k8's automatic layout at --quads 4000, 1.55 % of the diagonal at an ear's tip, where
//! the next spot misses by 1.05 %. Moving the nearest free corner of the quad that misses
//! onto the point covers it, and costs the angles of its quads.
//!
//! Rounds, each from the distances as the last one left them: the surface's points farthest
//! from the quads first, each one that misses by more than [`TIP`] of an edge gets the move of
//! a corner of its nearest quad that leaves every point near those quads, and their probes,
//! nearer than it was by [`GAIN`]; the first one no move covers is as near as the quads come,
//! and the round ends there (moving others would cost angles for no lower maximum). The
//! samples of tagged curves and the boundary stay (they are the edge loops asked for); the
//! other nodes may move, as in the relaxation.
//!
//! At --quads 4000 on the automatic layouts of 29 of CGAL's meshes never used in tuning, the
//! geometric-mean Hausdorff distance fell from 0.971 to 0.876 % and the mean angle deviation
//! rose from 7.39 to 7.46° (horizons 0.89 → 0.26 %, knot2 1.48 → 0.56 % with 8.57 → 9.81°,
//! lion 1.63 → 1.14 %, pig 1.79 → 1.17 %); the others are unchanged.

use super::closest::{closest_point_on_triangle, TriangleTree};
use super::quality::{quad_triangles, scaled_jacobian};
use super::relax::{keeps, probes, shape, size, skew, QuadState, Surface};
use super::QuadMesh;
use crate::geom::{add, norm, scale, sub, Vec3};

/// Rounds at most; each moves the vertices of quads no earlier move of the round touched (the
/// distances near those are found again for the next).
const ROUNDS: usize = 4;
/// A move must bring the point it covers, and every point and probe near the quads it moves,
/// nearer than this share of the point's distance: less is churn.
const GAIN: f64 = 0.9;
/// The shares of the way to the point a corner is moved, each tried: all the way may turn a
/// corner of its quads inside out where a shorter step still covers the point better.
const SHARES: [f64; 3] = [1.0, 0.7, 0.4];
/// No moved quad's corner may come flatter than this (the sine of its angle), or flatter than
/// it was.
const FLAT: f64 = 0.1;
/// Only a point that misses its nearest quad by more than this share of the quad's mean edge
/// length is covered: a bend the quads cannot follow, with a radius of curvature under about
/// 2.5 edges (a smooth bend's chord misses it by about edge² / (4 × radius) at a quad's
/// centre). Below, on a sphere or an ellipsoid's caps, every move skewed four quads by 40–80°
/// to take a few hundredths of a percent off the Hausdorff distance (CGAL's sphere966: 0.23 →
/// 0.15 %, 2.93 → 4.50° on the mean); the tips of ears and tails miss by 0.2–1.4 edges.
const TIP: f64 = 0.1;

/// The distance from `x` to the nearest of the quads `ids` at `positions` (each the two
/// triangles on either side of its diagonal 0–2, as the quality measures it), and that quad.
pub(super) fn nearest_quad(positions: &[Vec3], quads: &[[u32; 4]], ids: impl IntoIterator<Item = u32>, x: Vec3) -> (f64, u32) {
    let mut best = (f64::INFINITY, u32::MAX);
    for i in ids {
        for [a, b, d] in quad_triangles(quads[i as usize].map(|v| positions[v as usize])) {
            let distance = norm(sub(closest_point_on_triangle(x, a, b, d), x));
            if distance < best.0 {
                best = (distance, i);
            }
        }
    }
    best
}

/// Moves vertices of `quads` that are not `fixed` onto the points of `surface` (its
/// [`Surface::samples`]) that the quads miss most, while each move lowers the largest miss
/// round it. Returns the number of vertices moved.
pub fn cover(quads: &mut QuadMesh, surface: &Surface, fixed: &[bool]) -> usize {
    let points = &surface.samples();
    let n = quads.positions.len();
    let mut incident: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, q) in quads.quads.iter().enumerate() {
        q.iter().for_each(|&v| incident[v as usize].push(i as u32));
    }
    let mut leaf = 0;
    let mut normals: Vec<Vec3> = quads.positions.iter().map(|&p| surface.project(p, &mut leaf).map_or([0.0; 3], |(_, n)| n)).collect();
    let mut moved = vec![false; n];
    let mut miss: Vec<(f64, u32)> = vec![(0.0, u32::MAX); points.len()];
    // The points whose distance is looked up again: all at first; then those nearest a quad
    // that moved or its neighbours, and those that missed by more than [`TIP`].
    let mut stale = vec![true; points.len()];
    for _ in 0..ROUNDS {
        let tree = TriangleTree::new(quads.quads.iter().flat_map(|q| quad_triangles(q.map(|v| quads.positions[v as usize]))));
        // Each point's distance and nearest quad, found again where it may have changed; the
        // others keep theirs, which bound their distance still (their nearest quad did not
        // move, and a quad that moved can only have come nearer).
        for (m, (&p, again)) in miss.iter_mut().zip(points.iter().zip(&stale)) {
            if *again {
                *m = tree.closest_from(p, &mut leaf).map_or((0.0, u32::MAX), |hit| (hit.distance_squared.sqrt(), hit.triangle / 2));
            }
        }
        let mut nearest_to: Vec<Vec<u32>> = vec![Vec::new(); quads.quads.len()];
        for (i, &(_, q)) in miss.iter().enumerate() {
            if let Some(list) = nearest_to.get_mut(q as usize) {
                list.push(i as u32);
            }
        }
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        order.sort_by(|&a, &b| miss[b as usize].0.total_cmp(&miss[a as usize].0));
        // Quads a move of this round changed: the distances near them are no longer exact.
        let mut touched = vec![false; quads.quads.len()];
        let mut moves = 0;
        for &i in &order {
            let (d, q) = miss[i as usize];
            if q == u32::MAX || d <= 0.0 {
                break;
            }
            if touched[q as usize] {
                continue;
            }
            if d <= TIP * size(&quads.positions, quads.quads[q as usize]) {
                continue;
            }
            let point = points[i as usize];
            // The corner whose move all the way skews its quads least; only where none may go
            // all the way, the same with shorter moves.
            let free = quads.quads[q as usize].map(|v| !fixed[v as usize] && !moved[v as usize] && incident[v as usize].iter().all(|&a| !touched[a as usize]));
            let mut best: Option<(f64, u32, Vec3, Vec3)> = None;
            for share in SHARES {
                for (v, _) in quads.quads[q as usize].into_iter().zip(free).filter(|&(_, free)| free) {
                    let v = v as usize;
                    // Part of the way lands on the surface at the nearest point (one far from
                    // where it aimed is another sheet of the surface).
                    let aim = add(quads.positions[v], scale(share, sub(point, quads.positions[v])));
                    let Some(target) = (if share == 1.0 { Some(point) } else { surface.project(aim, &mut leaf).map(|(p, _)| p) }) else { continue };
                    if norm(sub(target, aim)) > norm(sub(aim, quads.positions[v])) {
                        continue;
                    }
                    // The surface's pseudo-normal there: a tip's triangles each lean their own way.
                    let Some(normal) = surface.facing(target, &mut leaf) else { continue };
                    let (worst, skew) = after_move(quads, surface, &incident, &normals, &nearest_to, points, v, target, normal);
                    if worst < GAIN * d && best.is_none_or(|b| skew < b.0) {
                        best = Some((skew, v as u32, target, normal));
                    }
                }
                if best.is_some() {
                    break;
                }
            }
            let Some((_, v, target, normal)) = best else { break };
            let v = v as usize;
            quads.positions[v] = target;
            normals[v] = normal;
            moved[v] = true;
            moves += 1;
            // The quads moved and their neighbours (whose points may now be nearest the
            // moved ones) wait for the next round's exact distances.
            for &a in &incident[v] {
                for &w in &quads.quads[a as usize] {
                    incident[w as usize].iter().for_each(|&b| touched[b as usize] = true);
                }
            }
        }
        if moves == 0 {
            break;
        }
        for (again, &(d, q)) in stale.iter_mut().zip(&miss) {
            *again = touched.get(q as usize).is_some_and(|&t| t || d > TIP * size(&quads.positions, quads.quads[q as usize]));
        }
    }
    moved.iter().filter(|&&m| m).count()
}

/// With vertex `v` moved to `target` (surface normal `normal`): the largest distance from a
/// point nearest one of its quads to the quads round them, and from a probe of its quads to
/// the surface (infinite where a quad of `v` would fold, turn a corner inside out or come
/// flatter than [`FLAT`]); and its quads' skew (of the moves that cover a point, the one
/// that skews them least is taken).
#[allow(clippy::too_many_arguments)]
fn after_move(
    quads: &mut QuadMesh,
    surface: &Surface,
    incident: &[Vec<u32>],
    normals: &[Vec3],
    nearest_to: &[Vec<u32>],
    points: &[Vec3],
    v: usize,
    target: Vec3,
    normal: Vec3,
) -> (f64, f64) {
    let around = &incident[v];
    let mut leaf = 0;
    let before: Vec<(QuadState, f64)> = around
        .iter()
        .map(|&a| {
            let q = quads.quads[a as usize];
            (shape(&quads.positions, q, normals, surface, &mut leaf), scaled_jacobian(&q.map(|w| quads.positions[w as usize])))
        })
        .collect();
    let was = quads.positions[v];
    quads.positions[v] = target;
    let sound = around.iter().zip(&before).all(|(&a, (state, jacobian))| {
        let q = quads.quads[a as usize];
        // The quad on its own, its corners numbered 0–3, with the moved corner's normal.
        let corner_normals = q.map(|w| if w as usize == v { normal } else { normals[w as usize] });
        let now = shape(&q.map(|w| quads.positions[w as usize]), [0, 1, 2, 3], &corner_normals, surface, &mut leaf);
        keeps(state, &now) && scaled_jacobian(&q.map(|w| quads.positions[w as usize])) >= jacobian.min(FLAT)
    });
    let worst = if sound {
        // The quads round the moved ones: where a point's nearest quad may now be.
        let mut ring: Vec<u32> = around.iter().flat_map(|&a| quads.quads[a as usize]).flat_map(|w| incident[w as usize].iter().copied()).collect();
        ring.sort_unstable();
        ring.dedup();
        let from_points = around
            .iter()
            .flat_map(|&a| &nearest_to[a as usize])
            .map(|&i| nearest_quad(&quads.positions, &quads.quads, ring.iter().copied(), points[i as usize]).0)
            .fold(0.0, f64::max);
        let from_probes = around
            .iter()
            .flat_map(|&a| probes(&quads.positions, quads.quads[a as usize]))
            .map(|x| surface.project(x, &mut leaf).map_or(f64::INFINITY, |(p, _)| norm(sub(p, x))))
            .fold(0.0, f64::max);
        from_points.max(from_probes)
    } else {
        f64::INFINITY
    };
    let skew = around.iter().map(|&a| skew(&quads.positions, quads.quads[a as usize], 2.0)).sum();
    quads.positions[v] = was;
    (worst, skew)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NONE;

    /// The height of a cone of height `tip` whose apex is over (1.3, 1.3) and whose foot has
    /// radius 1.
    fn cone(tip: f64, x: f64, y: f64) -> f64 {
        tip * (1.0 - (x - 1.3).hypot(y - 1.3)).max(0.0)
    }

    /// The square [0, 4]² triangulated at steps of 0.1, with the [`cone`] on it (its apex is a
    /// vertex).
    fn spiked_plane(tip: f64) -> (Vec<Vec3>, Surface) {
        let n = 40;
        let height = |x: f64, y: f64| cone(tip, x, y);
        let positions: Vec<Vec3> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| (i as f64 * 0.1, j as f64 * 0.1)))
            .map(|(x, y)| [x, y, height(x, y)])
            .collect();
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let indices = (0..n).flat_map(|j| (0..n).flat_map(move |i| [[at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]])).collect();
        (positions.clone(), Surface::new(&positions, indices))
    }

    /// The unit quads over [0, 4]², their corners on the [`cone`] of height `tip` (its apex
    /// falls inside one).
    fn unit_grid(tip: f64) -> QuadMesh {
        let at = |i: u32, j: u32| j * 5 + i;
        let positions = (0..5).flat_map(|j| (0..5).map(move |i| [i as f64, j as f64, cone(tip, i as f64, j as f64)])).collect();
        let quads = (0..4).flat_map(|j| (0..4).map(move |i| [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)])).collect();
        QuadMesh { positions, quads, vertex_node: vec![NONE; 25] }
    }

    fn farthest_miss(quads: &QuadMesh, points: &[Vec3]) -> f64 {
        points.iter().map(|&p| nearest_quad(&quads.positions, &quads.quads, 0..quads.quads.len() as u32, p).0).fold(0.0, f64::max)
    }

    #[test]
    fn the_nearest_free_corner_goes_onto_a_tip_the_quads_cut_off() {
        let (points, surface) = spiked_plane(0.3);
        let mut quads = unit_grid(0.3);
        let before = quads.clone();
        let missed = farthest_miss(&quads, &points);
        assert!(missed > 0.1, "{missed}");
        let fixed = vec![false; 25];
        assert_eq!(cover(&mut quads, &surface, &fixed), 1);
        // The corner at (1, 1), the nearest to the apex, is on it; the others stay.
        assert_eq!(quads.positions[6], [1.3, 1.3, 0.3]);
        let others_stay = (0..25).filter(|&v| v != 6).all(|v| quads.positions[v] == before.positions[v]);
        assert!(others_stay);
        // The flanks of the cone between the corners still miss, by less (0.177 -> 0.132).
        let now = farthest_miss(&quads, &points);
        assert!(now < GAIN * missed, "{missed} -> {now}");
    }

    #[test]
    fn a_bend_the_quads_follow_within_a_tenth_of_an_edge_is_left_alone() {
        // A cone 0.08 high: the apex misses the unit quads by less than a tenth of an edge.
        let (_, surface) = spiked_plane(0.08);
        let mut quads = unit_grid(0.08);
        assert_eq!(cover(&mut quads, &surface, &[false; 25]), 0);
        assert_eq!(quads, unit_grid(0.08));
    }

    #[test]
    fn fixed_corners_and_a_flat_surface_move_nothing() {
        let (_, surface) = spiked_plane(0.3);
        let mut quads = unit_grid(0.3);
        let fixed = vec![true; 25];
        assert_eq!(cover(&mut quads, &surface, &fixed), 0);
        assert_eq!(quads, unit_grid(0.3));
        let (_, flat) = spiked_plane(0.0);
        let mut quads = unit_grid(0.0);
        assert_eq!(cover(&mut quads, &flat, &[false; 25]), 0);
        assert_eq!(quads, unit_grid(0.0));
    }
}
