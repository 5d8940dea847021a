//! Streamlines of the cross field walked along mesh edges, grown together as a motorcycle
//! graph (Eppstein, Goodrich, Kim, Tamstorf 2008; method-notes §11).
//!
//! A trace is a path of mesh vertices. Each step follows the arm of the cross nearest the
//! trace's heading and goes to the neighbour that stays closest to the ideal streamline (a
//! straight line along that arm through the trace's ideal position, kept as an offset from
//! the current vertex), so the path zig-zags along the streamline without drifting off it.
//! Paths of mesh edges that share no vertex cannot cross, so the layout curves made from
//! them meet only where a trace ends on another: the motorcycle rule. All traces grow in the
//! order of their length; a trace stops on the first vertex that is already taken (another
//! trace, a node, a feature line, the boundary), which becomes a T-junction.

use super::frames::tangential;
use super::CrossField;
use crate::geom::{dot, norm, sub, unit, Vec3};
use crate::mesh::{Mesh, NONE};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Taken by a node, a feature line or the boundary rather than by a trace.
pub const BLOCKED: u32 = u32::MAX - 1;

/// Steps after which a trace that comes next to another curve ends on it (the first steps
/// leave a node next to its other traces).
const SNAP_AFTER: usize = 3;

/// A step may leave at most this far from the followed arm (cosine of the angle).
const MIN_ALIGNMENT: f64 = 0.4;

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
}

/// The growing motorcycle graph: who owns each vertex, and the traces.
pub struct Motorcycles<'a> {
    mesh: &'a Mesh,
    field: &'a CrossField,
    /// Per vertex: [`NONE`] (free), [`BLOCKED`], or the trace that runs through it.
    pub owner: Vec<u32>,
    pub traces: Vec<Trace>,
    pending: Vec<Walker>,
    max_length: f64,
}

#[derive(Debug, Clone)]
struct Walker {
    trace: u32,
    heading: Vec3,
    /// Ideal streamline position minus the current vertex's position.
    offset: Vec3,
    length: f64,
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
        Motorcycles { mesh, field, owner, traces: Vec::new(), pending: Vec::new(), max_length }
    }

    /// Queues a trace leaving `start` along `heading` (a tangent direction at `start`).
    pub fn launch(&mut self, start: u32, heading: Vec3) {
        let trace = self.traces.len() as u32;
        self.traces.push(Trace { path: vec![start], end: TraceEnd::Free });
        self.pending.push(Walker { trace, heading: unit(heading), offset: [0.0; 3], length: 0.0 });
    }

    /// Grows every queued trace until it ends (motorcycle rule).
    pub fn run(&mut self) {
        let mut walkers: Vec<Walker> = std::mem::take(&mut self.pending);
        let mut heap: BinaryHeap<Next> = (0..walkers.len()).map(|k| Next(0.0, k)).collect();
        while let Some(Next(_, k)) = heap.pop() {
            let w = &walkers[k];
            let t = w.trace as usize;
            let v = *self.traces[t].path.last().unwrap_or(&NONE);
            let first = self.traces[t].path.len() == 1;
            let back = if first { NONE } else { self.traces[t].path[self.traces[t].path.len() - 2] };
            let Some((next, heading, offset, step)) = self.step(v, back, w, first) else { continue };
            let path = &mut self.traces[t].path;
            path.push(next);
            if self.owner[next as usize] != NONE {
                self.traces[t].end = TraceEnd::Hit;
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
                    self.traces[t].end = TraceEnd::Hit;
                    continue;
                }
            }
            self.owner[next as usize] = w.trace;
            let length = w.length + step;
            if length > self.max_length {
                continue;
            }
            walkers[k] = Walker { trace: w.trace, heading, offset, length };
            heap.push(Next(length, k));
        }
    }

    /// One step from `v` (not back to `back`): the next vertex, heading, offset and step length.
    fn step(&self, v: u32, back: u32, w: &Walker, first: bool) -> Option<(u32, Vec3, Vec3, f64)> {
        let mesh = self.mesh;
        let n = self.field.frames.normal[v as usize];
        let dir = if first {
            unit(tangential(w.heading, n))
        } else {
            let arms = self.field.arms(v);
            let best = arms.iter().copied().max_by(|a, b| dot(*a, w.heading).total_cmp(&dot(*b, w.heading)))?;
            best
        };
        let p = mesh.position(v);
        let ideal = [p[0] + w.offset[0], p[1] + w.offset[1], p[2] + w.offset[2]];
        let mut best: Option<(f64, u32, Vec3, f64)> = None;
        for u in mesh.neighbors(v) {
            let q = mesh.position(u);
            let e = sub(q, p);
            let len = norm(e);
            if u == back || dot(e, dir) < MIN_ALIGNMENT * len {
                continue;
            }
            let r = sub(q, ideal);
            let along = dot(r, dir);
            let lat = sub(r, [dir[0] * along, dir[1] * along, dir[2] * along]);
            let miss = norm(lat);
            if best.as_ref().is_none_or(|b| miss < b.0) {
                best = Some((miss, u, lat, len));
            }
        }
        let (_, u, lat, len) = best?;
        let nu = self.field.frames.normal[u as usize];
        let offset = tangential([-lat[0], -lat[1], -lat[2]], nu);
        Some((u, dir, offset, len))
    }
}
