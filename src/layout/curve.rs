//! Layout-edge curves traced on the surface as geodesics (paper Section 3, Fig. 3;
//! method-notes §0; layout-format.md, "edges").
//!
//! A curve is recorded as the mesh vertices it runs through and the points where it crosses
//! the interiors of mesh edges, in order ([`CurvePoint`]). Between two consecutive points it
//! is a straight segment inside one triangle (or along one mesh edge).
//!
//! # Method
//! 1. A shortest path over the edge graph (A* with the straight-line distance as the
//!    heuristic) that passes through no blocked vertex gives a chain of mesh edges.
//! 2. The triangles on one side of that chain at each of its vertices (the side with the
//!    smaller angle) form a *strip*: triangles `T_0 … T_n` in which `T_{i-1}` and `T_i` share
//!    a mesh edge, the *portal* `i`.
//! 3. The strip is unfolded into the plane and the path is pulled taut inside it with the
//!    funnel algorithm (string pulling). The taut path bends only at strip vertices, the
//!    *pivots*.
//! 4. A pivot `v` around which the path turns with the angle `β ≥ π` on the strip's side has
//!    the angle `θ(v) − β` on the other side (`θ` the total angle at `v`). If that is less than
//!    π the path gets shorter by passing `v` on the other side: the strip's triangles around
//!    `v` are replaced by those on the other side (Xin & Wang 2007, "Efficiently determining a
//!    locally exact shortest path on polyhedral surfaces"). Steps 3–4 repeat until no pivot
//!    qualifies or the length stops falling (at most [`MAX_ROUNDS`] rounds). Every reroute
//!    only ever widens the strip towards shorter paths, so a straight line that leaves the
//!    first strip is still found.
//!
//! The result is a locally shortest path (a geodesic in the sense of polyhedral surfaces:
//! straight when unfolded across every edge it crosses, and with at least π on both sides of
//! every vertex it runs through). Saddle vertices (θ > 2π) and boundary vertices can be run
//! through; vertices of positive curvature (θ < 2π) never are. Along the straight sharp
//! feature lines of CAD meshes both sides measure π: the curve runs through their vertices.

use crate::geom::{angle2, cross, dist2, dot, norm, orient2, sub, sub2, Vec2, SNAP};
use crate::mesh::geometry::corner_angle;
use crate::mesh::{Mesh, NONE};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap, HashSet};
use std::f64::consts::PI;
use std::fmt;

/// A point of a curve: a mesh vertex, or a point inside mesh edge `edge` at parameter `t` in
/// (0, 1) measured along halfedge `2 * edge`:
/// `p = (1 - t) * pos(from_vertex(2e)) + t * pos(to_vertex(2e))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CurvePoint {
    Vertex(u32),
    Edge { edge: u32, t: f64 },
}

/// A curve on the surface (method-notes §0).
///
/// Invariants of traced curves: the first and last points are `Vertex(node)`; no two
/// consecutive points are equal; consecutive points lie in a common triangle, or are the two
/// ends of a mesh edge (see [`common_face`]); `t` of an `Edge` point is at least
/// [`SNAP`] away from 0 and 1 (closer crossings are recorded as the vertex).
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub points: Vec<CurvePoint>,
    /// Length on the surface: the sum of the straight segments between consecutive points.
    pub length: f64,
}

/// Why a curve could not be traced.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveError {
    /// Fewer than two stops were given.
    TooFewStops { count: usize },
    /// Stop `index` is not a vertex of the mesh, or a vertex no triangle uses.
    NotOnSurface { index: usize, vertex: u32 },
    /// Every stop is the same vertex: the curve would have length zero.
    ZeroLength { vertex: u32 },
    /// No path over the surface joins `from` and `to` without passing a blocked vertex (they
    /// lie on different components, or blocked vertices cut them apart).
    NoPath { from: u32, to: u32 },
    /// The shortest path from `from` to `to` runs through the blocked vertex `vertex`: going
    /// around it on either side is longer, so there is no shortest path avoiding it. (A
    /// layout node on the straight line between two others, or on a saddle or a concave
    /// boundary corner that the path wraps.) A waypoint can steer the curve around it.
    ThroughBlocked { from: u32, to: u32, vertex: u32 },
}

impl fmt::Display for CurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveError::TooFewStops { count } => {
                write!(f, "a curve needs at least two stops, got {count}")
            }
            CurveError::NotOnSurface { index, vertex } => {
                write!(f, "stop {index} (vertex {vertex}) is not a vertex of the surface")
            }
            CurveError::ZeroLength { vertex } => {
                write!(f, "every stop of the curve is vertex {vertex}: it would have length zero")
            }
            CurveError::NoPath { from, to } => write!(
                f,
                "no path on the surface joins vertex {from} to vertex {to} without passing \
                 another node"
            ),
            CurveError::ThroughBlocked { from, to, vertex } => write!(
                f,
                "the shortest path from vertex {from} to vertex {to} runs through vertex \
                 {vertex}, which is another node; add a waypoint to lead the curve around it"
            ),
        }
    }
}

impl std::error::Error for CurveError {}


/// A pivot is rerouted only if the angle on its other side is below π by more than this.
/// Smaller deficits shorten the path by a relative amount of order deficit² (< 1e-18):
/// less than rounding, and chasing them would make the straight feature lines of CAD meshes
/// (both sides π up to rounding) zig-zag across their vertices.
const ANGLE_TOL: f64 = 1e-9;

/// Bound on the unfold–funnel–reroute rounds per leg. Every round shortens the path, and in
/// practice a handful suffice; the bound only guarantees termination.
pub const MAX_ROUNDS: usize = 1000;

/// Shortest path on the surface from `stops[0]` through the waypoints `stops[1..n-1]` in
/// order to `stops[n-1]`, all mesh vertices (layout-format.md, "edges"; method-notes §0).
///
/// Each leg between consecutive stops is traced on its own (see the module documentation);
/// consecutive equal stops are skipped. `blocked[v]` marks vertices (the other layout nodes)
/// that the curve may not run through; stops may be blocked. Entries missing from `blocked`
/// count as not blocked.
///
/// The result is locally shortest: it is the shortest path when the edge-graph path it starts
/// from winds around the surface's features the way the shortest path does, which holds
/// unless the surface offers several routes of nearly equal length.
///
/// # Errors
/// - [`CurveError::TooFewStops`], [`CurveError::NotOnSurface`], [`CurveError::ZeroLength`]
///   for bad stops,
/// - [`CurveError::NoPath`] when blocked vertices or separate components keep a leg's ends
///   apart,
/// - [`CurveError::ThroughBlocked`] when the shortest path touches a blocked vertex.
pub fn trace_curve(mesh: &Mesh, stops: &[u32], blocked: &[bool]) -> Result<Curve, CurveError> {
    if stops.len() < 2 {
        return Err(CurveError::TooFewStops { count: stops.len() });
    }
    for (index, &vertex) in stops.iter().enumerate() {
        if vertex as usize >= mesh.n_vertices() || mesh.is_isolated(vertex) {
            return Err(CurveError::NotOnSurface { index, vertex });
        }
    }
    let mut points = vec![CurvePoint::Vertex(stops[0])];
    for leg in stops.windows(2) {
        if leg[0] == leg[1] {
            continue;
        }
        let pts = geodesic_leg(mesh, leg[0], leg[1], blocked)?;
        for p in pts.into_iter().skip(1) {
            push_point(&mut points, p);
        }
    }
    if points.len() < 2 {
        return Err(CurveError::ZeroLength { vertex: stops[0] });
    }
    let length = points.windows(2).map(|w| norm(sub(position(mesh, &w[1]), position(mesh, &w[0])))).sum();
    Ok(Curve { points, length })
}

/// The point in space of a curve point.
///
/// Precondition: the vertex or edge exists in `mesh`.
pub fn position(mesh: &Mesh, p: &CurvePoint) -> [f64; 3] {
    match *p {
        CurvePoint::Vertex(v) => mesh.position(v),
        CurvePoint::Edge { edge, t } => {
            let h = 2 * edge;
            let a = mesh.position(mesh.from_vertex(h));
            let b = mesh.position(mesh.to_vertex(h));
            std::array::from_fn(|k| (1.0 - t) * a[k] + t * b[k])
        }
    }
}

/// A triangle that contains both points (on its boundary), or `None`. For two points on one
/// mesh edge either triangle of that edge may be returned.
pub fn common_face(mesh: &Mesh, p: &CurvePoint, q: &CurvePoint) -> Option<u32> {
    let fq = faces_of(mesh, q);
    faces_of(mesh, p).into_iter().find(|f| fq.contains(f))
}

/// The triangles a curve point lies in.
fn faces_of(mesh: &Mesh, p: &CurvePoint) -> Vec<u32> {
    match *p {
        CurvePoint::Vertex(v) => mesh.outgoing(v).map(|h| mesh.face(h)).filter(|&f| f != NONE).collect(),
        CurvePoint::Edge { edge, .. } => {
            [mesh.face(2 * edge), mesh.face(2 * edge + 1)].into_iter().filter(|&f| f != NONE).collect()
        }
    }
}

/// Appends `p` unless it repeats the last point.
fn push_point(points: &mut Vec<CurvePoint>, p: CurvePoint) {
    if points.last() != Some(&p) {
        points.push(p);
    }
}

// ---------------------------------------------------------------------------------------
// Step 1: the shortest path over the edge graph.

/// Heap entry ordered so that `BinaryHeap` pops the smallest key first.
#[derive(PartialEq)]
pub(crate) struct Entry(pub f64, pub u32);
impl Eq for Entry {}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then_with(|| other.1.cmp(&self.1))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The per-vertex state of [`edge_path`], kept between its calls: a placement runs it once
/// per leg (about 1,500 legs for an automatic layout on bunny_28k), and filling three arrays
/// of the mesh's size for each took longer than most searches. Entries a search touched are
/// set back when it ends.
struct SearchState {
    dist: Vec<f64>,
    via: Vec<u32>,
    done: Vec<bool>,
    touched: Vec<u32>,
}

thread_local! {
    static SEARCH: std::cell::RefCell<SearchState> =
        const { std::cell::RefCell::new(SearchState { dist: Vec::new(), via: Vec::new(), done: Vec::new(), touched: Vec::new() }) };
}

/// The halfedges of a shortest edge path from `s` to `t` that enters no blocked vertex
/// except `t`, or `None` if there is none. A* with the straight-line distance to `t`, which
/// never overestimates and is consistent, so each vertex is settled once.
fn edge_path(mesh: &Mesh, s: u32, t: u32, blocked: &[bool]) -> Option<Vec<u32>> {
    SEARCH.with(|state| {
        let state = &mut *state.borrow_mut();
        let nv = mesh.n_vertices();
        if state.dist.len() < nv {
            state.dist.resize(nv, f64::INFINITY);
            state.via.resize(nv, NONE);
            state.done.resize(nv, false);
        }
        let path = a_star(mesh, s, t, blocked, state);
        for &v in &state.touched {
            state.dist[v as usize] = f64::INFINITY;
            state.via[v as usize] = NONE;
            state.done[v as usize] = false;
        }
        state.touched.clear();
        path
    })
}

/// The search of [`edge_path`] on `state`, whose entries are unset on entry; records every
/// vertex it sets in `state.touched`.
fn a_star(mesh: &Mesh, s: u32, t: u32, blocked: &[bool], state: &mut SearchState) -> Option<Vec<u32>> {
    let target = mesh.position(t);
    let heuristic = |v: u32| norm(sub(mesh.position(v), target));
    let SearchState { dist, via, done, touched } = state;
    let mut heap = BinaryHeap::new();
    dist[s as usize] = 0.0;
    touched.push(s);
    heap.push(Entry(heuristic(s), s));
    while let Some(Entry(_, v)) = heap.pop() {
        if done[v as usize] {
            continue;
        }
        done[v as usize] = true;
        if v == t {
            let mut path = Vec::new();
            let mut x = t;
            while x != s {
                let h = via[x as usize];
                path.push(h);
                x = mesh.from_vertex(h);
            }
            path.reverse();
            return Some(path);
        }
        let pv = mesh.position(v);
        for h in mesh.outgoing(v) {
            let w = mesh.to_vertex(h);
            if done[w as usize] || (w != t && blocked.get(w as usize).copied().unwrap_or(false)) {
                continue;
            }
            let d = dist[v as usize] + norm(sub(mesh.position(w), pv));
            if d < dist[w as usize] {
                if dist[w as usize] == f64::INFINITY {
                    touched.push(w);
                }
                dist[w as usize] = d;
                via[w as usize] = h;
                heap.push(Entry(d + heuristic(w), w));
            }
        }
    }
    None
}

// ---------------------------------------------------------------------------------------
// Step 2: strips of triangles.

/// A strip: the triangle `first`, then one triangle per crossing, `face(twin(h))` for each
/// crossing halfedge `h` (which belongs to the triangle before).
#[derive(Debug, Clone, PartialEq)]
struct Strip {
    first: u32,
    crossings: Vec<u32>,
}

impl Strip {
    /// `faces()[i]` is `T_i`.
    fn faces(&self, mesh: &Mesh) -> Vec<u32> {
        std::iter::once(self.first).chain(self.crossings.iter().map(|&h| mesh.face(h ^ 1))).collect()
    }

    /// Removes immediate returns (`T → T' → T`), which only lengthen paths.
    fn remove_u_turns(&mut self) {
        let mut kept: Vec<u32> = Vec::with_capacity(self.crossings.len());
        for &h in &self.crossings {
            if kept.last() == Some(&(h ^ 1)) {
                kept.pop();
            } else {
                kept.push(h);
            }
        }
        self.crossings = kept;
    }
}

/// Rotation around a vertex. `Cw` steps cross the halfedge of the current triangle that
/// leaves the vertex (the order of [`Mesh::outgoing`]), `Ccw` the one that enters it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Turn {
    Cw,
    Ccw,
}

/// The halfedge of triangle `f` leaving `v`, or NONE.
fn leaving(mesh: &Mesh, f: u32, v: u32) -> u32 {
    let mut h = mesh.face_halfedge(f, 0);
    for _ in 0..3 {
        if mesh.from_vertex(h) == v {
            return h;
        }
        h = mesh.next(h);
    }
    NONE
}

/// Total angle around `v`: the sum of its corner angles.
fn angle_sum(mesh: &Mesh, v: u32) -> f64 {
    mesh.outgoing(v).filter(|&h| mesh.face(h) != NONE).map(|h| corner_angle(mesh, h)).sum()
}

/// Walks around `v` from triangle `from` to triangle `to` turning `turn`: the crossings and
/// the sum of the corner angles at `v` of the triangles visited (both ends included). `None`
/// if the walk meets the boundary or does not arrive within one turn.
fn walk_around(mesh: &Mesh, v: u32, from: u32, to: u32, turn: Turn) -> Option<(Vec<u32>, f64)> {
    let mut f = from;
    let mut crossings = Vec::new();
    let mut angle = 0.0;
    for _ in 0..=mesh.valence(v) {
        if f == NONE {
            return None;
        }
        let out = leaving(mesh, f, v);
        if out == NONE {
            return None;
        }
        angle += corner_angle(mesh, out);
        if f == to {
            return Some((crossings, angle));
        }
        let h = match turn {
            Turn::Cw => out,
            Turn::Ccw => mesh.prev(out),
        };
        crossings.push(h);
        f = mesh.face(h ^ 1);
    }
    None
}

/// The strip along an edge path of at least two edges: at each inner vertex of the path the
/// triangles on one side, the side with the smaller angle, where the path could be shortened.
fn initial_strip(mesh: &Mesh, path: &[u32]) -> Option<Strip> {
    let mut first = NONE;
    let mut crossings = Vec::new();
    let mut previous_left = true;
    for i in 1..path.len() {
        let (h_in, h_out) = (path[i - 1], path[i]);
        let v = mesh.to_vertex(h_in);
        // Left of the path: from face(h_in) clockwise to face(h_out); right: from the
        // twins' faces counter-clockwise.
        let left = walk_around(mesh, v, mesh.face(h_in), mesh.face(h_out), Turn::Cw);
        let right = walk_around(mesh, v, mesh.face(h_in ^ 1), mesh.face(h_out ^ 1), Turn::Ccw);
        let (is_left, fan) = match (left, right) {
            (Some(l), Some(r)) => {
                if l.1 <= r.1 {
                    (true, l.0)
                } else {
                    (false, r.0)
                }
            }
            (Some(l), None) => (true, l.0),
            (None, Some(r)) => (false, r.0),
            (None, None) => return None,
        };
        if i == 1 {
            first = if is_left { mesh.face(h_in) } else { mesh.face(h_in ^ 1) };
        } else if is_left != previous_left {
            // The previous fan ended in the triangle on its side of h_in: cross h_in.
            crossings.push(if previous_left { h_in } else { h_in ^ 1 });
        }
        crossings.extend(fan);
        previous_left = is_left;
    }
    let mut strip = Strip { first, crossings };
    strip.remove_u_turns();
    Some(strip)
}

// ---------------------------------------------------------------------------------------
// Step 3: unfolding and the funnel.

type P2 = Vec2;

/// A strip vertex as unfolded: the mesh vertex and its place in the plane. A mesh vertex the
/// strip passes twice gets two places; consecutive portals share their common vertex's
/// coordinates exactly, so equality identifies it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    v: u32,
    p: P2,
}

/// Portal ends as seen travelling along the strip.
#[derive(Debug, Clone, Copy)]
struct Portal {
    l: Node,
    r: Node,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
}

impl Portal {
    fn end(&self, side: Side) -> Node {
        match side {
            Side::Left => self.l,
            Side::Right => self.r,
        }
    }
    fn has(&self, n: &Node) -> bool {
        self.l == *n || self.r == *n
    }
}

/// The strip laid out in the plane, orientation kept (counter-clockwise triangles stay
/// counter-clockwise): portal 0 is `(s, s)`, portal `i` in `1..=n` the edge crossed by
/// `crossings[i-1]`, portal `n+1` is `(t, t)`. `None` if the strip is inconsistent (its
/// first triangle lacks `s`, its last lacks `t`, or a crossing leaves the wrong triangle).
fn unfold(mesh: &Mesh, strip: &Strip, s: u32, t: u32) -> Option<Vec<Portal>> {
    if strip.first == NONE {
        return None;
    }
    let h0 = mesh.face_halfedge(strip.first, 0);
    let (a, b, c) = (mesh.from_vertex(h0), mesh.to_vertex(h0), mesh.to_vertex(mesh.next(h0)));
    let (pa, pb, pc) = (mesh.position(a), mesh.position(b), mesh.position(c));
    let (ab, ac) = (sub(pb, pa), sub(pc, pa));
    let lab = norm(ab);
    let mut tri = [
        Node { v: a, p: [0.0, 0.0] },
        Node { v: b, p: [lab, 0.0] },
        Node { v: c, p: [dot(ac, ab) / lab, norm(cross(ac, ab)) / lab] },
    ];
    let find = |tri: &[Node; 3], v: u32| tri.iter().find(|n| n.v == v).copied();
    let mut portals = Vec::with_capacity(strip.crossings.len() + 2);
    let start = find(&tri, s)?;
    portals.push(Portal { l: start, r: start });
    let mut face = strip.first;
    for &h in &strip.crossings {
        if mesh.face(h) != face {
            return None;
        }
        let (p, q) = (find(&tri, mesh.from_vertex(h))?, find(&tri, mesh.to_vertex(h))?);
        // Leaving the triangle across p→q (the triangle on its left), q is on the left.
        portals.push(Portal { l: q, r: p });
        let back = h ^ 1;
        face = mesh.face(back);
        if face == NONE {
            return None;
        }
        // The next triangle is q → p → c counter-clockwise: c goes left of q→p, at the
        // distances the surface gives.
        let c = mesh.to_vertex(mesh.next(back));
        let (pq3, pp3) = (mesh.position(q.v), mesh.position(p.v));
        let e3 = sub(pp3, pq3);
        let w3 = sub(mesh.position(c), pq3);
        let le = norm(e3);
        let (x, y) = (dot(w3, e3) / le, norm(cross(w3, e3)) / le);
        let d = [p.p[0] - q.p[0], p.p[1] - q.p[1]];
        let ld = d[0].hypot(d[1]);
        let u = [d[0] / ld, d[1] / ld];
        let pc = [q.p[0] + x * u[0] - y * u[1], q.p[1] + x * u[1] + y * u[0]];
        tri = [q, p, Node { v: c, p: pc }];
    }
    let end = find(&tri, t)?;
    portals.push(Portal { l: end, r: end });
    Some(portals)
}

/// A corner of the taut path: a strip vertex with the run of consecutive portals that end at
/// it (`run.0 ..= run.1`, on `side`). For the start the run is `(0, b)`, for the end
/// `(a, n+1)`, covering the portals that touch them.
#[derive(Debug, Clone, Copy)]
struct Pivot {
    node: Node,
    side: Side,
    run: (usize, usize),
}

/// The shortest path through the portals (the "simple stupid funnel" of navigation meshes,
/// with the apex allowed to be an end of the following portals). Collinear corners count as
/// corners, so a path running straight through a vertex records it. `None` only if the
/// iteration bound is hit, which the strictly increasing restart index rules out.
fn funnel(portals: &[Portal]) -> Option<Vec<Pivot>> {
    let n = portals.len();
    let last = n - 1;
    let start = portals[0].l;
    // The end may be a corner of portals before the last: reaching it there ends the path.
    let end = portals[last].l;
    let mut pivots = vec![Pivot { node: start, side: Side::Left, run: (0, 0) }];
    let (mut apex, mut left, mut right) = (start, start, start);
    let (mut li, mut ri) = (0usize, 0usize);
    let mut i = 1;
    let mut steps = 0usize;
    let limit = n.saturating_mul(n).saturating_add(16);
    while i < n {
        steps += 1;
        if steps > limit {
            return None;
        }
        let Portal { l, r } = portals[i];
        // Right side of the funnel.
        if r == apex {
            (right, ri) = (apex, i);
        } else if right == apex || orient2(apex.p, right.p, r.p) >= 0.0 {
            if left == apex || orient2(apex.p, left.p, r.p) < 0.0 {
                (right, ri) = (r, i);
            } else {
                // r reaches over the left side: the path bends at `left`.
                if left == end {
                    break;
                }
                pivots.push(Pivot { node: left, side: Side::Left, run: (li, li) });
                apex = left;
                (right, ri) = (apex, li);
                i = li + 1;
                continue;
            }
        }
        // Left side.
        if l == apex {
            (left, li) = (apex, i);
        } else if left == apex || orient2(apex.p, left.p, l.p) <= 0.0 {
            if right == apex || orient2(apex.p, right.p, l.p) > 0.0 {
                (left, li) = (l, i);
            } else {
                if right == end {
                    break;
                }
                pivots.push(Pivot { node: right, side: Side::Right, run: (ri, ri) });
                apex = right;
                (left, li) = (apex, ri);
                i = ri + 1;
                continue;
            }
        }
        i += 1;
    }
    pivots.push(Pivot { node: end, side: Side::Left, run: (last, last) });
    // Runs: the consecutive portals that share each corner.
    let m = pivots.len();
    for (k, pv) in pivots.iter_mut().enumerate() {
        let (mut a, mut b) = pv.run;
        if k == 0 {
            while b + 1 < last && portals[b + 1].has(&pv.node) {
                b += 1;
            }
        } else if k == m - 1 {
            while a > 1 && portals[a - 1].has(&pv.node) {
                a -= 1;
            }
        } else {
            while a > 1 && portals[a - 1].end(pv.side) == pv.node {
                a -= 1;
            }
            while b + 1 < last && portals[b + 1].end(pv.side) == pv.node {
                b += 1;
            }
        }
        pv.run = (a, b);
    }
    Some(pivots)
}

fn path_length(pivots: &[Pivot]) -> f64 {
    pivots.windows(2).map(|w| dist2(w[0].node.p, w[1].node.p)).sum()
}

// ---------------------------------------------------------------------------------------
// Step 4: rerouting around pivots.

/// A pivot worth passing on its other side.
struct Reroute {
    run: (usize, usize),
    v: u32,
    side: Side,
    /// π minus the angle on the other side: how much shorter the path can get.
    deficit: f64,
}

/// The inner pivots whose other side measures less than π.
fn reroutes(mesh: &Mesh, portals: &[Portal], pivots: &[Pivot], s: u32, t: u32) -> Vec<Reroute> {
    let mut out = Vec::new();
    for k in 1..pivots.len().saturating_sub(1) {
        let pv = pivots[k];
        let v = pv.node.v;
        // Beyond a boundary vertex lies the hole: its other side cannot be taken.
        if v == s || v == t || mesh.is_boundary_vertex(v) {
            continue;
        }
        // The angle on the strip's side, from the incoming segment over the run's spokes to
        // the outgoing one; each step stays inside one strip triangle, so the steps add up.
        let o = pv.node.p;
        let dir = |p: P2| sub2(p, o);
        let mut previous = dir(pivots[k - 1].node.p);
        let mut beta = 0.0;
        for portal in &portals[pv.run.0..=pv.run.1] {
            let other = match pv.side {
                Side::Left => portal.r,
                Side::Right => portal.l,
            };
            let d = dir(other.p);
            beta += angle2(previous, d);
            previous = d;
        }
        beta += angle2(previous, dir(pivots[k + 1].node.p));
        let other_side = angle_sum(mesh, v) - beta;
        if other_side < PI - ANGLE_TOL {
            out.push(Reroute { run: pv.run, v, side: pv.side, deficit: PI - other_side });
        }
    }
    out
}

/// The strip with the triangles of each chosen pivot's run replaced by the triangles on the
/// other side of its vertex. Pivots whose triangles overlap a chosen one wait for a later
/// round (largest gain first). `None` if no reroute applies.
fn apply_reroutes(mesh: &Mesh, strip: &Strip, mut todo: Vec<Reroute>) -> Option<Strip> {
    let faces = strip.faces(mesh);
    todo.sort_by(|a, b| b.deficit.total_cmp(&a.deficit));
    // (a, b, new crossings): replaces crossings[a-1..b], i.e. the triangles T_a..T_{b-1}.
    let mut chosen: Vec<(usize, usize, Vec<u32>)> = Vec::new();
    for r in todo {
        let (a, b) = r.run;
        if a == 0 || b >= faces.len() {
            continue;
        }
        if chosen.iter().any(|&(ca, cb, _)| a - 1 < cb && ca - 1 < b) {
            continue;
        }
        // The run turned counter-clockwise around a vertex on its left (it crossed halfedges
        // entering the vertex), clockwise around one on its right; go the other way.
        let turn = match r.side {
            Side::Left => Turn::Cw,
            Side::Right => Turn::Ccw,
        };
        let (from, to) = (faces[a - 1], faces[b]);
        let steps =
            if from == to { Some(Vec::new()) } else { walk_around(mesh, r.v, from, to, turn).map(|w| w.0) };
        if let Some(steps) = steps {
            chosen.push((a, b, steps));
        }
    }
    if chosen.is_empty() {
        return None;
    }
    chosen.sort_by_key(|c| c.0);
    let mut crossings = Vec::with_capacity(strip.crossings.len() + 16);
    let mut at = 0;
    for (a, b, steps) in chosen {
        crossings.extend_from_slice(&strip.crossings[at..a - 1]);
        crossings.extend(steps);
        at = b;
    }
    crossings.extend_from_slice(&strip.crossings[at..]);
    let mut out = Strip { first: strip.first, crossings };
    out.remove_u_turns();
    Some(out)
}

// ---------------------------------------------------------------------------------------
// Putting a leg together.

/// The curve points of the taut path through an unfolded strip.
fn leg_points(mesh: &Mesh, strip: &Strip, portals: &[Portal], pivots: &[Pivot]) -> Vec<CurvePoint> {
    let inner = portals.len() - 2;
    let mut pts = vec![CurvePoint::Vertex(pivots[0].node.v)];
    let mut k = 0;
    for (i, portal) in portals.iter().enumerate().take(inner + 1).skip(1) {
        while k + 1 < pivots.len() && pivots[k + 1].run.0 <= i {
            k += 1;
            push_point(&mut pts, CurvePoint::Vertex(pivots[k].node.v));
        }
        if i <= pivots[k].run.1 || k + 1 >= pivots.len() {
            // The portal ends at the corner: the path touches it there.
            continue;
        }
        let (a, b) = (pivots[k].node.p, pivots[k + 1].node.p);
        let h = strip.crossings[i - 1];
        for p in crossing(mesh, h, portal, a, b) {
            push_point(&mut pts, p);
        }
    }
    for pv in &pivots[k + 1..] {
        push_point(&mut pts, CurvePoint::Vertex(pv.node.v));
    }
    pts
}

/// Where the segment a→b crosses the portal of crossing halfedge `h`: one point, or both
/// ends of the portal when the segment runs along it.
fn crossing(mesh: &Mesh, h: u32, portal: &Portal, a: P2, b: P2) -> Vec<CurvePoint> {
    let Portal { l, r } = *portal;
    // Signed distances (times |b - a|) of the portal's ends from the line through a, b:
    // l lies on the left, r on the right.
    let dl = orient2(a, b, l.p);
    let dr = orient2(a, b, r.p);
    let tol = SNAP * dist2(l.p, r.p) * dist2(a, b);
    let near_l = dl.abs() <= tol;
    let near_r = dr.abs() <= tol;
    let along = |p: P2| (p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]);
    match (near_l, near_r) {
        (true, true) => {
            let (first, second) = if along(l.p) <= along(r.p) { (l, r) } else { (r, l) };
            vec![CurvePoint::Vertex(first.v), CurvePoint::Vertex(second.v)]
        }
        (true, false) => vec![CurvePoint::Vertex(l.v)],
        (false, true) => vec![CurvePoint::Vertex(r.v)],
        (false, false) => {
            let den = dl - dr;
            if den.is_nan() || den <= 0.0 || dl < 0.0 || dr > 0.0 {
                // The segment misses the portal (only by rounding): take the nearer end.
                return vec![CurvePoint::Vertex(if dl.abs() <= dr.abs() { l.v } else { r.v })];
            }
            let u = (dl / den).clamp(0.0, 1.0); // from l towards r
            let e = mesh.edge(h);
            let from = mesh.from_vertex(2 * e);
            let t = if from == l.v { u } else { 1.0 - u };
            if t < SNAP {
                vec![CurvePoint::Vertex(from)]
            } else if t > 1.0 - SNAP {
                vec![CurvePoint::Vertex(mesh.to_vertex(2 * e))]
            } else {
                vec![CurvePoint::Edge { edge: e, t }]
            }
        }
    }
}

/// True if consecutive points share a triangle (or an edge) and no point repeats.
fn well_formed(mesh: &Mesh, pts: &[CurvePoint]) -> bool {
    pts.windows(2).all(|w| w[0] != w[1] && common_face(mesh, &w[0], &w[1]).is_some())
}

/// The geodesic from `s` to `t` (s ≠ t), as curve points from `Vertex(s)` to `Vertex(t)`.
fn geodesic_leg(mesh: &Mesh, s: u32, t: u32, blocked: &[bool]) -> Result<Vec<CurvePoint>, CurveError> {
    let path = edge_path(mesh, s, t, blocked).ok_or(CurveError::NoPath { from: s, to: t })?;
    let edge_points: Vec<CurvePoint> = std::iter::once(CurvePoint::Vertex(s))
        .chain(path.iter().map(|&h| CurvePoint::Vertex(mesh.to_vertex(h))))
        .collect();
    if path.len() == 1 {
        // A mesh edge is the straight segment between its ends: nothing is shorter.
        return Ok(edge_points);
    }
    let Some(mut strip) = initial_strip(mesh, &path) else {
        debug_assert!(false, "no strip along the edge path from {s} to {t}");
        return Ok(edge_points);
    };
    let is_blocked = |v: u32| blocked.get(v as usize).copied().unwrap_or(false);
    // Strips only grow by a fan per reroute; this bound just caps memory on pathological input.
    let max_crossings = 4 * mesh.n_faces() + 64;
    let mut best: Option<(Strip, Vec<Portal>, Vec<Pivot>, f64)> = None;
    for _ in 0..MAX_ROUNDS {
        let Some(portals) = unfold(mesh, &strip, s, t) else { break };
        let Some(pivots) = funnel(&portals) else { break };
        let length = path_length(&pivots);
        if let Some(b) = &best {
            // Each reroute shortens the path; a round that does not (rounding) ends the loop.
            if length.is_nan() || length >= b.3 {
                break;
            }
        }
        let todo = reroutes(mesh, &portals, &pivots, s, t);
        let next = if todo.is_empty() { None } else { apply_reroutes(mesh, &strip, todo) };
        best = Some((strip, portals, pivots, length));
        match next {
            Some(n) if n.crossings.len() <= max_crossings => strip = n,
            _ => break,
        }
    }
    let Some((strip, portals, pivots, _)) = best else {
        debug_assert!(false, "the strip from {s} to {t} does not unfold");
        return Ok(edge_points);
    };
    for pv in &pivots[1..pivots.len() - 1] {
        if pv.node.v != s && pv.node.v != t && is_blocked(pv.node.v) {
            return Err(CurveError::ThroughBlocked { from: s, to: t, vertex: pv.node.v });
        }
    }
    let pts = leg_points(mesh, &strip, &portals, &pivots);
    if !well_formed(mesh, &pts)
        || pts.first() != Some(&CurvePoint::Vertex(s))
        || pts.last() != Some(&CurvePoint::Vertex(t))
    {
        debug_assert!(false, "malformed geodesic from {s} to {t}: {pts:?}");
        return Ok(edge_points);
    }
    for p in &pts[1..pts.len() - 1] {
        if let CurvePoint::Vertex(v) = *p {
            if v != s && v != t && is_blocked(v) {
                return Err(CurveError::ThroughBlocked { from: s, to: t, vertex: v });
            }
        }
    }
    Ok(pts)
}

// ---------------------------------------------------------------------------------------
// Meeting curves.

/// Tolerance on edge parameters and triangle perimeter positions when comparing points of
/// two curves: the crossings' own.
const MEET_TOL: f64 = SNAP;

/// Where two curves meet away from the vertices they may share (`shared`, typically the
/// layout nodes both curves end at): `None` if they don't (method-notes §0: curves may meet
/// only at nodes; layout-format.md, "edges").
///
/// Touching counts: a vertex both run through, a point where both cross the same edge,
/// segments crossing or touching inside a triangle, a stretch both run along a mesh edge,
/// or one crossing an edge the other runs along. Leaving a shared vertex along the same
/// direction (so that the curves overlap) counts too.
///
/// Precondition: both curves are well formed (as [`trace_curve`] returns them).
pub fn meeting_point(mesh: &Mesh, a: &Curve, b: &Curve, shared: &[u32]) -> Option<[f64; 3]> {
    meeting_point_of(mesh, a, &Prepared::new(mesh, a), &Prepared::new(mesh, b), shared)
}

/// [`meeting_point`] of `a` and the curve `pb` was made from, `pa` made from `a`: a layout
/// tests each curve against many, and makes each [`Prepared`] once.
pub fn meeting_point_of(mesh: &Mesh, a: &Curve, pa: &Prepared, pb: &Prepared, shared: &[u32]) -> Option<[f64; 3]> {
    // A vertex both run through or end at.
    for p in &a.points {
        if let CurvePoint::Vertex(v) = *p {
            if pb.vertices.contains(&v) && !shared.contains(&v) {
                return Some(mesh.position(v));
            }
        }
    }
    // The same crossing of an edge.
    for p in &a.points {
        if let CurvePoint::Edge { edge, t } = *p {
            if let Some(us) = pb.edge_points.get(&edge) {
                if us.iter().any(|&u| (u - t).abs() <= MEET_TOL) {
                    return Some(position(mesh, p));
                }
            }
        }
    }
    // Stretches along edges.
    if let Some(p) = along_edges(mesh, pa, pb).or_else(|| along_edges(mesh, pb, pa)) {
        return Some(p);
    }
    // Segments inside triangles.
    for (f, ca) in &pa.chords {
        for &k in pb.chords_in.get(f).map(Vec::as_slice).unwrap_or(&[]) {
            if let Some(p) = chords_meet(mesh, *f, ca, &pb.chords[k].1, shared) {
                return Some(p);
            }
        }
    }
    None
}

/// A curve sorted for meeting tests ([`meeting_point_of`]). Lists keep the curve's order, so
/// that the meeting point reported is the same from run to run.
pub struct Prepared {
    vertices: HashSet<u32>,
    /// Edge → parameters of the crossings on it.
    edge_points: HashMap<u32, Vec<f64>>,
    /// Stretches along mesh edges: (edge, lowest, highest parameter).
    intervals: Vec<(u32, f64, f64)>,
    /// Segments crossing a triangle's interior, with the triangle.
    chords: Vec<(u32, (CurvePoint, CurvePoint))>,
    /// Triangle → indices into `chords`.
    chords_in: HashMap<u32, Vec<usize>>,
}

/// The parameter along halfedge `2e` of a point on edge `e`, if it is on it.
fn param_on_edge(mesh: &Mesh, p: &CurvePoint, e: u32) -> Option<f64> {
    match *p {
        CurvePoint::Vertex(v) if v == mesh.from_vertex(2 * e) => Some(0.0),
        CurvePoint::Vertex(v) if v == mesh.to_vertex(2 * e) => Some(1.0),
        CurvePoint::Edge { edge, t } if edge == e => Some(t),
        _ => None,
    }
}

impl Prepared {
    /// The meeting-test view of `c`.
    pub fn new(mesh: &Mesh, c: &Curve) -> Prepared {
        let mut out = Prepared {
            vertices: HashSet::new(),
            edge_points: HashMap::new(),
            intervals: Vec::new(),
            chords: Vec::new(),
            chords_in: HashMap::new(),
        };
        for p in &c.points {
            match *p {
                CurvePoint::Vertex(v) => {
                    out.vertices.insert(v);
                }
                CurvePoint::Edge { edge, t } => out.edge_points.entry(edge).or_default().push(t),
            }
        }
        for w in c.points.windows(2) {
            let (p, q) = (w[0], w[1]);
            // The one edge both could lie on: an Edge point's, or the edge joining two vertices.
            let edge = match (p, q) {
                (CurvePoint::Edge { edge, .. }, _)
                | (CurvePoint::Vertex(_), CurvePoint::Edge { edge, .. }) => Some(edge),
                (CurvePoint::Vertex(x), CurvePoint::Vertex(y)) => {
                    mesh.find_halfedge(x, y).map(|h| mesh.edge(h))
                }
            };
            if let Some(e) = edge {
                if let (Some(s), Some(t)) = (param_on_edge(mesh, &p, e), param_on_edge(mesh, &q, e)) {
                    out.intervals.push((e, s.min(t), s.max(t)));
                    continue;
                }
            }
            if let Some(f) = common_face(mesh, &p, &q) {
                out.chords_in.entry(f).or_default().push(out.chords.len());
                out.chords.push((f, (p, q)));
            }
        }
        out
    }
}

/// A point where `a` runs along an edge that `b` crosses or also runs along.
fn along_edges(mesh: &Mesh, a: &Prepared, b: &Prepared) -> Option<[f64; 3]> {
    for &(e, lo, hi) in &a.intervals {
        if let Some(ts) = b.edge_points.get(&e) {
            if let Some(&t) = ts.iter().find(|&&t| t >= lo - MEET_TOL && t <= hi + MEET_TOL) {
                return Some(position(mesh, &CurvePoint::Edge { edge: e, t }));
            }
        }
        for &(e2, lo2, hi2) in &b.intervals {
            let (x, y) = (lo.max(lo2), hi.min(hi2));
            if e2 == e && y - x > MEET_TOL {
                return Some(position(mesh, &CurvePoint::Edge { edge: e, t: 0.5 * (x + y) }));
            }
        }
    }
    None
}

/// Position of a point on the boundary of triangle `f`, as `k + u` on the side from corner
/// `k` to corner `k + 1` (corners in the order of `triangles()[f]`).
fn perimeter(mesh: &Mesh, f: u32, p: &CurvePoint) -> Option<f64> {
    let c = mesh.triangles()[f as usize];
    match *p {
        CurvePoint::Vertex(v) => c.iter().position(|&x| x == v).map(|k| k as f64),
        CurvePoint::Edge { edge, t } => {
            let (x, y) = (mesh.from_vertex(2 * edge), mesh.to_vertex(2 * edge));
            (0..3).find_map(|k| {
                let (ck, cn) = (c[k], c[(k + 1) % 3]);
                if ck == x && cn == y {
                    Some(k as f64 + t)
                } else if ck == y && cn == x {
                    Some(k as f64 + 1.0 - t)
                } else {
                    None
                }
            })
        }
    }
}

/// Do two segments inside triangle `f` meet away from a shared vertex? Both have their ends
/// on the triangle's boundary, so they cross exactly when their ends interleave around it.
fn chords_meet(
    mesh: &Mesh,
    f: u32,
    a: &(CurvePoint, CurvePoint),
    b: &(CurvePoint, CurvePoint),
    shared: &[u32],
) -> Option<[f64; 3]> {
    let per = |p: &CurvePoint| perimeter(mesh, f, p);
    let (a0, a1, b0, b1) = (per(&a.0)?, per(&a.1)?, per(&b.0)?, per(&b.1)?);
    let same = |x: f64, y: f64| {
        let d = (x - y).abs();
        d.min(3.0 - d) <= MEET_TOL
    };
    let is_shared = |p: &CurvePoint| matches!(p, CurvePoint::Vertex(v) if shared.contains(v));
    let pairs = [
        (a0, &a.0, b0, a1, b1, &a.1),
        (a0, &a.0, b1, a1, b0, &a.1),
        (a1, &a.1, b0, a0, b1, &a.0),
        (a1, &a.1, b1, a0, b0, &a.0),
    ];
    for (x, px, y, x_other, y_other, p_other) in pairs {
        if same(x, y) {
            if !is_shared(px) {
                return Some(position(mesh, px));
            }
            // Both leave a shared vertex: they overlap only if they go the same way.
            if same(x_other, y_other) {
                let (p, q) = (position(mesh, px), position(mesh, p_other));
                return Some(std::array::from_fn(|k| 0.5 * (p[k] + q[k])));
            }
            return None;
        }
    }
    let inside = |z: f64| (z - a0).rem_euclid(3.0) < (a1 - a0).rem_euclid(3.0);
    if inside(b0) == inside(b1) {
        return None;
    }
    // Segment intersection in the reference triangle (0,0), (1,0), (0,1): the parameters
    // along each segment are affine invariants, so they hold on the surface triangle too.
    let corner = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let flat = |z: f64| -> P2 {
        let k = (z.floor() as usize).min(2);
        let u = z - k as f64;
        let (p, q) = (corner[k], corner[(k + 1) % 3]);
        [p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1])]
    };
    let (p, q, r, s) = (flat(a0), flat(a1), flat(b0), flat(b1));
    let d1 = orient2(r, s, p);
    let d2 = orient2(r, s, q);
    let lambda = if d1 != d2 { (d1 / (d1 - d2)).clamp(0.0, 1.0) } else { 0.5 };
    let (x, y) = (position(mesh, &a.0), position(mesh, &a.1));
    Some(std::array::from_fn(|k| x[k] + lambda * (y[k] - x[k])))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::{build_mesh, TriangleSoup};

    /// A small deterministic generator (tests must not depend on a random source).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// An n×n grid of unit squares in the plane z = 0, diagonals alternating; interior
    /// vertices moved by up to `jitter` in x and y.
    fn grid(n: u32, jitter: f64) -> Mesh {
        let mut rng = Lcg(7);
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let inner = i > 0 && j > 0 && i < n && j < n;
                let (dx, dy) = if inner {
                    (jitter * (2.0 * rng.next() - 1.0), jitter * (2.0 * rng.next() - 1.0))
                } else {
                    (0.0, 0.0)
                };
                positions.push([i as f64 + dx, j as f64 + dy, 0.0]);
            }
        }
        let triangles = crate::mesh::primitives::grid_triangles(n);
        build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).unwrap().mesh
    }

    fn gid(n: u32, i: u32, j: u32) -> u32 {
        j * (n + 1) + i
    }

    /// The surface of the unit cube, each face an n×n grid, outward facing; the vertex of
    /// lattice point (i, j, k) in 0..=n is `ids[&[i, j, k]]`.
    fn cube(n: u32) -> (Mesh, HashMap<[u32; 3], u32>) {
        crate::mesh::primitives::parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], n)
    }

    /// A mesh of `../shared/meshes`.
    pub(crate) fn load(name: &str) -> Mesh {
        let path = format!("{}/../shared/meshes/{name}", env!("CARGO_MANIFEST_DIR"));
        let bytes = std::fs::read(&path).unwrap();
        crate::io::read_mesh(&bytes, &path).unwrap().mesh
    }

    fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
        norm(sub(a, b))
    }

    /// Structural invariants of a traced curve.
    fn assert_well_formed(mesh: &Mesh, c: &Curve, stops: &[u32]) {
        assert_eq!(c.points.first(), Some(&CurvePoint::Vertex(stops[0])));
        assert_eq!(c.points.last(), Some(&CurvePoint::Vertex(*stops.last().unwrap())));
        for w in c.points.windows(2) {
            assert_ne!(w[0], w[1]);
            assert!(common_face(mesh, &w[0], &w[1]).is_some(), "{:?} and {:?} share no triangle", w[0], w[1]);
        }
        for p in &c.points {
            if let CurvePoint::Edge { t, .. } = p {
                assert!(*t >= SNAP && *t <= 1.0 - SNAP, "unsnapped t = {t}");
            }
        }
        for s in stops {
            assert!(c.points.contains(&CurvePoint::Vertex(*s)));
        }
        let len: f64 = c.points.windows(2).map(|w| dist(position(mesh, &w[0]), position(mesh, &w[1]))).sum();
        assert!((len - c.length).abs() <= 1e-12 * len.max(1.0));
    }

    /// Angular coordinate around `v` of the direction towards point `p` (which lies in a
    /// triangle at `v`), measured clockwise along `outgoing(v)` from its first halfedge.
    fn angular(mesh: &Mesh, v: u32, p: [f64; 3]) -> Option<f64> {
        let o = mesh.position(v);
        let mut acc = 0.0;
        let out: Vec<u32> = mesh.outgoing(v).collect();
        for (j, &h) in out.iter().enumerate() {
            let f = mesh.face(h);
            if f != NONE && j > 0 {
                acc += corner_angle(mesh, h);
            }
            // Direction along halfedge h itself.
            let d = sub(mesh.position(mesh.to_vertex(h)), o);
            let w = sub(p, o);
            if norm(cross(d, w)) <= 1e-12 * norm(d) * norm(w) && dot(d, w) > 0.0 {
                return Some(acc);
            }
            // Inside the triangle clockwise after h: face(twin(h)), between h and the next.
            let g = mesh.face(h ^ 1);
            if g != NONE {
                let next = mesh.to_vertex(mesh.next(h ^ 1));
                let e = sub(mesh.position(next), o);
                let full = norm(cross(d, e)).atan2(dot(d, e));
                let part = norm(cross(d, w)).atan2(dot(d, w));
                let rest = norm(cross(w, e)).atan2(dot(w, e));
                if (part + rest - full).abs() < 1e-9 {
                    return Some(acc + part);
                }
            }
        }
        None
    }

    /// The curve is a geodesic of the polyhedral surface: straight when unfolded across each
    /// crossed edge, and at least π on both sides of every inner vertex it runs through.
    fn assert_locally_straight(mesh: &Mesh, c: &Curve, tol: f64) {
        let pts = &c.points;
        for k in 1..pts.len() - 1 {
            let (p, x, q) =
                (position(mesh, &pts[k - 1]), position(mesh, &pts[k]), position(mesh, &pts[k + 1]));
            match pts[k] {
                CurvePoint::Edge { edge, .. } => {
                    let u = sub(
                        mesh.position(mesh.to_vertex(2 * edge)),
                        mesh.position(mesh.from_vertex(2 * edge)),
                    );
                    let ang = |w: [f64; 3]| norm(cross(u, w)).atan2(dot(u, w));
                    let sum = ang(sub(p, x)) + ang(sub(q, x));
                    assert!((sum - PI).abs() < tol, "bent by {} at crossing {k}", sum - PI);
                }
                CurvePoint::Vertex(v) => {
                    if mesh.is_boundary_vertex(v) {
                        continue;
                    }
                    let total = angle_sum(mesh, v);
                    let (a, b) = (angular(mesh, v, p).unwrap(), angular(mesh, v, q).unwrap());
                    let one = (a - b).abs();
                    assert!(
                        one >= PI - tol && total - one >= PI - tol,
                        "sides {one} and {} at vertex {v}",
                        total - one
                    );
                }
            }
        }
    }

    /// Distance of point x from the segment a–b.
    fn off_segment(a: [f64; 3], b: [f64; 3], x: [f64; 3]) -> f64 {
        let d = sub(b, a);
        let s = (dot(sub(x, a), d) / dot(d, d)).clamp(0.0, 1.0);
        dist(x, std::array::from_fn(|k| a[k] + s * d[k]))
    }

    fn edge_path_length(mesh: &Mesh, s: u32, t: u32) -> f64 {
        let path = edge_path(mesh, s, t, &[]).unwrap();
        path.iter().map(|&h| dist(mesh.position(mesh.from_vertex(h)), mesh.position(mesh.to_vertex(h)))).sum()
    }

    #[test]
    fn straight_line_on_a_plane_grid() {
        let n = 20;
        for jitter in [0.0, 0.3] {
            let m = grid(n, jitter);
            for (s, t) in [((1, 2), (19, 15)), ((18, 1), (2, 17)), ((0, 0), (20, 7)), ((3, 19), (17, 0))] {
                let (s, t) = (gid(n, s.0, s.1), gid(n, t.0, t.1));
                let c = trace_curve(&m, &[s, t], &[]).unwrap();
                assert_well_formed(&m, &c, &[s, t]);
                let (a, b) = (m.position(s), m.position(t));
                for p in &c.points {
                    let off = off_segment(a, b, position(&m, p));
                    assert!(off < 1e-9, "jitter {jitter}: {p:?} is {off} off the segment");
                }
                assert!((c.length - dist(a, b)).abs() < 1e-9, "{} vs {}", c.length, dist(a, b));
                // The edge path it started from is longer: the test compares real geodesics.
                assert!(edge_path_length(&m, s, t) > c.length + 0.1);
            }
        }
    }

    #[test]
    fn a_waypoint_makes_two_straight_segments() {
        let n = 20;
        let m = grid(n, 0.3);
        let (s, w, t) = (gid(n, 2, 3), gid(n, 15, 4), gid(n, 11, 18));
        let c = trace_curve(&m, &[s, w, t], &[]).unwrap();
        assert_well_formed(&m, &c, &[s, w, t]);
        let (ps, pw, pt) = (m.position(s), m.position(w), m.position(t));
        let k = c.points.iter().position(|p| *p == CurvePoint::Vertex(w)).unwrap();
        for p in &c.points[..=k] {
            assert!(off_segment(ps, pw, position(&m, p)) < 1e-9);
        }
        for p in &c.points[k..] {
            assert!(off_segment(pw, pt, position(&m, p)) < 1e-9);
        }
        assert!((c.length - dist(ps, pw) - dist(pw, pt)).abs() < 1e-9);
    }

    #[test]
    fn a_path_through_a_vertex_records_it() {
        let n = 20;
        let m = grid(n, 0.0);
        // The line from (2,2) to (18,10) passes the grid vertices (4,3), (6,4), ...
        let c = trace_curve(&m, &[gid(n, 2, 2), gid(n, 18, 10)], &[]).unwrap();
        assert_well_formed(&m, &c, &[gid(n, 2, 2), gid(n, 18, 10)]);
        for k in 1..8 {
            assert!(
                c.points.contains(&CurvePoint::Vertex(gid(n, 2 + 2 * k, 2 + k))),
                "misses ({}, {})",
                2 + 2 * k,
                2 + k
            );
        }
        assert!((c.length - 320f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn the_strip_widens_across_a_wall_of_blocked_vertices() {
        // Blocked vertices x = 10, y = 0..=17 force the edge path over the top of the wall;
        // the geodesic passes between two of them, far outside the first strip.
        let n = 20;
        let m = grid(n, 0.0);
        let mut blocked = vec![false; m.n_vertices()];
        for j in 0..=17 {
            blocked[gid(n, 10, j) as usize] = true;
        }
        let (s, t) = (gid(n, 2, 3), gid(n, 18, 12));
        let c = trace_curve(&m, &[s, t], &blocked).unwrap();
        assert_well_formed(&m, &c, &[s, t]);
        let (a, b) = (m.position(s), m.position(t));
        assert!((c.length - dist(a, b)).abs() < 1e-9, "{} vs {}", c.length, dist(a, b));
        for p in &c.points {
            assert!(off_segment(a, b, position(&m, p)) < 1e-9);
            if let CurvePoint::Vertex(v) = p {
                assert!(!blocked[*v as usize] || *v == s || *v == t);
            }
        }
        // The edge path went over the top of the wall.
        let path = edge_path(&m, s, t, &blocked).unwrap();
        assert!(path.iter().any(|&h| m.position(m.to_vertex(h))[1] >= 18.0));
    }

    #[test]
    fn blocked_vertices_are_never_run_through() {
        let n = 20;
        let m = grid(n, 0.0);
        let (s, t) = (gid(n, 2, 2), gid(n, 18, 10));
        // On the straight line: no shortest path avoids it.
        let mut blocked = vec![false; m.n_vertices()];
        blocked[gid(n, 10, 6) as usize] = true;
        blocked[s as usize] = true;
        blocked[t as usize] = true;
        assert_eq!(
            trace_curve(&m, &[s, t], &blocked),
            Err(CurveError::ThroughBlocked { from: s, to: t, vertex: gid(n, 10, 6) })
        );
        // Off the line but on the edge path: avoided without detour.
        let (s, t) = (gid(n, 1, 2), gid(n, 19, 15));
        let path = edge_path(&m, s, t, &[]).unwrap();
        let mut blocked = vec![false; m.n_vertices()];
        for &h in &path[2..path.len() - 2] {
            blocked[m.to_vertex(h) as usize] = true;
        }
        let c = trace_curve(&m, &[s, t], &blocked).unwrap();
        assert!((c.length - dist(m.position(s), m.position(t))).abs() < 1e-9);
        // Walled in: no path at all.
        let mut blocked = vec![false; m.n_vertices()];
        for v in m.neighbors(s) {
            blocked[v as usize] = true;
        }
        assert_eq!(trace_curve(&m, &[s, t], &blocked), Err(CurveError::NoPath { from: s, to: t }));
        // On a curved mesh, every vertex of the result is free.
        let m = load("bunny_1k8.obj");
        let mut rng = Lcg(3);
        let nv = m.n_vertices();
        let mut blocked = vec![false; nv];
        for _ in 0..200 {
            blocked[(rng.next() * nv as f64) as usize % nv] = true;
        }
        let mut traced = 0;
        for _ in 0..30 {
            let s = (rng.next() * nv as f64) as u32 % nv as u32;
            let t = (rng.next() * nv as f64) as u32 % nv as u32;
            if s == t {
                continue;
            }
            match trace_curve(&m, &[s, t], &blocked) {
                Ok(c) => {
                    traced += 1;
                    assert_well_formed(&m, &c, &[s, t]);
                    for p in &c.points[1..c.points.len() - 1] {
                        if let CurvePoint::Vertex(v) = p {
                            assert!(!blocked[*v as usize]);
                        }
                    }
                }
                Err(CurveError::ThroughBlocked { vertex, .. }) => assert!(blocked[vertex as usize]),
                Err(e) => panic!("{e}"),
            }
        }
        assert!(traced >= 20);
    }

    #[test]
    fn bounds_and_straightness_on_a_curved_mesh() {
        let m = load("bunny_1k8.obj");
        let nv = m.n_vertices() as u32;
        let mut rng = Lcg(11);
        let mut shorter = 0;
        for _ in 0..60 {
            let s = (rng.next() * nv as f64) as u32 % nv;
            let t = (rng.next() * nv as f64) as u32 % nv;
            if s == t {
                continue;
            }
            let c = trace_curve(&m, &[s, t], &[]).unwrap();
            assert_well_formed(&m, &c, &[s, t]);
            let euclid = dist(m.position(s), m.position(t));
            let graph = edge_path_length(&m, s, t);
            assert!(c.length >= euclid - 1e-12, "{} < straight {euclid}", c.length);
            assert!(c.length <= graph + 1e-12, "{} > edge path {graph}", c.length);
            if c.length < graph * 0.99 {
                shorter += 1;
            }
            assert_locally_straight(&m, &c, 1e-6);
        }
        assert!(shorter > 30, "only {shorter} curves beat the edge path by 1%");
    }

    #[test]
    fn across_a_cube_edge_the_curve_is_the_unfolded_line() {
        let n = 6;
        let (m, ids) = cube(n);
        // A = (1/6, 4/6, 1) on top, B = (5/6, 0, 2/6) on the front (y = 0). Unfolded about
        // the edge y = 0, z = 1, B lands at (5/6, -4/6) in the top's (x, y).
        let (s, t) = (ids[&[1, 4, 6]], ids[&[5, 0, 2]]);
        let c = trace_curve(&m, &[s, t], &[]).unwrap();
        assert_well_formed(&m, &c, &[s, t]);
        assert!((c.length - 80f64.sqrt() / 6.0).abs() < 1e-9, "{}", c.length);
        let (a, b) = ([1.0 / 6.0, 4.0 / 6.0], [5.0 / 6.0, -4.0 / 6.0]);
        for p in &c.points {
            let x = position(&m, p);
            let flat = if (x[2] - 1.0).abs() < 1e-12 { [x[0], x[1]] } else { [x[0], x[2] - 1.0] };
            assert!(orient2(a, b, flat).abs() / dist2(a, b) < 1e-9, "{x:?} off the line");
        }
        // Across the cube's corner region the same holds in the other direction.
        let c2 = trace_curve(&m, &[t, s], &[]).unwrap();
        assert!((c2.length - c.length).abs() < 1e-12);
    }

    #[test]
    fn meeting_points() {
        let n = 20;
        let m = grid(n, 0.3);
        let p = |i, j| m.position(gid(n, i, j));
        let curve = |a: (u32, u32), b: (u32, u32)| {
            trace_curve(&m, &[gid(n, a.0, a.1), gid(n, b.0, b.1)], &[]).unwrap()
        };
        // Two crossing lines meet where the lines intersect.
        let a = curve((2, 2), (18, 16));
        let b = curve((2, 16), (18, 3));
        let x = meeting_point(&m, &a, &b, &[]).unwrap();
        let (p0, p1, q0, q1) = (p(2, 2), p(18, 16), p(2, 16), p(18, 3));
        let (d, e) = ([p1[0] - p0[0], p1[1] - p0[1]], [q1[0] - q0[0], q1[1] - q0[1]]);
        let s = ((q0[0] - p0[0]) * e[1] - (q0[1] - p0[1]) * e[0]) / (d[0] * e[1] - d[1] * e[0]);
        let expect = [p0[0] + s * d[0], p0[1] + s * d[1], 0.0];
        assert!(dist(x, expect) < 1e-9, "{x:?} vs {expect:?}");
        assert!(meeting_point(&m, &b, &a, &[]).is_some());
        // Sharing only an end node.
        let c = curve((2, 2), (18, 5));
        assert_eq!(meeting_point(&m, &a, &c, &[gid(n, 2, 2)]), None);
        assert_eq!(meeting_point(&m, &c, &a, &[gid(n, 2, 2)]), None);
        assert!(meeting_point(&m, &a, &c, &[]).is_some());
        // Disjoint curves.
        let f = curve((2, 18), (19, 19));
        assert_eq!(meeting_point(&m, &a, &f, &[]), None);
        // An end node of one lying on the other.
        let g = curve((10, 0), (10, 20));
        let h = curve((0, 10), (10, 20));
        assert!(meeting_point(&m, &g, &h, &[]).is_some());

        // On the unjittered grid the diagonal runs through vertices.
        let m = grid(n, 0.0);
        let curve = |a: (u32, u32), b: (u32, u32)| {
            trace_curve(&m, &[gid(n, a.0, a.1), gid(n, b.0, b.1)], &[]).unwrap()
        };
        let a = curve((0, 0), (10, 10));
        let b = curve((0, 10), (10, 0));
        let x = meeting_point(&m, &a, &b, &[]).unwrap();
        assert!(dist(x, [5.0, 5.0, 0.0]) < 1e-12, "{x:?}");
        // Overlapping along a line through vertices and along edges, sharing one end.
        let c = curve((0, 0), (6, 6));
        assert!(meeting_point(&m, &a, &c, &[gid(n, 0, 0)]).is_some());
        let d = curve((3, 0), (9, 0));
        let e = curve((0, 0), (12, 0));
        assert!(meeting_point(&m, &d, &e, &[]).is_some());
        // Two curves between the same two adjacent nodes overlap entirely.
        let f = curve((4, 4), (5, 4));
        assert!(meeting_point(&m, &f, &f, &[gid(n, 4, 4), gid(n, 5, 4)]).is_some());
        // Curves meeting at a shared node from opposite sides.
        let g = curve((0, 0), (8, 3));
        let h = curve((8, 3), (20, 9));
        assert_eq!(meeting_point(&m, &g, &h, &[gid(n, 8, 3)]), None);
    }

    #[test]
    fn curves_follow_straight_feature_lines_of_fandisk() {
        let m = load("fandisk.obj");
        // Sharp edges: the normals of their two triangles differ by more than 30 degrees.
        let normal = |f: u32| {
            let [a, b, c] = m.triangles()[f as usize].map(|v| m.position(v));
            let n = cross(sub(b, a), sub(c, a));
            let l = norm(n);
            n.map(|x| x / l)
        };
        let sharp = |e: u32| {
            let (f, g) = (m.face(2 * e), m.face(2 * e + 1));
            f != NONE && g != NONE && dot(normal(f), normal(g)) < (30f64).to_radians().cos()
        };
        let mut feature_at: Vec<Vec<u32>> = vec![Vec::new(); m.n_vertices()];
        for e in 0..m.n_edges() as u32 {
            if sharp(e) {
                feature_at[m.from_vertex(2 * e) as usize].push(2 * e);
                feature_at[m.to_vertex(2 * e) as usize].push(2 * e + 1);
            }
        }
        // Longest chain of sharp edges running straight on in space through vertices that
        // have exactly two of them.
        let straight = |h: u32, g: u32| {
            let (u, w) = (
                sub(m.position(m.to_vertex(h)), m.position(m.from_vertex(h))),
                sub(m.position(m.to_vertex(g)), m.position(m.from_vertex(g))),
            );
            norm(cross(u, w)) <= 1e-12 * norm(u) * norm(w) && dot(u, w) > 0.0
        };
        let mut best: Vec<u32> = Vec::new();
        for v in 0..m.n_vertices() as u32 {
            for &h in &feature_at[v as usize] {
                let mut chain = vec![v, m.to_vertex(h)];
                let mut cur = h;
                while chain.len() < 40 {
                    let w = m.to_vertex(cur);
                    let outs = &feature_at[w as usize];
                    if outs.len() != 2 {
                        break;
                    }
                    let Some(&next) = outs.iter().find(|&&g| g != cur ^ 1) else { break };
                    if !straight(cur, next) || chain.contains(&m.to_vertex(next)) {
                        break;
                    }
                    chain.push(m.to_vertex(next));
                    cur = next;
                }
                if chain.len() > best.len() {
                    best = chain;
                }
            }
        }
        assert!(best.len() >= 5, "no straight feature line found ({} vertices)", best.len());
        let (s, t) = (best[0], *best.last().unwrap());
        let c = trace_curve(&m, &[s, t], &[]).unwrap();
        assert_well_formed(&m, &c, &[s, t]);
        let expect: Vec<CurvePoint> = best.iter().map(|&v| CurvePoint::Vertex(v)).collect();
        assert_eq!(c.points, expect);
        // And on a curved stretch of the mesh, curves stay geodesics.
        let nv = m.n_vertices() as u32;
        let mut rng = Lcg(5);
        for _ in 0..20 {
            let s = (rng.next() * nv as f64) as u32 % nv;
            let t = (rng.next() * nv as f64) as u32 % nv;
            if s != t {
                let c = trace_curve(&m, &[s, t], &[]).unwrap();
                assert_well_formed(&m, &c, &[s, t]);
                assert_locally_straight(&m, &c, 1e-6);
            }
        }
    }

    #[test]
    fn geodesics_on_every_shared_mesh() {
        // Closed and open, genus 0 to 3: curves are well formed, locally straight, and
        // between the straight-line distance and the edge path.
        for name in ["nefertiti.obj", "eight.obj", "mushroom.obj", "elephant_44k.obj"] {
            let m = load(name);
            let nv = m.n_vertices() as u32;
            let mut rng = Lcg(17);
            let mut traced = 0;
            while traced < 40 {
                let s = (rng.next() * nv as f64) as u32 % nv;
                let t = (rng.next() * nv as f64) as u32 % nv;
                if s == t || m.is_isolated(s) || m.is_isolated(t) {
                    continue;
                }
                let c = trace_curve(&m, &[s, t], &[]).unwrap();
                assert_well_formed(&m, &c, &[s, t]);
                assert_locally_straight(&m, &c, 1e-6);
                assert!(c.length >= dist(m.position(s), m.position(t)) - 1e-12);
                assert!(c.length <= edge_path_length(&m, s, t) + 1e-12, "{name}");
                traced += 1;
            }
        }
    }

    #[test]
    fn bad_stops_are_errors() {
        let m = grid(4, 0.0);
        assert_eq!(trace_curve(&m, &[3], &[]), Err(CurveError::TooFewStops { count: 1 }));
        assert_eq!(trace_curve(&m, &[3, 99], &[]), Err(CurveError::NotOnSurface { index: 1, vertex: 99 }));
        assert_eq!(trace_curve(&m, &[3, 3], &[]), Err(CurveError::ZeroLength { vertex: 3 }));
        let c = trace_curve(&m, &[0, 1], &[]).unwrap();
        assert_eq!(c.points, vec![CurvePoint::Vertex(0), CurvePoint::Vertex(1)]);
    }

    #[test]
    fn timing_on_bunny_28k() {
        let m = load("bunny_28k.obj");
        let (lo, hi) = crate::mesh::geometry::bounding_box(&m);
        let diag = dist(lo, hi);
        let nv = m.n_vertices() as u32;
        let mut rng = Lcg(1);
        let mut pairs = Vec::new();
        while pairs.len() < 20 {
            let s = (rng.next() * nv as f64) as u32 % nv;
            let t = (rng.next() * nv as f64) as u32 % nv;
            let d = dist(m.position(s), m.position(t));
            if d > 0.3 * diag && d < 0.37 * diag {
                pairs.push((s, t));
            }
        }
        let start = std::time::Instant::now();
        let curves: Vec<Curve> = pairs.iter().map(|&(s, t)| trace_curve(&m, &[s, t], &[]).unwrap()).collect();
        let elapsed = start.elapsed();
        let points: usize = curves.iter().map(|c| c.points.len()).sum();
        println!("20 curves on bunny_28k: {elapsed:?}, {points} points in all");
        for (c, &(s, t)) in curves.iter().zip(&pairs) {
            assert_well_formed(&m, c, &[s, t]);
            assert_locally_straight(&m, c, 1e-6);
        }
        assert!(elapsed.as_secs_f64() < 5.0);
    }
}
