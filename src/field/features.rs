//! Sharp feature edges and the lines they form (issue 22; `--feature-angle`).
//!
//! An interior mesh edge is sharp when the normals of its two triangles differ by more than
//! the feature angle. Sharp edges chain into feature lines; a line is cut at its *corners*:
//! vertices where other than two sharp edges meet, or where the line turns sharply. Small
//! groups of sharp edges (noise on scanned surfaces) are dropped, and so are groups whose
//! surface keeps turning beside them (a coarse or noisy tessellation of a smooth surface).

use crate::geom::{add, dot, norm, scale, sub, unit, Vec3};
use crate::mesh::geometry::{edge_lengths, face_normals};
use crate::mesh::adjacency::Adjacency;
use crate::mesh::{Mesh, NONE};
use std::collections::HashMap;


/// The sharp edges kept, and the feature lines between corners.
#[derive(Debug, Clone, Default)]
pub struct Features {
    /// Per mesh edge: part of a kept feature line.
    pub sharp: Vec<bool>,
    /// Per vertex: number of kept sharp edges at it.
    pub degree: Vec<u32>,
    /// Vertices where feature lines end, meet or bend: layout nodes.
    pub corners: Vec<u32>,
    /// Each feature line as its vertices in order, from corner to corner (a closed line
    /// without corners starts and ends at the same vertex).
    pub lines: Vec<Vec<u32>>,
}

/// A line turning by more than this at a vertex has a corner there.
const CORNER_TURN_DEG: f64 = 45.0;
/// A sharp edge is a feature only if it bends this many times more than the most bent
/// non-sharp edge of its two triangles.
const CREASE_RATIO: f64 = 3.0;
/// Groups of sharp edges shorter than this fraction of the bounding-box diagonal are noise.
const MIN_GROUP_LENGTH: f64 = 0.1;
/// The flanks of a sharp edge: the triangles on each side within this fraction of the
/// diagonal of its midpoint, or within [`FLANK_EDGES`] of its lengths where it is longer.
const FLANK_RADIUS: f64 = 0.04;
const FLANK_EDGES: f64 = 3.0;

/// How much the surface turns beside a sharp edge: a flood of the triangles on each side,
/// across edges that are not sharp, within a radius of the edge's midpoint.
struct Flanks<'a> {
    mesh: &'a Mesh,
    normals: &'a [Vec3],
    dihedral: &'a [f64],
    limit: f64,
    radius: f64,
    centroids: Vec<Vec3>,
    /// The last side (halfedge) whose flood reached each triangle (`NONE`: none yet).
    reached: Vec<u32>,
    stack: Vec<u32>,
}

impl<'a> Flanks<'a> {
    fn new(mesh: &'a Mesh, normals: &'a [Vec3], dihedral: &'a [f64], limit: f64, radius: f64) -> Self {
        let centroids = mesh.triangles().iter().map(|t| scale(1.0 / 3.0, t.iter().fold([0.0; 3], |c, &v| add(c, mesh.position(v))))).collect();
        let reached = vec![NONE; mesh.n_faces()];
        Flanks { mesh, normals, dihedral, limit, radius, centroids, reached, stack: Vec::new() }
    }

    /// The largest angle between the normal of a triangle beside interior edge `e` and a
    /// normal of the flank on its side, over both sides.
    fn turn(&mut self, e: u32) -> f64 {
        let m = self.mesh;
        let (a, b) = (m.position(m.from_vertex(2 * e)), m.position(m.to_vertex(2 * e)));
        let mid = scale(0.5, add(a, b));
        let r = self.radius.max(FLANK_EDGES * norm(sub(b, a)));
        let mut worst: f64 = 0.0;
        for h in [2 * e, 2 * e + 1] {
            let start = m.face(h);
            let n0 = self.normals[start as usize];
            self.reached[start as usize] = h;
            self.stack.push(start);
            while let Some(t) = self.stack.pop() {
                for k in 0..3 {
                    let g = m.face_halfedge(t, k);
                    let u = m.face(m.twin(g));
                    if u == NONE || self.reached[u as usize] == h || self.dihedral[m.edge(g) as usize] > self.limit {
                        continue;
                    }
                    if norm(sub(self.centroids[u as usize], mid)) <= r {
                        self.reached[u as usize] = h;
                        worst = worst.max(dot(n0, self.normals[u as usize]).clamp(-1.0, 1.0).acos());
                        self.stack.push(u);
                    }
                }
            }
        }
        worst
    }
}

/// A region that the sharp edges and the boundary cut out with every vertex on them can hold
/// no quad, and no layout face may be without a vertex inside: a chamfer one triangle wide
/// round a hole (CGAL's couplingdown and handle) is a ring of such triangles that no cut
/// makes a disk. The sharp edges between such a region and the neighbour with vertices inside
/// it shares the most of them with are not kept, which merges the two (a chamfer's line
/// along the larger side goes); again until no region is hollow or none has such a neighbour.
fn merge_hollow_regions(mesh: &Mesh, sharp: &mut [bool]) {
    let lengths = edge_lengths(mesh);
    loop {
        let (region, count) = Adjacency::new(mesh).regions(|e| sharp[e as usize]);
        let mut on_line: Vec<bool> = (0..mesh.n_vertices() as u32).map(|v| mesh.is_boundary_vertex(v)).collect();
        for e in (0..mesh.n_edges() as u32).filter(|&e| sharp[e as usize]) {
            on_line[mesh.from_vertex(2 * e) as usize] = true;
            on_line[mesh.to_vertex(2 * e) as usize] = true;
        }
        let mut has_inside = vec![false; count];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            has_inside[region[t] as usize] |= tri.iter().any(|&v| !on_line[v as usize]);
        }
        // Per hollow region: the length of sharp edges it shares with each neighbour that
        // has vertices inside.
        let mut shared: HashMap<(u32, u32), f64> = HashMap::new();
        let sides = |e: u32| [2 * e, 2 * e + 1].map(|h| mesh.face(h)).map(|f| if f == NONE { NONE } else { region[f as usize] });
        for e in (0..mesh.n_edges() as u32).filter(|&e| sharp[e as usize]) {
            let [a, b] = sides(e);
            for (r, n) in [(a, b), (b, a)] {
                if r != n && r != NONE && n != NONE && !has_inside[r as usize] && has_inside[n as usize] {
                    *shared.entry((r, n)).or_default() += lengths[e as usize];
                }
            }
        }
        if shared.is_empty() {
            return;
        }
        // The neighbour sharing the most; of equal lengths the first (whatever the map's order).
        let mut merge_with = vec![NONE; count];
        let mut most = vec![0.0; count];
        for (&(r, n), &l) in &shared {
            if l > most[r as usize] || (l == most[r as usize] && n < merge_with[r as usize]) {
                (most[r as usize], merge_with[r as usize]) = (l, n);
            }
        }
        for e in 0..mesh.n_edges() as u32 {
            let [a, b] = sides(e);
            let joins = |r: u32, n: u32| r != NONE && merge_with[r as usize] == n;
            if sharp[e as usize] && (joins(a, b) || joins(b, a)) {
                sharp[e as usize] = false;
            }
        }
    }
}

/// Finds the sharp edges of `mesh` (dihedral angle above `angle_deg`) and their lines.
impl Features {
    /// No feature lines at all.
    pub fn none(mesh: &Mesh) -> Features {
        Features { sharp: vec![false; mesh.n_edges()], degree: vec![0; mesh.n_vertices()], corners: Vec::new(), lines: Vec::new() }
    }
}

pub fn find_features(mesh: &Mesh, angle_deg: f64) -> Features {
    let ne = mesh.n_edges();
    let normals = face_normals(mesh);
    let limit = angle_deg.to_radians();
    let dihedral: Vec<f64> = (0..ne as u32)
        .map(|e| {
            let h = 2 * e;
            if mesh.is_boundary_edge(e) {
                return 0.0;
            }
            dot(normals[mesh.face(h) as usize], normals[mesh.face(h ^ 1) as usize]).clamp(-1.0, 1.0).acos()
        })
        .collect();
    // A crease stands out from the edges beside it; on a coarse curved surface every edge
    // bends about as much, and none is a feature.
    let mut sharp: Vec<bool> = (0..ne as u32)
        .map(|e| {
            let d = dihedral[e as usize];
            if d <= limit {
                return false;
            }
            let beside = [2 * e, 2 * e + 1]
                .into_iter()
                .flat_map(|h| [mesh.next(h), mesh.prev(h)])
                .map(|g| dihedral[mesh.edge(g) as usize])
                .filter(|&b| b <= limit)
                .fold(0.0, f64::max);
            d > CREASE_RATIO * beside
        })
        .collect();

    // Drop small groups of sharp edges, and those whose flanks are no flatter than they.
    let diag = super::diagonal(mesh);
    let min_len = MIN_GROUP_LENGTH * diag;
    let mut flank = Flanks::new(mesh, &normals, &dihedral, limit, FLANK_RADIUS * diag);
    let len = |e: u32| norm(sub(mesh.position(mesh.to_vertex(2 * e)), mesh.position(mesh.from_vertex(2 * e))));
    let mut seen = vec![false; ne];
    for s in 0..ne {
        if !sharp[s] || seen[s] {
            continue;
        }
        let mut group = vec![s as u32];
        seen[s] = true;
        let mut k = 0;
        while k < group.len() {
            let e = group[k];
            k += 1;
            for v in [mesh.to_vertex(2 * e), mesh.from_vertex(2 * e)] {
                for h in mesh.outgoing(v) {
                    let f = mesh.edge(h) as usize;
                    if sharp[f] && !seen[f] {
                        seen[f] = true;
                        group.push(f as u32);
                    }
                }
            }
        }
        // A crease bends the surface at once and leaves it flat beside it: on a coarse or
        // noisy tessellation of a smooth surface (the low-resolution bunny, the 315-vertex
        // eight) the surface goes on turning beside the sharp edges about as much as at them.
        // Measured at --feature-angle 35: fandisk's creases bend 14 times more than their
        // flanks turn (median), the sharp groups of bunny_1k8, eight, nefertiti at most 1.9
        // times. Decided per group, so a line is kept or dropped whole.
        // Short groups go whatever their flanks, without flooding them.
        let short = group.iter().map(|&e| len(e)).sum::<f64>() < min_len;
        let mut smooth = || {
            let mut ratios: Vec<f64> = group.iter().map(|&e| dihedral[e as usize] / flank.turn(e).max(f64::MIN_POSITIVE)).collect();
            ratios.sort_by(f64::total_cmp);
            ratios[ratios.len() / 2] < CREASE_RATIO
        };
        if short || smooth() {
            for e in group {
                sharp[e as usize] = false;
            }
        }
    }

    merge_hollow_regions(mesh, &mut sharp);

    let mut degree = vec![0u32; mesh.n_vertices()];
    for e in 0..ne as u32 {
        if sharp[e as usize] {
            degree[mesh.to_vertex(2 * e) as usize] += 1;
            degree[mesh.from_vertex(2 * e) as usize] += 1;
        }
    }
    let sharp_out = |v: u32| mesh.outgoing(v).filter(|&h| sharp[mesh.edge(h) as usize]).collect::<Vec<_>>();
    let mut is_corner = vec![false; mesh.n_vertices()];
    for v in 0..mesh.n_vertices() as u32 {
        let d = degree[v as usize];
        if d == 0 {
            continue;
        }
        if d != 2 || mesh.is_boundary_vertex(v) {
            is_corner[v as usize] = true;
            continue;
        }
        let hs = sharp_out(v);
        let p = mesh.position(v);
        let a = unit(sub(mesh.position(mesh.to_vertex(hs[0])), p));
        let b = unit(sub(mesh.position(mesh.to_vertex(hs[1])), p));
        // Straight through: a and b opposite.
        if -dot(a, b) < CORNER_TURN_DEG.to_radians().cos() {
            is_corner[v as usize] = true;
        }
    }

    // Walk lines from corners, then the closed loops that have none.
    let mut used = vec![false; ne];
    let mut lines = Vec::new();
    let walk = |start: u32, h0: u32, used: &mut Vec<bool>, is_corner: &[bool]| {
        let mut line = vec![start];
        let mut h = h0;
        loop {
            used[mesh.edge(h) as usize] = true;
            let v = mesh.to_vertex(h);
            line.push(v);
            if is_corner[v as usize] || v == start {
                break;
            }
            match sharp_out(v).into_iter().find(|&g| !used[mesh.edge(g) as usize]) {
                Some(g) => h = g,
                None => break,
            }
        }
        line
    };
    for v in 0..mesh.n_vertices() as u32 {
        if !is_corner[v as usize] {
            continue;
        }
        for h in sharp_out(v) {
            if !used[mesh.edge(h) as usize] {
                lines.push(walk(v, h, &mut used, &is_corner));
            }
        }
    }
    for e in 0..ne as u32 {
        if sharp[e as usize] && !used[e as usize] {
            // A closed line without corners: its start becomes one.
            let v = mesh.from_vertex(2 * e);
            is_corner[v as usize] = true;
            lines.push(walk(v, 2 * e, &mut used, &is_corner));
        }
    }
    let corners = (0..mesh.n_vertices() as u32).filter(|&v| is_corner[v as usize]).collect();
    Features { sharp, degree, corners, lines }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::primitives::quad_grid;

    /// Two square loops of sharp edges one grid cell apart on a 20 × 20 grid: the band
    /// between them has every vertex on a loop, so it merges with the outside, which it
    /// shares the longer loop with; the inner loop stays.
    #[test]
    fn a_band_with_no_vertex_inside_loses_its_longer_line() {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let square = |lo: u32, hi: u32| {
            let mut edges = Vec::new();
            for k in lo..hi {
                for (a, b) in [(at(k, lo), at(k + 1, lo)), (at(hi, k), at(hi, k + 1)), (at(k, hi), at(k + 1, hi)), (at(lo, k), at(lo, k + 1))] {
                    edges.push(mesh.edge(mesh.find_halfedge(a, b).expect("a grid edge")));
                }
            }
            edges
        };
        let (inner, outer) = (square(7, 13), square(6, 14));
        let mut sharp = vec![false; mesh.n_edges()];
        for &e in inner.iter().chain(&outer) {
            sharp[e as usize] = true;
        }
        merge_hollow_regions(&mesh, &mut sharp);
        assert!(inner.iter().all(|&e| sharp[e as usize]), "the inner loop stays");
        assert!(outer.iter().all(|&e| !sharp[e as usize]), "the outer loop goes");
        // Nothing hollow is left: merging again changes nothing.
        let kept = sharp.clone();
        merge_hollow_regions(&mesh, &mut sharp);
        assert_eq!(sharp, kept);
    }
}
