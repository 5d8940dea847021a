//! The patch (layout face) of every mesh vertex (paper Section 3, Fig. 3).
//!
//! Curves cut the mesh: vertices that no curve runs through and that are not nodes are
//! flooded over the mesh edges no curve crosses; each flood region lies inside one face. A
//! face finds its regions on the left of the curve pieces around it. A vertex a curve runs
//! through joins the face on the left of that curve (the fixed rule of method-notes §1).
//! Nodes belong to every face around them and get no patch of their own.

use super::curve::{position, Curve, CurvePoint};
use super::embedding::{CurveNodes, Directed};
use crate::geom::{cross, dot, sub};
use crate::mesh::topology::vertex_regions;
use crate::mesh::{Mesh, NONE};

/// Which curve runs through each vertex and which edges curves cross.
pub struct Cuts {
    /// Per vertex: the curve running through it (not counting its end nodes), or NONE.
    pub on_curve: Vec<u32>,
    pub is_node: Vec<bool>,
    pub crossed: Vec<bool>,
}

pub fn cuts(mesh: &Mesh, node_vertex: &[u32], curves: &[(CurveNodes, &Curve)]) -> Cuts {
    let mut is_node = vec![false; mesh.n_vertices()];
    for &v in node_vertex {
        is_node[v as usize] = true;
    }
    let mut on_curve = vec![NONE; mesh.n_vertices()];
    let mut crossed = vec![false; mesh.n_edges()];
    for (c, (_, curve)) in curves.iter().enumerate() {
        for p in &curve.points {
            match *p {
                CurvePoint::Vertex(v) if !is_node[v as usize] => on_curve[v as usize] = c as u32,
                CurvePoint::Edge { edge, .. } => crossed[edge as usize] = true,
                _ => {}
            }
        }
    }
    Cuts { on_curve, is_node, crossed }
}

/// Flood regions of the vertices off all curves: (region per vertex or NONE, count).
pub fn regions(mesh: &Mesh, cuts: &Cuts) -> (Vec<u32>, usize) {
    let free = |v: u32| !cuts.is_node[v as usize] && cuts.on_curve[v as usize] == NONE && !mesh.is_isolated(v);
    vertex_regions(mesh, free, |h| !cuts.crossed[mesh.edge(h) as usize])
}

/// The triangle holding two consecutive curve points; along a mesh edge, the one on the
/// left of the direction `a → b`.
fn segment_triangle(mesh: &Mesh, a: &CurvePoint, b: &CurvePoint) -> Option<u32> {
    if let (CurvePoint::Vertex(u), CurvePoint::Vertex(v)) = (a, b) {
        return mesh.find_halfedge(*u, *v).map(|h| mesh.face(h)).filter(|&f| f != NONE);
    }
    super::curve::common_face(mesh, a, b)
}

/// A piece of a curve inside one triangle.
struct Segment {
    curve: u32,
    /// Index of its first point in the curve.
    index: usize,
    a: [f64; 3],
    b: [f64; 3],
}

/// The curve segments inside each triangle, so a vertex can be tested for being separated
/// from a curve by another curve that runs through the same triangle.
pub struct SegmentIndex {
    by_face: std::collections::HashMap<u32, Vec<Segment>>,
}

impl SegmentIndex {
    pub fn new(mesh: &Mesh, curves: &[(CurveNodes, &Curve)]) -> SegmentIndex {
        let mut by_face: std::collections::HashMap<u32, Vec<Segment>> = Default::default();
        for (c, (_, curve)) in curves.iter().enumerate() {
            for (k, w) in curve.points.windows(2).enumerate() {
                if let Some(f) = segment_triangle(mesh, &w[0], &w[1]) {
                    let (a, b) = (position(mesh, &w[0]), position(mesh, &w[1]));
                    by_face.entry(f).or_default().push(Segment { curve: c as u32, index: k, a, b });
                }
            }
        }
        SegmentIndex { by_face }
    }

    /// Whether the straight way from `from` to `to` inside triangle `f` (with normal `n`)
    /// crosses a curve segment other than segment `index` of curve `curve`.
    fn blocked(&self, f: u32, n: [f64; 3], curve: u32, index: usize, from: [f64; 3], to: [f64; 3]) -> bool {
        let orient = |p: [f64; 3], q: [f64; 3], r: [f64; 3]| dot(n, cross(sub(q, p), sub(r, p)));
        self.by_face.get(&f).is_some_and(|segs| {
            segs.iter().filter(|s| !(s.curve == curve && s.index == index)).any(|s| {
                let (d1, d2) = (orient(s.a, s.b, from), orient(s.a, s.b, to));
                let (d3, d4) = (orient(from, to, s.a), orient(from, to, s.b));
                d1 * d2 <= 0.0 && d3 * d4 <= 0.0
            })
        })
    }
}

/// Vertices of the triangles along a curve that lie on its left (`forward`) or right, with
/// no other curve in between.
pub fn left_vertices(mesh: &Mesh, index: &SegmentIndex, c: u32, curve: &Curve, forward: bool, out: &mut Vec<u32>) {
    for (k, w) in curve.points.windows(2).enumerate() {
        // Along a mesh edge, the triangle on the left of the direction the face runs it.
        let (p, q) = if forward { (&w[0], &w[1]) } else { (&w[1], &w[0]) };
        let Some(f) = segment_triangle(mesh, p, q) else { continue };
        let tri = mesh.triangles()[f as usize];
        let [p0, p1, p2] = tri.map(|v| mesh.position(v));
        let normal = cross(sub(p1, p0), sub(p2, p0));
        let (mut pa, mut pb) = (position(mesh, &w[0]), position(mesh, &w[1]));
        if !forward {
            std::mem::swap(&mut pa, &mut pb);
        }
        let mid: [f64; 3] = std::array::from_fn(|i| 0.5 * (pa[i] + pb[i]));
        for v in tri {
            let x = mesh.position(v);
            if dot(normal, cross(sub(pb, pa), sub(x, pa))) > 0.0 && !index.blocked(f, normal, c, k, mid, x) {
                out.push(v);
            }
        }
    }
}

/// For each face (given by its directed pieces), the flood regions on the left of them.
pub fn face_regions(
    mesh: &Mesh,
    curves: &[(CurveNodes, &Curve)],
    faces: &[Vec<Directed>],
    region: &[u32],
) -> Vec<Vec<u32>> {
    let index = SegmentIndex::new(mesh, curves);
    let mut buf = Vec::new();
    faces
        .iter()
        .map(|pieces| {
            buf.clear();
            for d in pieces {
                left_vertices(mesh, &index, d.curve, curves[d.curve as usize].1, d.forward, &mut buf);
            }
            let mut r: Vec<u32> = buf.iter().map(|&v| region[v as usize]).filter(|&r| r != NONE).collect();
            r.sort_unstable();
            r.dedup();
            r
        })
        .collect()
}

/// Euler characteristic of the part of the mesh spanned by each flood region (its
/// vertices, the uncut edges and the uncut triangles between them). A disk has 1.
pub fn region_euler(mesh: &Mesh, cuts: &Cuts, region: &[u32], count: usize) -> Vec<i64> {
    let mut chi = vec![0i64; count];
    for &r in region.iter().filter(|&&r| r != NONE) {
        chi[r as usize] += 1;
    }
    // The region of an edge or triangle whose vertices all lie in one region.
    let common = |vs: &[u32]| {
        let r = region[vs[0] as usize];
        (r != NONE && vs.iter().all(|&v| region[v as usize] == r)).then_some(r as usize)
    };
    for edge in 0..mesh.n_edges() as u32 {
        let h = 2 * edge;
        if !cuts.crossed[edge as usize] {
            if let Some(r) = common(&[mesh.from_vertex(h), mesh.to_vertex(h)]) {
                chi[r] -= 1;
            }
        }
    }
    for (fi, t) in mesh.triangles().iter().enumerate() {
        let h = mesh.face_halfedge(fi as u32, 0);
        let cut = [h, mesh.next(h), mesh.prev(h)].iter().any(|&h| cuts.crossed[mesh.edge(h) as usize]);
        if let (Some(r), false) = (common(t), cut) {
            chi[r] += 1;
        }
    }
    chi
}
