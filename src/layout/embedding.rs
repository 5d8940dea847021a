//! The layout graph embedded in the surface: the cyclic order of curves around each node,
//! and the faces it bounds (paper Section 3, Fig. 3; layout-format.md, "patches").
//!
//! Around a node `v`, directions are measured by a clockwise key: the `j`-th halfedge of
//! [`Mesh::outgoing`] has key `j`, and a curve leaving `v` through the interior of the
//! triangle `face(h_j)` (which lies between `h_{j-1}` and `h_j`) gets a key in `(j-1, j)`
//! from where it crosses the opposite edge. A face is traced with the rule of rotation
//! systems: arriving at a node, leave by the next curve clockwise. The face then lies on
//! the left of every curve piece it runs along, so its node cycle is counter-clockwise.

use super::curve::{Curve, CurvePoint};
use crate::geom::{angle, sub};
use crate::mesh::geometry::corner_angle;
use crate::mesh::{Mesh, NONE};

/// One end of a curve: where it leaves its first node (`at_start`) or its last node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct End {
    pub curve: u32,
    pub at_start: bool,
}

/// A curve run in one direction; the face it bounds lies on its left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Directed {
    pub curve: u32,
    pub forward: bool,
}

impl Directed {
    /// The end through which this directed curve leaves its first node.
    pub fn departure(self) -> End {
        End { curve: self.curve, at_start: self.forward }
    }
    /// The end through which it arrives at its last node.
    pub fn arrival(self) -> End {
        End { curve: self.curve, at_start: !self.forward }
    }
}

/// A curve end at a node with its direction.
#[derive(Debug, Clone, Copy)]
pub struct EndDirection {
    pub end: End,
    /// Clockwise key (see the module documentation).
    pub key: f64,
    /// Clockwise angle on the surface from the node's first outgoing halfedge.
    pub theta: f64,
}

/// Curve ends around every node, clockwise.
pub struct Rotation {
    /// Per node: its ends sorted by key.
    pub ends: Vec<Vec<EndDirection>>,
    /// Per node: the total angle around it (sum of triangle angles; less than the full
    /// turn's share of the hole at boundary nodes).
    pub total_angle: Vec<f64>,
    pub boundary_node: Vec<bool>,
}

/// The endpoints of each curve as node indices.
pub type CurveNodes = [u32; 2];

/// Key and angle of the direction from `v` towards the curve point `p`.
///
/// Precondition: `p` is a neighbour of `v` or lies on the edge opposite `v` in one of its
/// triangles (true for the second point of any traced curve).
fn direction(mesh: &Mesh, v: u32, outgoing: &[u32], thetas: &[f64], p: &CurvePoint) -> Option<(f64, f64)> {
    let pv = mesh.position(v);
    match *p {
        CurvePoint::Vertex(w) => {
            let j = outgoing.iter().position(|&h| mesh.to_vertex(h) == w)?;
            Some((j as f64, thetas[j]))
        }
        CurvePoint::Edge { edge, t } => {
            let j = outgoing.iter().position(|&h| {
                mesh.face(h) != NONE && mesh.edge(mesh.next(h)) == edge
            })?;
            let h = outgoing[j];
            let opposite = mesh.next(h);
            let lambda = if opposite == 2 * edge { t } else { 1.0 - t };
            let a = mesh.position(mesh.from_vertex(opposite));
            let b = mesh.position(mesh.to_vertex(opposite));
            let q: [f64; 3] = std::array::from_fn(|k| a[k] + lambda * (b[k] - a[k]));
            // Angle from the direction of h_{j-1} (towards b) clockwise to q.
            let (u, w) = (sub(b, pv), sub(q, pv));
            let from_prev = angle(u, w);
            let theta_prev = if j == 0 { thetas[j] - corner_angle(mesh, h) } else { thetas[j - 1] };
            Some((j as f64 - lambda, theta_prev + from_prev))
        }
    }
}


/// Sorts the curve ends around every node.
///
/// Returns `None` naming a curve whose second point is not next to its node, which traced
/// curves never produce.
pub fn rotation(mesh: &Mesh, node_vertex: &[u32], curves: &[(CurveNodes, &Curve)]) -> Result<Rotation, u32> {
    let n = node_vertex.len();
    let mut ends: Vec<Vec<EndDirection>> = vec![Vec::new(); n];
    let mut total_angle = vec![0.0; n];
    let mut boundary_node = vec![false; n];
    let mut outgoing_of = Vec::with_capacity(n);
    for (i, &v) in node_vertex.iter().enumerate() {
        let out: Vec<u32> = mesh.outgoing(v).collect();
        let mut thetas = Vec::with_capacity(out.len());
        let mut acc = 0.0;
        for &h in &out {
            if mesh.face(h) != NONE {
                acc += corner_angle(mesh, h);
            }
            thetas.push(acc);
        }
        // theta_j is measured from h_0 clockwise: face(h_j) lies before h_j.
        let first = if mesh.face(out[0]) != NONE { corner_angle(mesh, out[0]) } else { 0.0 };
        for t in &mut thetas {
            *t -= first;
        }
        total_angle[i] = acc;
        boundary_node[i] = mesh.is_boundary_vertex(v);
        outgoing_of.push((out, thetas));
    }
    for (c, (nodes, curve)) in curves.iter().enumerate() {
        let pts = &curve.points;
        for (at_start, node, p) in [(true, nodes[0], &pts[1]), (false, nodes[1], &pts[pts.len() - 2])] {
            let (out, thetas) = &outgoing_of[node as usize];
            let v = node_vertex[node as usize];
            let (key, theta) = direction(mesh, v, out, thetas, p).ok_or(c as u32)?;
            ends[node as usize].push(EndDirection { end: End { curve: c as u32, at_start }, key, theta });
        }
    }
    for e in &mut ends {
        e.sort_by(|a, b| a.key.total_cmp(&b.key));
    }
    Ok(Rotation { ends, total_angle, boundary_node })
}

/// A face of the layout: the directed curves around it, face on their left.
#[derive(Debug, Clone)]
pub struct TracedFace {
    pub pieces: Vec<Directed>,
    /// The node each piece leaves from.
    pub nodes: Vec<u32>,
    /// Interior angle on the surface at each node of `nodes`.
    pub angles: Vec<f64>,
}

/// Traces every face of the rotation system.
pub fn trace_faces(rot: &Rotation, curves: &[(CurveNodes, &Curve)]) -> Vec<TracedFace> {
    let position = |node: u32, end: End| rot.ends[node as usize].iter().position(|e| e.end == end);
    let mut seen = std::collections::HashSet::new();
    let mut faces = Vec::new();
    for c in 0..curves.len() as u32 {
        for forward in [true, false] {
            let start = Directed { curve: c, forward };
            if seen.contains(&start) {
                continue;
            }
            let mut face = TracedFace { pieces: Vec::new(), nodes: Vec::new(), angles: Vec::new() };
            let mut d = start;
            // Each directed curve belongs to one face: the walk closes within 2 × curves steps.
            for _ in 0..=2 * curves.len() {
                seen.insert(d);
                let nodes = curves[d.curve as usize].0;
                let (from, to) = if d.forward { (nodes[0], nodes[1]) } else { (nodes[1], nodes[0]) };
                face.pieces.push(d);
                face.nodes.push(from);
                let ring = &rot.ends[to as usize];
                let i = position(to, d.arrival()).unwrap_or(0);
                let j = (i + 1) % ring.len();
                let next = ring[j].end;
                let mut angle = ring[j].theta - ring[i].theta;
                if j <= i {
                    angle += rot.total_angle[to as usize];
                }
                face.angles.push(angle);
                d = Directed { curve: next.curve, forward: next.at_start };
                if d == start {
                    break;
                }
            }
            // angles[k] was computed at the node where piece k arrives: rotate to its start.
            face.angles.rotate_right(1);
            faces.push(face);
        }
    }
    faces
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::layout::curve::trace_curve;

    /// A planar n×n grid on [0,1]², diagonals alternating.
    pub fn grid(n: u32) -> Mesh {
        crate::mesh::primitives::quad_grid([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], n)
    }

    #[test]
    fn a_plus_sign_of_curves_bounds_four_corners_of_ninety_degrees() {
        let n = 10;
        let m = grid(n);
        let id = |i: u32, j: u32| j * (n + 1) + i;
        // A centre node and four arms to nodes inside the grid.
        let node_vertex = vec![id(5, 5), id(8, 5), id(5, 8), id(2, 5), id(5, 2)];
        let blocked = vec![false; m.n_vertices()];
        let traced: Vec<Curve> = (1..5)
            .map(|k| trace_curve(&m, &[node_vertex[0], node_vertex[k]], &blocked).unwrap())
            .collect();
        let curves: Vec<(CurveNodes, &Curve)> =
            traced.iter().enumerate().map(|(k, c)| ([0, k as u32 + 1], c)).collect();
        let rot = rotation(&m, &node_vertex, &curves).unwrap();
        assert_eq!(rot.ends[0].len(), 4);
        let faces = trace_faces(&rot, &curves);
        // A tree: one face running around all arms, with 8 pieces.
        assert_eq!(faces.len(), 1);
        assert_eq!(faces[0].pieces.len(), 8);
        let at_centre: Vec<f64> =
            (0..8).filter(|&k| faces[0].nodes[k] == 0).map(|k| faces[0].angles[k]).collect();
        assert_eq!(at_centre.len(), 4);
        for a in at_centre {
            assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{a}");
        }
    }
}
