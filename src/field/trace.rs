//! Streamlines of the cross field, grown together as a motorcycle graph (Eppstein, Goodrich,
//! Kim, Tamstorf 2008; method-notes §11), each kept as the path of mesh vertices nearest it.
//!
//! A trace walks across triangles: in each it goes straight along the field, the arm of each
//! corner's cross nearest the trace's heading blended by the entry point's barycentric
//! weights (or, where the field has them, the triangle's iso-line direction nearest the
//! heading: [`super::seamless`]), to the triangle's boundary, and on into the next triangle.
//! Of every mesh edge it crosses, the nearer end joins the trace's vertex path; consecutive
//! such vertices share a triangle, so the path runs along mesh edges, within half an edge of
//! the streamline, and the streamline does not drift as a walk from vertex to vertex does
//! (the next vertex's direction always a neighbour's, up to 30° off the field on a coarse
//! mesh).
//! Paths of mesh edges that share no vertex cannot cross, so the layout curves made from
//! them meet only where a trace ends on another: the motorcycle rule. All traces grow in the
//! order of their length; a trace stops on the first vertex that is already taken (another
//! trace, a node, a feature line, the boundary), which becomes a T-junction. Where that is a
//! feature line met square enough, a new trace goes on from there on the other side
//! ([`Motorcycles::crossing`]): the two meet the line in a crossing.

use super::frames::tangential;
use super::CrossField;
use crate::geom::{add, cross, dot, norm, scale, sub, unit, Vec3};
use crate::mesh::{Mesh, NONE};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap, VecDeque};

/// Taken by a node, a feature line or the boundary rather than by a trace.
pub const BLOCKED: u32 = u32::MAX - 1;

/// Steps after which a trace that comes next to another curve ends on it (the first steps
/// leave a node next to its other traces).
const SNAP_AFTER: usize = 3;

/// A trace goes on across a feature line it meets at more than this angle
/// ([`Motorcycles::continuation`]); one nearer along the line is running beside it.
const CROSS_ANGLE: f64 = std::f64::consts::PI / 3.0;

/// How a trace ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TraceEnd {
    /// On a taken vertex (the last of the path).
    Hit,
    /// Nowhere to go, or too long: the trace dangles.
    Free,
}

/// A trace: its vertices from start to end.
#[derive(Debug, Clone)]
pub struct Trace {
    pub path: Vec<u32>,
    pub end: TraceEnd,
    /// The trace this one continues across a feature line ([`Motorcycles::crossing`]), or
    /// [`NONE`] for a launched one.
    pub continues: u32,
}

/// A ray that misses a triangle's edges by more than this (in edge lengths) ends the trace.
const MAX_MISS: f64 = 0.25;
/// A crossing this close to an edge's end (in edge lengths) runs through the vertex.
const THROUGH_VERTEX: f64 = 1e-4;

/// The growing motorcycle graph: who owns each vertex, and the traces.
pub struct Motorcycles<'a> {
    mesh: &'a Mesh,
    field: &'a CrossField,
    /// Per vertex: [`NONE`] (free), [`BLOCKED`], or the trace that runs through it.
    owner: Vec<u32>,
    pub traces: Vec<Trace>,
    pending: Vec<Walker>,
    max_length: f64,
    /// Per vertex where traces end, their headings there ([`Motorcycles::end_at_crossing`];
    /// kept only when snapping).
    arrivals: HashMap<u32, Vec<Vec3>>,
    /// How far along a curve a trace's end moves to meet one from the other side; 0: never.
    snap: f64,
    /// Per vertex: the tangent of the feature line a trace that ends there goes on across, or
    /// zero (empty: none); see [`Motorcycles::crossing`].
    crossable: Vec<Vec3>,
}

/// A trace snaps at most this share of its length ([`Motorcycles::end_at_crossing`]).
const SNAP_SHARE: f64 = 0.25;
/// Headings at least this opposite (the cosine of the angle between them below its negative)
/// come from either side of the curve they end on.
const OPPOSITE: f64 = 0.5;

#[derive(Debug, Clone)]
struct Walker {
    trace: u32,
    /// Unit direction of the last step (or of the launch).
    heading: Vec3,
    /// The triangle the walker is in, and the halfedge of it by which it came in (`NONE` on
    /// the first triangle, entered at the trace's start vertex).
    face: u32,
    entry: u32,
    /// Where on the triangle's boundary the walker is.
    point: Vec3,
    /// The mesh vertex the walker stands on (its start, or a vertex the streamline ran
    /// through), or `NONE` inside a mesh edge.
    vertex: u32,
    length: f64,
    steps: usize,
}

/// Min-heap entry by length.
struct Next(f64, usize);
impl PartialEq for Next {
    fn eq(&self, o: &Self) -> bool {
        self.0 == o.0 && self.1 == o.1
    }
}
impl Eq for Next {}
impl PartialOrd for Next {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Next {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

impl<'a> Motorcycles<'a> {
    /// An empty graph; `owner` says which vertices are taken before any trace runs.
    pub fn new(mesh: &'a Mesh, field: &'a CrossField, owner: Vec<u32>, max_length: f64) -> Motorcycles<'a> {
        Motorcycles { mesh, field, owner, traces: Vec::new(), pending: Vec::new(), max_length, arrivals: HashMap::new(), snap: 0.0, crossable: Vec::new() }
    }

    /// The graph with traces that end within `snap` (along the curve they end on) of one that
    /// ended there from the other side moved to end where it did ([`Self::end_at_crossing`]).
    pub fn snapping(self, snap: f64) -> Motorcycles<'a> {
        Motorcycles { snap, ..self }
    }

    /// The graph with traces that end on a feature line, where `tangents` (per vertex) has
    /// the line's direction, going on across it on the other side ([`Self::continuation`]).
    pub fn crossing(self, tangents: Vec<Vec3>) -> Motorcycles<'a> {
        Motorcycles { crossable: tangents, ..self }
    }

    /// Queues a trace leaving `start` along `heading` (a tangent direction at `start`); a
    /// vertex no triangle holds in that direction starts nothing.
    pub fn launch(&mut self, start: u32, heading: Vec3) {
        let trace = self.traces.len() as u32;
        self.traces.push(Trace { path: vec![start], end: TraceEnd::Free, continues: NONE });
        let Some(face) = self.sector(start, heading) else { return };
        let point = self.mesh.position(start);
        let walker = Walker { trace, heading: unit(heading), face, entry: NONE, point, vertex: start, length: 0.0, steps: 0 };
        self.pending.push(walker);
    }

    /// Where trace `t` has just ended (walker `w`) on a feature line that it meets at more
    /// than [`CROSS_ANGLE`]: a new trace going on from there into the other side, square to
    /// the line as the field is there. The grid line goes on across the sharp edge as a hand
    /// layout of a CAD part draws it, rather than ending in a T-junction that the other side
    /// meets elsewhere with its own.
    fn continuation(&mut self, t: usize, w: &Walker) -> Option<Walker> {
        let mesh = self.mesh;
        let path = &self.traces[t].path;
        let (v, before) = (path[path.len() - 1], path[path.len() - 2]);
        let tangent = *self.crossable.get(v as usize)?;
        // Only after a vertex of its own (which also bounds the continuations by the free
        // vertices): `before` then lies on one side of the line, and a step from one line
        // straight onto another (between two lines an edge apart) goes no further.
        if self.owner[before as usize] != t as u32 || norm(tangent) == 0.0 || dot(w.heading, tangent).abs() > CROSS_ANGLE.cos() {
            return None;
        }
        // The triangles at v (each with its two edges there) on the side `before` is on: those
        // reached from its own across edges that are not sharp. The others are across the line.
        let sharp = &self.field.features.sharp;
        let at_v: Vec<(u32, [u32; 2])> =
            mesh.outgoing(v).filter(|&h| mesh.face(h) != NONE).map(|h| (mesh.face(h), [mesh.edge(h), mesh.edge(mesh.prev(h))])).collect();
        let first = at_v.iter().position(|t| mesh.triangles()[t.0 as usize].contains(&before))?;
        let mut near = vec![false; at_v.len()];
        near[first] = true;
        let mut stack = vec![first];
        while let Some(i) = stack.pop() {
            for j in 0..at_v.len() {
                if !near[j] && at_v[i].1.iter().any(|e| !sharp[*e as usize] && at_v[j].1.contains(e)) {
                    near[j] = true;
                    stack.push(j);
                }
            }
        }
        let far: Vec<u32> = at_v.iter().zip(&near).filter(|(_, &n)| !n).map(|(t, _)| t.0).collect();
        // Square to the line in the far side's mean plane, away from the line.
        let p = mesh.position(v);
        let (mut normal, mut towards) = ([0.0; 3], [0.0; 3]);
        for &f in &far {
            let [a, b, c] = mesh.triangles()[f as usize].map(|x| mesh.position(x));
            normal = add(normal, cross(sub(b, a), sub(c, a)));
            towards = add(towards, sub(scale(1.0 / 3.0, add(add(a, b), c)), p));
        }
        let d = unit(cross(normal, tangent));
        let d = if dot(d, towards) < 0.0 { scale(-1.0, d) } else { d };
        // Into a far triangle (d may run exactly along an edge of the far side, where a near
        // triangle holds it as little).
        let face = self.sector_among(v, d, |f| far.contains(&f))?;
        let trace = self.traces.len() as u32;
        self.traces.push(Trace { path: vec![v], end: TraceEnd::Free, continues: t as u32 });
        Some(Walker { trace, heading: d, face, entry: NONE, point: p, vertex: v, length: w.length, steps: 0 })
    }

    /// The triangle at `v` whose corner holds direction `d` (the one it points into most).
    fn sector(&self, v: u32, d: Vec3) -> Option<u32> {
        self.sector_among(v, d, |_| true)
    }

    /// [`Self::sector`] among the triangles `allowed` holds.
    fn sector_among(&self, v: u32, d: Vec3, allowed: impl Fn(u32) -> bool) -> Option<u32> {
        let mesh = self.mesh;
        let p = mesh.position(v);
        mesh.outgoing(v)
            .filter(|&h| mesh.face(h) != NONE && allowed(mesh.face(h)))
            .map(|h| {
                let a = unit(sub(mesh.position(mesh.to_vertex(h)), p));
                let b = unit(sub(mesh.position(mesh.to_vertex(mesh.next(h))), p));
                // Inside the corner when d lies between its two edges: score the smaller side.
                let n = cross(a, b);
                let inside = dot(cross(a, d), n).min(dot(cross(d, b), n));
                (inside, mesh.face(h))
            })
            .max_by(|x, y| x.0.total_cmp(&y.0))
            .map(|x| x.1)
    }

    /// Grows every queued trace until it ends (motorcycle rule).
    pub fn run(&mut self) {
        let mut walkers: Vec<Walker> = std::mem::take(&mut self.pending);
        let mut heap: BinaryHeap<Next> = (0..walkers.len()).map(|k| Next(0.0, k)).collect();
        let max_steps = 4 * self.mesh.n_faces() + 16;
        while let Some(Next(_, k)) = heap.pop() {
            let t = walkers[k].trace as usize;
            let Some((w, crossed)) = self.step(&walkers[k]) else { continue };
            if let Some(next) = crossed.filter(|&x| Some(&x) != self.traces[t].path.last()) {
                let path = &mut self.traces[t].path;
                path.push(next);
                // Ended on a taken vertex; a trace that goes on from it is queued.
                let mut end = |moto: &mut Self, w: &Walker| {
                    if let Some(c) = moto.ended(t, w) {
                        heap.push(Next(c.length, walkers.len()));
                        walkers.push(c);
                    }
                };
                if self.owner[next as usize] != NONE {
                    end(self, &w);
                    continue;
                }
                // Next to another curve: end on it rather than run beside it one edge away,
                // which would leave a face with no vertex inside.
                if path.len() > SNAP_AFTER {
                    let recent = &path[path.len() - 3..];
                    let p = self.mesh.position(next);
                    let near = self
                        .mesh
                        .neighbors(next)
                        .filter(|&x| self.owner[x as usize] != NONE && !recent.contains(&x))
                        .min_by(|&a, &b| {
                            norm(sub(self.mesh.position(a), p)).total_cmp(&norm(sub(self.mesh.position(b), p)))
                        });
                    if let Some(x) = near {
                        self.owner[next as usize] = w.trace;
                        self.traces[t].path.push(x);
                        end(self, &w);
                        continue;
                    }
                }
                self.owner[next as usize] = w.trace;
            }
            if w.length > self.max_length || w.steps > max_steps {
                continue;
            }
            heap.push(Next(w.length, k));
            walkers[k] = w;
        }
    }

    /// Trace `t` (walker `w`) has just ended on the last vertex of its path, a taken one:
    /// [`Self::end_at_crossing`], then the trace that goes on across the feature line there
    /// ([`Self::continuation`]), if any.
    fn ended(&mut self, t: usize, w: &Walker) -> Option<Walker> {
        self.traces[t].end = TraceEnd::Hit;
        self.end_at_crossing(t, w.heading, w.length);
        self.continuation(t, w)
    }

    /// Trace `t` has just ended on a taken vertex, heading `heading`, `length` long. Where
    /// another trace ended on the same curve within the snap (and [`SNAP_SHARE`] of `length`:
    /// a short trace in a thin part bends less) of it from the other side, `t`'s last
    /// stretch is rerouted to end there too: the two meet the curve in one crossing, not in
    /// two T-junctions with a short piece of the curve between them, which must take a segment
    /// of its own however short it is (more quads than asked, squeezed ones) and kinks the
    /// grid line the two traces would make together.
    fn end_at_crossing(&mut self, t: usize, heading: Vec3, length: f64) {
        // Without a snap no trace looks for the others' ends.
        if self.snap <= 0.0 {
            return;
        }
        let path = &self.traces[t].path;
        let mut end = path[path.len() - 1];
        let reach = self.snap.min(SNAP_SHARE * length);
        // Not on itself: the stretch rerouted could hold the vertex it would end on.
        if reach > 0.0 && path.len() > SNAP_AFTER + 1 && self.owner[end as usize] != t as u32 {
            if let Some(j) = self.crossing_near(end, heading, reach) {
                if self.reroute(t, end, j, heading, reach) {
                    end = j;
                }
            }
        }
        self.arrivals.entry(end).or_default().push(heading);
    }

    /// The nearest vertex within `reach` of `x` along the curve it lies on (the
    /// vertices of its owner) where a curve ended heading against `heading` and none with it
    /// (that would be a crossing already).
    fn crossing_near(&self, x: u32, heading: Vec3, reach: f64) -> Option<u32> {
        let curve = self.owner[x as usize];
        let p = self.mesh.position(x);
        let within = |v: u32| norm(sub(self.mesh.position(v), p)) <= reach;
        let mut seen = vec![x];
        let mut queue = VecDeque::from([x]);
        let mut best: Option<(f64, u32)> = None;
        while let Some(v) = queue.pop_front() {
            if let Some(at) = self.arrivals.get(&v) {
                let d = norm(sub(self.mesh.position(v), p));
                let against = at.iter().any(|&a| dot(a, heading) < -OPPOSITE);
                let along = at.iter().any(|&a| dot(a, heading) > OPPOSITE);
                if v != x && against && !along && best.is_none_or(|b| d < b.0) {
                    best = Some((d, v));
                }
            }
            for u in self.mesh.neighbors(v) {
                if self.owner[u as usize] == curve && !seen.contains(&u) && within(u) {
                    seen.push(u);
                    queue.push_back(u);
                }
            }
        }
        best.map(|b| b.1)
    }

    /// Trace `t`, which ended on `x` heading `heading`, ends on `j` (within `reach` of `x`)
    /// instead: its path from where it was twice `reach` from `x` is replaced by the shortest
    /// path of free vertices that reaches `j` from the side `heading` comes from, so the bend
    /// spreads over that stretch; `false` (nothing changed) where there is none.
    fn reroute(&mut self, t: usize, x: u32, j: u32, heading: Vec3, reach: f64) -> bool {
        let mesh = self.mesh;
        let p = mesh.position(x);
        let path = &self.traces[t].path;
        // The last vertex at least twice the reach from x, past the first few steps.
        let from = (SNAP_AFTER..path.len() - 1).rev().find(|&k| norm(sub(mesh.position(path[k]), p)) >= 2.0 * reach).unwrap_or(SNAP_AFTER);
        let start = path[from];
        let dropped: Vec<u32> = path[from + 1..path.len() - 1].to_vec();
        for &v in &dropped {
            self.owner[v as usize] = NONE;
        }
        // The shortest path over free vertices near x.
        let around = 3.0 * reach;
        let mut dist: HashMap<u32, (f64, u32)> = HashMap::from([(start, (0.0, NONE))]);
        let mut heap = BinaryHeap::from([Next(0.0, start as usize)]);
        let mut last = None;
        while let Some(Next(d, v)) = heap.pop() {
            let v = v as u32;
            if dist.get(&v).is_some_and(|e| d > e.0) {
                continue;
            }
            if mesh.neighbors(v).any(|u| u == j) && dot(sub(mesh.position(j), mesh.position(v)), heading) > 0.0 {
                last = Some(v);
                break;
            }
            for u in mesh.neighbors(v) {
                if self.owner[u as usize] != NONE || norm(sub(mesh.position(u), p)) > around {
                    continue;
                }
                let du = d + norm(sub(mesh.position(u), mesh.position(v)));
                if dist.get(&u).is_none_or(|e| du < e.0) {
                    dist.insert(u, (du, v));
                    heap.push(Next(du, u as usize));
                }
            }
        }
        let Some(mut v) = last else {
            for &v in &dropped {
                self.owner[v as usize] = t as u32;
            }
            return false;
        };
        let mut route = Vec::new();
        while v != start {
            route.push(v);
            v = dist[&v].1;
        }
        route.reverse();
        let path = &mut self.traces[t].path;
        path.truncate(from + 1);
        for &v in &route {
            self.owner[v as usize] = t as u32;
        }
        path.extend(route);
        path.push(j);
        true
    }

    /// The field's direction in triangle `f` at `point`, nearest `heading`: each corner's arm
    /// nearest it, blended by barycentric weight, in the triangle's plane.
    fn direction(&self, f: u32, point: Vec3, heading: Vec3, n: Vec3) -> Vec3 {
        let corners = self.mesh.triangles()[f as usize];
        let p = corners.map(|v| self.mesh.position(v));
        let area = |a: Vec3, b: Vec3, c: Vec3| dot(cross(sub(b, a), sub(c, a)), n).max(0.0);
        let w = [area(point, p[1], p[2]), area(p[0], point, p[2]), area(p[0], p[1], point)];
        let total = (w[0] + w[1] + w[2]).max(1e-300);
        let mut d = [0.0; 3];
        for k in 0..3 {
            let arm = self.field.arms(corners[k]).into_iter().map(|a| tangential(a, n)).max_by(|a, b| dot(*a, heading).total_cmp(&dot(*b, heading)));
            if let Some(a) = arm {
                let a = unit(a);
                for i in 0..3 {
                    d[i] += w[k] / total * a[i];
                }
            }
        }
        if norm(d) < 1e-12 {
            heading
        } else {
            unit(d)
        }
    }

    /// The iso-line direction of triangle `f` nearest `heading`, if the field has them there.
    fn iso_direction(&self, f: u32, heading: Vec3) -> Option<Vec3> {
        let [du, dv] = (*self.field.iso.arms.get(f as usize)?)?;
        [du, dv, scale(-1.0, du), scale(-1.0, dv)].into_iter().max_by(|a, b| dot(*a, heading).total_cmp(&dot(*b, heading)))
    }

    /// One step of walker `w` across its triangle: the walker in the next triangle and the
    /// nearer end of the mesh edge it crossed (or the vertex it ran through); `None` where
    /// the trace ends (a degenerate triangle, no way on).
    fn step(&self, w: &Walker) -> Option<(Walker, Option<u32>)> {
        let mesh = self.mesh;
        // On a vertex, the triangle its iso-line leaves into (the heading's may hold none).
        let f = match (w.vertex, self.iso_direction(w.face, w.heading)) {
            (v, Some(d)) if v != NONE && w.steps > 0 => self.sector(v, d).unwrap_or(w.face),
            _ => w.face,
        };
        let p = mesh.triangles()[f as usize].map(|v| mesh.position(v));
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        if norm(n) < 1e-300 {
            return None;
        }
        let n = unit(n);
        let heading = unit(tangential(w.heading, n));
        // Leaving the start vertex, the launch direction (the field has no direction at a
        // singularity); then the triangle's iso-line if it has one; at a vertex run through,
        // its cross's arm; else the field's blend.
        let d = if w.steps == 0 {
            heading
        } else if let Some(d) = self.iso_direction(f, heading) {
            d
        } else if w.vertex != NONE {
            let arms = self.field.arms(w.vertex).map(|a| tangential(a, n));
            arms.into_iter().max_by(|a, b| dot(*a, heading).total_cmp(&dot(*b, heading))).map_or(heading, unit)
        } else {
            self.direction(f, w.point, heading, n)
        };
        // The exit: the edge of f (not the one entered by, none at the vertex stood on) that
        // the ray crosses first; a ray along an edge, or a hair outside the triangle, leaves
        // by the edge it misses least.
        let mut best: Option<(f64, f64, u32, f64)> = None;
        for k in 0..3 {
            let h = mesh.face_halfedge(f, k);
            let (i, j) = (mesh.from_vertex(h), mesh.to_vertex(h));
            if h == w.entry || i == w.vertex || j == w.vertex {
                continue;
            }
            let (a, b) = (mesh.position(i), mesh.position(j));
            let e = sub(b, a);
            // point + t d = a + s e, in the plane: cross with n to solve the 2×2 system.
            let denom = dot(cross(d, e), n);
            if denom.abs() < 1e-300 {
                continue;
            }
            let r = sub(a, w.point);
            let t = dot(cross(r, e), n) / denom;
            let s = dot(cross(r, d), n) / denom;
            let miss = (-s).max(s - 1.0).max(0.0);
            if t > 0.0 && best.is_none_or(|b| (miss, t) < (b.0, b.1)) {
                best = Some((miss, t, h, s.clamp(0.0, 1.0)));
            }
        }
        let (_, t, h, s) = best.filter(|b| b.0 < MAX_MISS)?;
        let point = [w.point[0] + t * d[0], w.point[1] + t * d[1], w.point[2] + t * d[2]];
        let length = w.length + t;
        let steps = w.steps + 1;
        let nearer = if s < 0.5 { mesh.from_vertex(h) } else { mesh.to_vertex(h) };
        if !(THROUGH_VERTEX..=1.0 - THROUGH_VERTEX).contains(&s) {
            // Through a vertex: go on from it into the triangle the direction points into.
            let Some(face) = self.sector(nearer, d) else {
                return Some((Walker { steps: usize::MAX, ..w.clone() }, Some(nearer)));
            };
            let point = mesh.position(nearer);
            let walker = Walker { trace: w.trace, heading: d, face, entry: NONE, point, vertex: nearer, length, steps };
            return Some((walker, Some(nearer)));
        }
        let twin = mesh.twin(h);
        let next_face = mesh.face(twin);
        let walker = Walker { trace: w.trace, heading: d, face: next_face, entry: twin, point, vertex: NONE, length, steps };
        if next_face == NONE {
            // Out over the boundary: the nearer end is a boundary vertex, taken, so the
            // trace ends there; a walker off the surface never steps again.
            return Some((Walker { face: f, entry: h, steps: usize::MAX, ..walker }, Some(nearer)));
        }
        Some((walker, Some(nearer)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::compute_field;
    use crate::mesh::primitives::{parallelepiped, quad_grid};

    /// Two traces up and down (or both up) a 20 × 20 grid of the unit square toward a curve
    /// across its middle row, two columns apart, grown with `snap`; their ends.
    fn ends(second_from_above: bool, snap: f64) -> [u32; 2] {
        let n = 20;
        let mesh = quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n);
        let field = compute_field(&mesh, 35.0).unwrap();
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut owner = vec![NONE; mesh.n_vertices()];
        for i in 0..=n {
            owner[id(i, 10) as usize] = BLOCKED;
        }
        let mut moto = Motorcycles::new(&mesh, &field, owner, 3.0).snapping(snap);
        moto.launch(id(5, 1), [0.0, 1.0, 0.0]);
        if second_from_above {
            moto.launch(id(7, 19), [0.0, -1.0, 0.0]);
        } else {
            moto.launch(id(7, 1), [0.0, 1.0, 0.0]);
        }
        moto.run();
        assert!(moto.traces.iter().all(|t| t.end == TraceEnd::Hit));
        [0, 1].map(|k| *moto.traces[k].path.last().unwrap())
    }

    #[test]
    fn traces_meeting_a_curve_from_either_side_close_together_cross_it_at_one_vertex() {
        let id = |i: u32| 10 * 21 + i;
        let [a, b] = ends(true, 0.12);
        assert_eq!(a, b);
        assert!([id(5), id(7)].contains(&a), "{a}");
        // Not without the snap, nor from the same side (the strip between them is a face).
        assert_eq!(ends(true, 0.0), [id(5), id(7)]);
        assert_eq!(ends(false, 0.12), [id(5), id(7)]);
    }

    /// A trace from the middle of a cube's bottom along +x, its edges taken as feature lines:
    /// with crossing it goes on up the side, over the top and down, and ends on its own start,
    /// a ring round the cube in four traces each square to the edge it leaves (one ending
    /// where the next starts); without, it ends on the first edge.
    #[test]
    fn a_trace_goes_on_across_the_feature_lines_it_meets() {
        let n = 10;
        let (mesh, ids) = parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], n);
        let field = compute_field(&mesh, 35.0).unwrap();
        let mut owner = vec![NONE; mesh.n_vertices()];
        let mut tangents = vec![[0.0; 3]; mesh.n_vertices()];
        for (g, &v) in &ids {
            let inner: Vec<usize> = (0..3).filter(|&a| g[a] != 0 && g[a] != n).collect();
            if inner.len() < 2 {
                owner[v as usize] = BLOCKED;
            }
            if inner.len() == 1 {
                tangents[v as usize][inner[0]] = 1.0;
            }
        }
        // The start is a node, as a launch's is.
        owner[ids[&[5, 5, 0]] as usize] = BLOCKED;
        let run = |tangents: Vec<Vec3>| {
            let mut moto = Motorcycles::new(&mesh, &field, owner.clone(), 10.0).crossing(tangents);
            moto.launch(ids[&[5, 5, 0]], [1.0, 0.0, 0.0]);
            moto.run();
            moto.traces
        };
        let plain = run(Vec::new());
        assert_eq!(plain.len(), 1);
        assert_eq!(plain[0].path.last(), Some(&ids[&[n, 5, 0]]));
        let ring = run(tangents);
        let ends: Vec<u32> = ring.iter().map(|t| *t.path.last().unwrap()).collect();
        assert_eq!(ends, [[n, 5, 0], [n, 5, n], [0, 5, n], [0, 5, 0], [5, 5, 0]].map(|g| ids[&g]));
        for (k, t) in ring.iter().enumerate() {
            assert_eq!(t.end, TraceEnd::Hit);
            assert_eq!(t.continues, if k == 0 { NONE } else { k as u32 - 1 });
            // Straight along its face: every vertex on the ring y = 5.
            assert!(t.path.iter().all(|v| ids.iter().any(|(g, x)| x == v && g[1] == 5)), "trace {k}: {:?}", t.path);
        }
    }
}
