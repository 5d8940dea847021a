//! Building a [`Mesh`] from a triangle soup: validation, safe repairs, halfedges.
//!
//! Preconditions checked, each a [`MeshError`] naming the element: finite coordinates,
//! indices in range, three distinct vertices per face, at most two faces per edge, faces on
//! an edge oriented consistently, one fan of faces per vertex.
//!
//! The one repair made: faces of zero area are dropped when the rest is still a valid
//! mesh (they carry no surface, and their cotangent weights would be infinite). Vertex
//! indices never change, because layouts refer to vertices by their index in the file.

use super::{Mesh, NONE};
use std::fmt;

/// Vertices and triangles as read from a file, before any validation.
#[derive(Debug, Clone, Default)]
pub struct TriangleSoup {
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Repairs the reader already made (STL welding).
    pub repairs: Repairs,
}

/// Repairs made on the way from file to mesh. Welding, zero-area faces and unreferenced
/// vertices never change the surface; dropped components and filled holes are made only when
/// the user asks ([`RepairOptions`](super::RepairOptions)).
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize)]
pub struct Repairs {
    /// Vertices merged because they had exactly the same coordinates (STL stores no shared
    /// vertices).
    pub welded_vertices: usize,
    /// Faces dropped because their area is zero (up to rounding).
    pub removed_zero_area_faces: usize,
    /// Vertices that no face uses; they keep their index and are otherwise ignored.
    pub unreferenced_vertices: usize,
    /// Connected components dropped because the user kept only the largest
    /// ([`repair_mesh`](super::repair::repair_mesh)), and their triangles.
    pub removed_components: usize,
    pub removed_component_faces: usize,
    /// Boundary loops closed because the user asked to fill holes, and the vertices added.
    pub filled_holes: usize,
    pub fill_vertices: usize,
    /// How many times every triangle was split into four because the mesh was coarse
    /// ([`refine_coarse`](super::refine_coarse)), and the vertices and triangles it had
    /// before.
    pub refinements: usize,
    pub vertices_before_refinement: usize,
    pub triangles_before_refinement: usize,
}

impl Repairs {
    pub fn is_empty(&self) -> bool {
        *self == Repairs::default()
    }
}

/// A validated mesh with what was repaired on the way.
#[derive(Debug, Clone)]
pub struct BuiltMesh {
    pub mesh: Mesh,
    pub repairs: Repairs,
    /// For each triangle of the mesh, its index in the soup (differs after removals).
    pub soup_face: Vec<u32>,
}

/// Why a triangle soup is not a mesh quadlay can work on. Face indices count the soup's
/// triangles (after readers split polygons); readers add the file's own face or line.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    NoVertices,
    NoFaces,
    /// Every one of the `triangles` faces has zero area (so none is left).
    AllZeroArea { triangles: usize },
    NonFinite { vertex: u32 },
    IndexOutOfRange { face: u32, index: u32, vertices: usize },
    RepeatedVertex { face: u32, vertex: u32 },
    /// More than two faces share the edge `(a, b)`.
    NonManifoldEdge { a: u32, b: u32, faces: Vec<u32> },
    /// Two faces traverse the edge `(a, b)` in the same direction.
    InconsistentOrientation { a: u32, b: u32, faces: [u32; 2] },
    /// The faces around the vertex form more than one fan.
    NonManifoldVertex { vertex: u32 },
}

impl MeshError {
    /// The soup face the error is about, if any (readers translate it to a file location).
    pub fn face(&self) -> Option<u32> {
        match self {
            MeshError::IndexOutOfRange { face, .. } | MeshError::RepeatedVertex { face, .. } => {
                Some(*face)
            }
            MeshError::NonManifoldEdge { faces, .. } => faces.first().copied(),
            MeshError::InconsistentOrientation { faces, .. } => Some(faces[1]),
            _ => None,
        }
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::NoVertices => write!(f, "the mesh has no vertices"),
            MeshError::NoFaces => write!(f, "the mesh has no faces"),
            MeshError::AllZeroArea { triangles } => write!(
                f,
                "the mesh has no faces of non-zero area: all {triangles} triangles, from triangle 0 on, are flat \
                 (their corners lie on one line)"
            ),
            MeshError::NonFinite { vertex } => {
                write!(f, "vertex {vertex} has a coordinate that is not a finite number")
            }
            MeshError::IndexOutOfRange { face, index, vertices } => write!(
                f,
                "triangle {face} refers to vertex {index}, but there are only {vertices} vertices"
            ),
            MeshError::RepeatedVertex { face, vertex } => {
                write!(f, "triangle {face} uses vertex {vertex} more than once")
            }
            MeshError::NonManifoldEdge { a, b, faces } => {
                let list: Vec<String> = faces.iter().map(|x| x.to_string()).collect();
                write!(
                    f,
                    "non-manifold edge between vertices {a} and {b}: shared by triangles {}",
                    list.join(", ")
                )
            }
            MeshError::InconsistentOrientation { a, b, faces } => write!(
                f,
                "inconsistent orientation: triangles {} and {} both run from vertex {a} to vertex {b}",
                faces[0], faces[1]
            ),
            MeshError::NonManifoldVertex { vertex } => write!(
                f,
                "non-manifold vertex {vertex}: its faces form more than one fan"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

/// Validates `soup` and builds its halfedge mesh, dropping faces of zero area.
///
/// # Errors
/// Any [`MeshError`]; see the module documentation.
pub fn build_mesh(soup: TriangleSoup) -> Result<BuiltMesh, MeshError> {
    let TriangleSoup { positions, triangles, mut repairs } = soup;
    if positions.is_empty() {
        return Err(MeshError::NoVertices);
    }
    if let Some(v) = positions.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(MeshError::NonFinite { vertex: v as u32 });
    }
    if positions.len() >= NONE as usize {
        return Err(MeshError::IndexOutOfRange {
            face: 0,
            index: NONE,
            vertices: positions.len(),
        });
    }
    for (f, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            if t[k] as usize >= positions.len() {
                let vertices = positions.len();
                return Err(MeshError::IndexOutOfRange { face: f as u32, index: t[k], vertices });
            }
            if t[k] == t[(k + 1) % 3] {
                return Err(MeshError::RepeatedVertex { face: f as u32, vertex: t[k] });
            }
        }
    }
    let mut kept = Vec::with_capacity(triangles.len());
    let mut soup_face = Vec::with_capacity(triangles.len());
    for (f, t) in triangles.iter().enumerate() {
        if has_zero_area(&positions, t) {
            repairs.removed_zero_area_faces += 1;
        } else {
            kept.push(*t);
            soup_face.push(f as u32);
        }
    }
    if kept.is_empty() {
        return Err(if triangles.is_empty() { MeshError::NoFaces } else { MeshError::AllZeroArea { triangles: triangles.len() } });
    }
    let mesh = connect(positions, kept, &soup_face)?;
    repairs.unreferenced_vertices = mesh.vertex_out.iter().filter(|&&h| h == NONE).count();
    Ok(BuiltMesh { mesh, repairs, soup_face })
}

/// Zero area up to the rounding of the cross product, relative to the longest edge. The
/// edges are first divided by their largest coordinate, so the test is the same at every
/// scale: squared lengths of a mesh in units of 1e-80 (or 1e80) would underflow (overflow).
fn has_zero_area(p: &[[f64; 3]], t: &[u32; 3]) -> bool {
    // Halved, so that differences of coordinates near ±f64::MAX stay finite.
    let [a, b, c] = t.map(|i| p[i as usize].map(|x| 0.5 * x));
    let (u, v, w) = (sub(b, a), sub(c, a), sub(c, b));
    let scale = u.iter().chain(&v).chain(&w).fold(0.0f64, |m, x| m.max(x.abs()));
    if scale == 0.0 {
        return true;
    }
    let unit = |x: [f64; 3]| x.map(|c| c / scale);
    let (u, v, w) = (unit(u), unit(v), unit(w));
    let cr = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let cross2 = dot(cr, cr);
    let longest2 = dot(u, u).max(dot(v, v)).max(dot(w, w));
    cross2.sqrt() <= 8.0 * f64::EPSILON * longest2
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Halfedge construction. Face corners `c = 3f + k` stand for the directed edge from
/// `triangles[f][k]` to `triangles[f][k+1]`; corners are bucketed by their source vertex
/// so the opposite corner of each edge is found without hashing.
/// The corners of `triangles` (corner `c` is vertex `c % 3` of triangle `c / 3`) bucketed by
/// vertex, as compressed rows: vertex `v`'s corners, in increasing order, are
/// `corners[start[v]..start[v + 1]]` (`start` has `n_vertices + 1` entries).
pub fn corners_by_vertex(n_vertices: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n_vertices + 1];
    for &v in triangles.iter().flatten() {
        start[v as usize + 1] += 1;
    }
    for v in 0..n_vertices {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut corners = vec![0u32; 3 * triangles.len()];
    for (c, &v) in triangles.iter().flatten().enumerate() {
        corners[fill[v as usize] as usize] = c as u32;
        fill[v as usize] += 1;
    }
    (start, corners)
}

fn connect(
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    soup_face: &[u32],
) -> Result<Mesh, MeshError> {
    let nv = positions.len();
    let nc = triangles.len() * 3;
    let corner_from = |c: usize| triangles[c / 3][c % 3];
    let corner_to = |c: usize| triangles[c / 3][(c % 3 + 1) % 3];

    // Corners bucketed by source vertex (CSR).
    let (start, mut by_source) = corners_by_vertex(nv, &triangles);
    // Sorted by target, so the corners of one directed edge are found by binary search
    // (a plain scan is quadratic at vertices of huge valence, e.g. big PLY polygons).
    for v in 0..nv {
        by_source[start[v] as usize..start[v + 1] as usize].sort_unstable_by_key(|&c| corner_to(c as usize));
    }
    let corners_from_to = |a: u32, b: u32| {
        let s = &by_source[start[a as usize] as usize..start[a as usize + 1] as usize];
        let lo = s.partition_point(|&c| corner_to(c as usize) < b);
        let hi = s.partition_point(|&c| corner_to(c as usize) <= b);
        &s[lo..hi]
    };

    let soup = |c: usize| soup_face[c / 3];
    let mut corner_he = vec![NONE; nc];
    let mut he_to: Vec<u32> = Vec::with_capacity(nc + nc / 8);
    let mut he_face: Vec<u32> = Vec::with_capacity(nc + nc / 8);
    for c in 0..nc {
        if corner_he[c] != NONE {
            continue;
        }
        let (a, b) = (corner_from(c), corner_to(c));
        let same: Vec<usize> =
            corners_from_to(a, b).iter().map(|&x| x as usize).filter(|&x| x != c).collect();
        let opposite: Vec<usize> = corners_from_to(b, a).iter().map(|&x| x as usize).collect();
        if 1 + same.len() + opposite.len() > 2 {
            let mut faces: Vec<u32> = std::iter::once(c)
                .chain(same.iter().copied())
                .chain(opposite.iter().copied())
                .map(soup)
                .collect();
            faces.sort_unstable();
            return Err(MeshError::NonManifoldEdge { a: a.min(b), b: a.max(b), faces });
        }
        if let Some(&other) = same.first() {
            return Err(MeshError::InconsistentOrientation { a, b, faces: [soup(c), soup(other)] });
        }
        let h = he_to.len() as u32;
        corner_he[c] = h;
        he_to.push(b);
        he_face.push((c / 3) as u32);
        he_to.push(a);
        match opposite.first() {
            Some(&o) => {
                corner_he[o] = h + 1;
                he_face.push((o / 3) as u32);
            }
            None => he_face.push(NONE),
        }
    }

    let nh = he_to.len();
    let mut he_next = vec![NONE; nh];
    let mut he_prev = vec![NONE; nh];
    for c in 0..nc {
        let f = c / 3;
        let n = corner_he[3 * f + (c % 3 + 1) % 3];
        he_next[corner_he[c] as usize] = n;
        he_prev[n as usize] = corner_he[c];
    }
    // Boundary halfedges: at a manifold vertex exactly one leaves along the boundary.
    let mut boundary_out = vec![NONE; nv];
    for h in 0..nh {
        if he_face[h] == NONE {
            let from = he_to[h ^ 1] as usize;
            if boundary_out[from] != NONE {
                return Err(MeshError::NonManifoldVertex { vertex: from as u32 });
            }
            boundary_out[from] = h as u32;
        }
    }
    for h in 0..nh {
        if he_face[h] == NONE {
            let n = boundary_out[he_to[h] as usize];
            he_next[h] = n;
            he_prev[n as usize] = h as u32;
        }
    }
    let mut vertex_out = boundary_out;
    let mut degree = vec![0u32; nv];
    for h in (0..nh).step_by(2) {
        degree[he_to[h] as usize] += 1;
        degree[he_to[h + 1] as usize] += 1;
    }
    for c in 0..nc {
        let a = corner_from(c) as usize;
        if vertex_out[a] == NONE {
            vertex_out[a] = corner_he[c];
        }
    }
    let face_he = (0..triangles.len()).map(|f| corner_he[3 * f]).collect();
    let mesh = Mesh { positions, triangles, he_to, he_next, he_prev, he_face, vertex_out, face_he };

    // One fan per vertex: circulation from one outgoing halfedge must meet every edge.
    for v in 0..nv as u32 {
        if mesh.vertex_out[v as usize] == NONE {
            continue;
        }
        let d = degree[v as usize] as usize;
        if mesh.outgoing(v).take(d + 1).count() != d {
            return Err(MeshError::NonManifoldVertex { vertex: v });
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> TriangleSoup {
        TriangleSoup { positions, triangles, repairs: Repairs::default() }
    }

    fn square() -> TriangleSoup {
        soup(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn square_has_halfedges_that_close_up() {
        let m = build_mesh(square()).unwrap().mesh;
        assert_eq!(m.n_edges(), 5);
        for h in 0..m.n_halfedges() as u32 {
            assert_eq!(m.prev(m.next(h)), h);
            assert_eq!(m.from_vertex(m.next(h)), m.to_vertex(h));
        }
        for v in 0..4 {
            assert!(m.is_boundary_vertex(v));
        }
        assert_eq!(m.valence(0), 3);
        assert_eq!(m.valence(1), 2);
        assert_eq!(m.face_halfedge(1, 0), m.find_halfedge(0, 2).unwrap());
    }

    #[test]
    fn zero_area_face_is_removed_and_reported() {
        let mut s = square();
        s.positions.push([0.5, 0.0, 0.0]);
        s.triangles = vec![[0, 4, 2], [4, 1, 2], [0, 2, 3], [0, 1, 4]];
        // face 3 is flat: 0, 1 and 4 are collinear. It leaves a zero-width slit, still manifold.
        let b = build_mesh(s).unwrap();
        assert_eq!(b.repairs.removed_zero_area_faces, 1);
        assert_eq!(b.mesh.n_faces(), 3);
        assert_eq!(b.soup_face, vec![0, 1, 2]);
    }

    #[test]
    fn errors_name_the_element() {
        let mut s = square();
        s.triangles[1] = [0, 3, 2];
        assert_eq!(
            build_mesh(s).unwrap_err(),
            MeshError::InconsistentOrientation { a: 2, b: 0, faces: [0, 1] }
        );
        let mut s = square();
        s.positions[2][1] = f64::NAN;
        assert_eq!(build_mesh(s).unwrap_err(), MeshError::NonFinite { vertex: 2 });
        let mut s = square();
        s.triangles[1] = [0, 2, 9];
        assert!(matches!(build_mesh(s), Err(MeshError::IndexOutOfRange { face: 1, index: 9, .. })));
        let mut s = square();
        s.triangles[0] = [0, 1, 1];
        assert_eq!(build_mesh(s).unwrap_err(), MeshError::RepeatedVertex { face: 0, vertex: 1 });
    }

    #[test]
    fn three_faces_on_an_edge_are_non_manifold() {
        let mut s = square();
        s.positions.push([0.5, 0.5, 1.0]);
        s.triangles.push([0, 2, 4]);
        assert!(matches!(
            build_mesh(s),
            Err(MeshError::NonManifoldEdge { a: 0, b: 2, .. })
        ));
    }

    #[test]
    fn bowtie_vertex_is_non_manifold() {
        let s = soup(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(build_mesh(s).unwrap_err(), MeshError::NonManifoldVertex { vertex: 0 });
    }
}
