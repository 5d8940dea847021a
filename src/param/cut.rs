//! The mesh refined along the layout curves, so that every curve runs along mesh edges.
//!
//! The paper lets layout edges cross triangles (Fig. 3, 6a) and couples the two sides of
//! each crossed edge through transitions, with alignment rows on interpolated points (eq.
//! 11). We insert a vertex at every crossing instead and split the crossed triangles: then
//! every triangle lies in exactly one face, a crossing point is a vertex whose alignment is
//! a constraint on that vertex alone, and the three-faces-in-one-triangle case near nodes
//! (method-notes §1) cannot arise. The split adds only vertices on the curves; each new
//! triangle is a flat piece of an input triangle, so the surface is unchanged.

use crate::layout::curve::{common_face, position, CurvePoint};
use crate::layout::SurfaceLayout;
use crate::geom::{cross, dot, norm, sub};
use crate::mesh::{Mesh, NONE};
use std::collections::HashMap;

/// The refined mesh and what each of its elements is in the layout.
#[derive(Debug, Clone)]
pub struct CutMesh {
    /// The input's vertices (same indices), then one vertex per curve crossing.
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// The layout face each triangle lies in.
    pub triangle_face: Vec<u32>,
    /// The input triangle each triangle is a piece of.
    pub triangle_origin: Vec<u32>,
    /// The curve running through each vertex ([`NONE`] for nodes and vertices off curves).
    pub vertex_curve: Vec<u32>,
    /// The node at each vertex, or [`NONE`].
    pub vertex_node: Vec<u32>,
    /// The face every vertex belongs to ([`NONE`] for nodes and unused vertices): a vertex
    /// on a curve belongs to the face on the curve's left.
    pub vertex_face: Vec<u32>,
    /// Per curve: its vertices in order, from its first node to its last.
    pub curve_vertices: Vec<Vec<u32>>,
}

impl CutMesh {
    /// Whether vertex `v` lies on the layout: on a curve, or at a node.
    pub fn on_layout(&self, v: u32) -> bool {
        self.vertex_curve[v as usize] != NONE || self.vertex_node[v as usize] != NONE
    }
}

/// The faces on the left and right of every curve ([`NONE`] right of a boundary piece).
pub fn curve_sides(layout: &SurfaceLayout) -> Vec<[u32; 2]> {
    let mut sides = vec![[NONE, NONE]; layout.curves.len()];
    for (fi, f) in layout.faces.iter().enumerate() {
        for d in &f.pieces {
            sides[d.curve as usize][if d.forward { 0 } else { 1 }] = fi as u32;
        }
    }
    sides
}

/// Splits the mesh along the layout's curves.
pub fn cut_mesh(mesh: &Mesh, layout: &SurfaceLayout) -> CutMesh {
    let n = mesh.n_vertices();
    let sides = curve_sides(layout);
    let mut positions = mesh.positions().to_vec();
    let mut vertex_curve = vec![NONE; n];
    let mut vertex_node = vec![NONE; n];
    for (i, &v) in layout.node_vertex.iter().enumerate() {
        vertex_node[v as usize] = i as u32;
    }
    // Every curve point gets a vertex id; crossings become new vertices.
    let mut curve_vertices = Vec::with_capacity(layout.curves.len());
    let mut on_edge: HashMap<u32, Vec<(f64, u32)>> = HashMap::new();
    for (c, lc) in layout.curves.iter().enumerate() {
        let ids: Vec<u32> = lc
            .curve
            .points
            .iter()
            .map(|p| match *p {
                CurvePoint::Vertex(v) => {
                    if vertex_node[v as usize] == NONE {
                        vertex_curve[v as usize] = c as u32;
                    }
                    v
                }
                CurvePoint::Edge { edge, t } => {
                    let id = positions.len() as u32;
                    positions.push(position(mesh, p));
                    vertex_curve.push(c as u32);
                    vertex_node.push(NONE);
                    on_edge.entry(edge).or_default().push((t, id));
                    id
                }
            })
            .collect();
        curve_vertices.push(ids);
    }
    // Curve segments by their end vertices: (curve, whether the curve runs a → b).
    let mut segment: HashMap<(u32, u32), (u32, bool)> = HashMap::new();
    let mut chords_in: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for (c, lc) in layout.curves.iter().enumerate() {
        let ids = &curve_vertices[c];
        for k in 0..ids.len() - 1 {
            let (a, b) = (ids[k], ids[k + 1]);
            segment.insert((a, b), (c as u32, true));
            segment.insert((b, a), (c as u32, false));
            let (p, q) = (&lc.curve.points[k], &lc.curve.points[k + 1]);
            let along_edge = matches!((p, q), (CurvePoint::Vertex(_), CurvePoint::Vertex(_)));
            if !along_edge {
                if let Some(f) = common_face(mesh, p, q) {
                    chords_in.entry(f).or_default().push((a, b));
                }
            }
        }
    }

    let mut out = CutMesh {
        positions,
        triangles: Vec::with_capacity(mesh.n_faces() + 4 * chords_in.len()),
        triangle_face: Vec::new(),
        triangle_origin: Vec::new(),
        vertex_curve,
        vertex_node,
        vertex_face: Vec::new(),
        curve_vertices,
    };
    let vertex_face: Vec<u32> = (0..out.positions.len())
        .map(|v| {
            if v < n {
                layout.vertex_face[v]
            } else {
                sides[out.vertex_curve[v] as usize][0]
            }
        })
        .collect();
    // Most triangles lie inside a face: no curve crosses or runs along them. They are kept
    // as they are (without the general path's hashing and allocations).
    let mut crossed = vec![false; mesh.n_edges()];
    for &e in on_edge.keys() {
        crossed[e as usize] = true;
    }
    for f in 0..mesh.n_faces() as u32 {
        let corners = [0, 1, 2].map(|k| mesh.from_vertex(mesh.face_halfedge(f, k)));
        let inside = (0..3).all(|k| !crossed[mesh.edge(mesh.face_halfedge(f, k)) as usize])
            && !corners.iter().any(|&v| out.on_layout(v))
            && !chords_in.contains_key(&f);
        if inside {
            if has_area(&out.positions, corners) {
                let face = off_curve_face(&corners, &vertex_face, &out.vertex_curve, n);
                out.triangles.push(corners);
                out.triangle_face.push(face.unwrap_or(layout.triangle_face[f as usize]));
                out.triangle_origin.push(f);
            }
            continue;
        }
        let boundary = triangle_boundary(mesh, f, &on_edge);
        let chords = chords_in.get(&f).map(Vec::as_slice).unwrap_or(&[]);
        for piece in split(boundary, chords) {
            let face = piece_face(&piece, &segment, &sides, &vertex_face, &out.vertex_curve, n)
                .unwrap_or(layout.triangle_face[f as usize]);
            for t in triangulate(&piece, &out.positions) {
                out.triangles.push(t);
                out.triangle_face.push(face);
                out.triangle_origin.push(f);
            }
        }
    }
    out.vertex_face = vertex_face;
    split_chords(&mut out, &segment, &chart_sides(layout));
    out
}

/// The chart sides each layout vertex lies on, per face: bit s for side s (0..4, from corner
/// s to corner s + 1). A curve lies on one side of each of its faces; a node on the side it
/// is a T-vertex of, or on the two that meet at it as a corner.
struct ChartSides {
    curve: HashMap<(u32, u32), u8>,
    node: HashMap<(u32, u32), u8>,
}

impl ChartSides {
    /// The sides of face `face` that vertex `v` of `out` lies on (none if it is off the layout).
    fn of(&self, out: &CutMesh, v: u32, face: u32) -> u8 {
        let (c, n) = (out.vertex_curve[v as usize], out.vertex_node[v as usize]);
        if n != NONE {
            self.node.get(&(n, face)).copied().unwrap_or(0)
        } else if c != NONE {
            self.curve.get(&(c, face)).copied().unwrap_or(0)
        } else {
            0
        }
    }
}

fn chart_sides(layout: &SurfaceLayout) -> ChartSides {
    let mut sides = ChartSides { curve: HashMap::new(), node: HashMap::new() };
    for (f, face) in layout.faces.iter().enumerate() {
        let f = f as u32;
        for (k, (piece, &node)) in face.pieces.iter().zip(&face.nodes).enumerate() {
            let s = face.corners.iter().rposition(|&c| c <= k).unwrap_or(0);
            let bits = if face.corners.contains(&k) { 1 << s | 1 << ((s + 3) % 4) } else { 1 << s };
            *sides.curve.entry((piece.curve, f)).or_default() |= 1 << s;
            *sides.node.entry((node, f)).or_default() |= bits;
        }
    }
    sides
}

/// Splits at its midpoint every edge inside a face between two vertices on one side of its
/// chart (a chord of that side): Tutte's condition for a harmonic map into a convex chart to
/// be an embedding. A triangle whose three vertices lie on one chart side, as where a curve
/// runs along two edges of a triangle or past a T-vertex with a triangle on both of its
/// pieces, is otherwise squeezed to a line by the side's straightness: on bunny_28k's
/// automatic layout, all 8 triangles still flipped after the curves were kept in order were
/// such. The midpoint is a vertex of the face, placed off the side by the solve. The surface
/// is unchanged (the chord is an input edge or lies in an input triangle).
///
/// Chords between two sides are left: their triangles have area in the chart, and next to a
/// corner whose surface angle is near 180° their midpoint would sit almost on the corner,
/// in triangles so obtuse that their negative weights fold them (bunny-ears' loop flipped 17
/// triangles when every chord was split).
fn split_chords(out: &mut CutMesh, segment: &HashMap<(u32, u32), (u32, bool)>, sides: &ChartSides) {
    let chord = |a: u32, b: u32| out.on_layout(a) && out.on_layout(b) && !segment.contains_key(&(a, b));
    let mut holder: HashMap<(u32, u32), usize> = HashMap::new();
    for (t, tri) in out.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if chord(a, b) {
                holder.insert((a, b), t);
            }
        }
    }
    let mut chords: Vec<(u32, u32)> = holder.keys().copied().filter(|&(a, b)| a < b && holder.contains_key(&(b, a))).collect();
    chords.sort_unstable();
    for (a, b) in chords {
        let (t1, t2) = (holder[&(a, b)], holder[&(b, a)]);
        let face = out.triangle_face[t1];
        if out.triangle_face[t2] != face || sides.of(out, a, face) & sides.of(out, b, face) == 0 {
            continue;
        }
        let m = out.positions.len() as u32;
        let (pa, pb) = (out.positions[a as usize], out.positions[b as usize]);
        out.positions.push(std::array::from_fn(|k| 0.5 * (pa[k] + pb[k])));
        out.vertex_curve.push(NONE);
        out.vertex_node.push(NONE);
        out.vertex_face.push(face);
        // t1 = (a, b, p) becomes (a, m, p) and (m, b, p); t2 = (b, a, q), (b, m, q) and (m, a, q).
        for (t, x, y) in [(t1, a, b), (t2, b, a)] {
            let tri = out.triangles[t];
            let k = (0..3).find(|&k| tri[k] == x).unwrap_or(0);
            let p = tri[(k + 2) % 3];
            out.triangles[t] = [x, m, p];
            out.triangles.push([m, y, p]);
            out.triangle_face.push(face);
            out.triangle_origin.push(out.triangle_origin[t]);
            if let Some(h) = holder.get_mut(&(y, p)) {
                *h = out.triangles.len() - 1;
            }
        }
    }
}

/// The boundary of input triangle `f`, counter-clockwise: its corners with the crossing
/// vertices on each side in order.
fn triangle_boundary(mesh: &Mesh, f: u32, on_edge: &HashMap<u32, Vec<(f64, u32)>>) -> Vec<u32> {
    let mut out = Vec::with_capacity(6);
    for k in 0..3 {
        let h = mesh.face_halfedge(f, k);
        out.push(mesh.from_vertex(h));
        if let Some(cross) = on_edge.get(&mesh.edge(h)) {
            // t runs along halfedge 2e; measure it from this side's start.
            let forward = h.is_multiple_of(2);
            let mut pts: Vec<(f64, u32)> =
                cross.iter().map(|&(t, id)| (if forward { t } else { 1.0 - t }, id)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            out.extend(pts.into_iter().map(|(_, id)| id));
        }
    }
    out
}

/// Splits a convex polygon (vertex ids, counter-clockwise) along chords between its
/// boundary points. Chords do not cross (curves meet only at nodes).
fn split(boundary: Vec<u32>, chords: &[(u32, u32)]) -> Vec<Vec<u32>> {
    let mut pieces = vec![boundary];
    for &(a, b) in chords {
        let Some(i) = pieces.iter().position(|p| p.contains(&a) && p.contains(&b)) else { continue };
        let p = pieces.swap_remove(i);
        let ia = p.iter().position(|&x| x == a).unwrap_or(0);
        let ib = p.iter().position(|&x| x == b).unwrap_or(0);
        let walk = |from: usize, to: usize| {
            let mut v = Vec::new();
            let mut k = from;
            loop {
                v.push(p[k]);
                if k == to {
                    break;
                }
                k = (k + 1) % p.len();
            }
            v
        };
        for piece in [walk(ia, ib), walk(ib, ia)] {
            if piece.len() >= 3 {
                pieces.push(piece);
            }
        }
    }
    pieces
}

/// The face a piece lies in: left or right of a curve segment on its boundary (the piece is
/// on the left of its counter-clockwise boundary), else the face of a vertex off the curves.
fn piece_face(
    piece: &[u32],
    segment: &HashMap<(u32, u32), (u32, bool)>,
    sides: &[[u32; 2]],
    vertex_face: &[u32],
    vertex_curve: &[u32],
    n_input: usize,
) -> Option<u32> {
    for k in 0..piece.len() {
        let (a, b) = (piece[k], piece[(k + 1) % piece.len()]);
        if let Some(&(c, forward)) = segment.get(&(a, b)) {
            let f = sides[c as usize][if forward { 0 } else { 1 }];
            if f != NONE {
                return Some(f);
            }
        }
    }
    off_curve_face(piece, vertex_face, vertex_curve, n_input)
}

/// The face of the first of `vertices` that is an input vertex off the curves, if any.
fn off_curve_face(vertices: &[u32], vertex_face: &[u32], vertex_curve: &[u32], n_input: usize) -> Option<u32> {
    vertices
        .iter()
        .find(|&&v| (v as usize) < n_input && vertex_curve[v as usize] == NONE && vertex_face[v as usize] != NONE)
        .map(|&v| vertex_face[v as usize])
}

/// The smallest corner angle of triangle `t` (0 for a degenerate one).
fn min_angle(positions: &[[f64; 3]], t: [u32; 3]) -> f64 {
    corners(positions, t).iter().map(|&(x, y, z)| corner_sine(x, y, z).atan2(dot(sub(y, x), sub(z, x)))).fold(f64::INFINITY, f64::min)
}

/// Triangle `t`'s three corners, each as (corner, next, previous) positions.
fn corners(positions: &[[f64; 3]], t: [u32; 3]) -> [([f64; 3], [f64; 3], [f64; 3]); 3] {
    let [pa, pb, pc] = t.map(|v| positions[v as usize]);
    [(pa, pb, pc), (pb, pc, pa), (pc, pa, pb)]
}

/// |u × w| for the edges u = y − x, w = z − x at corner x (zero if and only if the corner
/// angle is 0 or π).
fn corner_sine(x: [f64; 3], y: [f64; 3], z: [f64; 3]) -> f64 {
    norm(cross(sub(y, x), sub(z, x)))
}

/// Whether triangle `t` has area: [`min_angle`] > 0, without its arc tangents when no
/// corner is straight or flat (the common case).
fn has_area(positions: &[[f64; 3]], t: [u32; 3]) -> bool {
    corners(positions, t).iter().all(|&(x, y, z)| corner_sine(x, y, z) > 0.0)
        || min_angle(positions, t) > 0.0
}

/// Triangulates a convex polygon whose sides may hold collinear points, by clipping the ear
/// with the largest smallest angle first (no zero-area triangles while a proper ear exists).
fn triangulate(piece: &[u32], positions: &[[f64; 3]]) -> Vec<[u32; 3]> {
    let mut poly = piece.to_vec();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    let min_angle = |a: u32, b: u32, c: u32| min_angle(positions, [a, b, c]);
    while poly.len() > 3 {
        let m = poly.len();
        let best = (0..m)
            .map(|i| (i, min_angle(poly[(i + m - 1) % m], poly[i], poly[(i + 1) % m])))
            .max_by(|x, y| x.1.total_cmp(&y.1));
        let Some((i, angle)) = best else { break };
        if angle <= 0.0 {
            break; // the rest is collinear: no area left
        }
        out.push([poly[(i + m - 1) % m], poly[i], poly[(i + 1) % m]]);
        poly.remove(i);
    }
    if poly.len() == 3 && has_area(positions, [poly[0], poly[1], poly[2]]) {
        out.push([poly[0], poly[1], poly[2]]);
    }
    out
}
