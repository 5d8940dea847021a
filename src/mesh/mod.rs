//! Triangle mesh with halfedge connectivity on index arrays.
//!
//! Every element is a `u32` handle; [`NONE`] stands for "no element". Edge `e` owns the
//! halfedges `2e` and `2e + 1`, so the twin of a halfedge is `h ^ 1` (pmp-library and
//! OpenMesh do the same). Boundary halfedges exist explicitly with face [`NONE`], which lets
//! circulation run across the boundary and boundary loops be walked with `next`.
//!
//! Connectivity lives here, geometry (lengths, angles, areas, cotangent weights) in
//! [`geometry`], global topology (components, boundary loops, genus) in [`topology`].
//! Meshes are made by [`build::build_mesh`], which validates and reports repairs.

pub mod adjacency;
pub mod build;
pub mod geometry;
pub mod primitives;
pub mod refine;
pub mod repair;
pub mod topology;

pub use build::{build_mesh, BuiltMesh, MeshError, Repairs, TriangleSoup};
pub use refine::refine_coarse;
pub use repair::{repair_mesh, RepairOptions};

/// The sentinel handle: no vertex, halfedge, edge or face.
pub const NONE: u32 = u32::MAX;

/// A 2-manifold, consistently oriented triangle mesh (possibly with boundary and with
/// unreferenced vertices, which belong to no face and are ignored by every algorithm).
#[derive(Debug, Clone)]
pub struct Mesh {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    /// Vertex a halfedge points to.
    he_to: Vec<u32>,
    he_next: Vec<u32>,
    he_prev: Vec<u32>,
    /// Face left of the halfedge, `NONE` on the boundary.
    he_face: Vec<u32>,
    /// One outgoing halfedge per vertex: the boundary one for boundary vertices, `NONE` for
    /// unreferenced vertices.
    vertex_out: Vec<u32>,
    /// The halfedge of face `f` that runs from `triangles[f][0]` to `triangles[f][1]`.
    face_he: Vec<u32>,
}

impl Mesh {
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    pub fn n_faces(&self) -> usize {
        self.triangles.len()
    }
    pub fn n_edges(&self) -> usize {
        self.he_to.len() / 2
    }
    pub fn n_halfedges(&self) -> usize {
        self.he_to.len()
    }
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    pub fn position(&self, v: u32) -> [f64; 3] {
        self.positions[v as usize]
    }
    /// Triangles as vertex triples, in the input's order and orientation.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    #[inline]
    pub fn twin(&self, h: u32) -> u32 {
        h ^ 1
    }
    #[inline]
    pub fn edge(&self, h: u32) -> u32 {
        h >> 1
    }
    /// Halfedge `0` or `1` of edge `e`.
    #[inline]
    pub fn edge_halfedge(&self, e: u32, side: u32) -> u32 {
        2 * e + side
    }
    #[inline]
    pub fn to_vertex(&self, h: u32) -> u32 {
        self.he_to[h as usize]
    }
    #[inline]
    pub fn from_vertex(&self, h: u32) -> u32 {
        self.he_to[(h ^ 1) as usize]
    }
    #[inline]
    pub fn next(&self, h: u32) -> u32 {
        self.he_next[h as usize]
    }
    #[inline]
    pub fn prev(&self, h: u32) -> u32 {
        self.he_prev[h as usize]
    }
    /// The face left of `h`, or [`NONE`] for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: u32) -> u32 {
        self.he_face[h as usize]
    }
    #[inline]
    pub fn is_boundary_halfedge(&self, h: u32) -> bool {
        self.he_face[h as usize] == NONE
    }
    pub fn is_boundary_edge(&self, e: u32) -> bool {
        self.is_boundary_halfedge(2 * e) || self.is_boundary_halfedge(2 * e + 1)
    }
    /// An outgoing halfedge of `v` (the boundary one if `v` is on the boundary), or [`NONE`].
    #[inline]
    pub fn vertex_halfedge(&self, v: u32) -> u32 {
        self.vertex_out[v as usize]
    }
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        let h = self.vertex_out[v as usize];
        h != NONE && self.is_boundary_halfedge(h)
    }
    pub fn is_isolated(&self, v: u32) -> bool {
        self.vertex_out[v as usize] == NONE
    }
    /// The halfedge of `f` leaving its `k`-th corner `triangles[f][k]`.
    #[inline]
    pub fn face_halfedge(&self, f: u32, k: usize) -> u32 {
        let mut h = self.face_he[f as usize];
        for _ in 0..k {
            h = self.next(h);
        }
        h
    }

    /// The outgoing halfedges of `v`, one ring around it; starts at the boundary halfedge
    /// for boundary vertices, so consecutive faces are neighbours across an edge.
    pub fn outgoing(&self, v: u32) -> Outgoing<'_> {
        let start = self.vertex_out[v as usize];
        Outgoing { mesh: self, start, current: start }
    }

    /// The one-ring neighbours of `v`, in the order of [`Mesh::outgoing`].
    pub fn neighbors(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.outgoing(v).map(move |h| self.to_vertex(h))
    }

    /// Number of edges at `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.outgoing(v).count()
    }

    /// The halfedge from `a` to `b`, if they share an edge.
    pub fn find_halfedge(&self, a: u32, b: u32) -> Option<u32> {
        self.outgoing(a).find(|&h| self.to_vertex(h) == b)
    }
}

/// Iterator over the outgoing halfedges of a vertex; see [`Mesh::outgoing`].
pub struct Outgoing<'a> {
    mesh: &'a Mesh,
    start: u32,
    current: u32,
}

impl Iterator for Outgoing<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.current == NONE {
            return None;
        }
        let h = self.current;
        // twin(h) comes into the vertex; the halfedge after it in its face leaves it again.
        let n = self.mesh.next(self.mesh.twin(h));
        self.current = if n == self.start { NONE } else { n };
        Some(h)
    }
}
