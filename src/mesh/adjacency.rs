//! Triangle and vertex adjacency of a [`Mesh`] as flat arrays.

use super::{Mesh, NONE};

/// Who neighbours whom, in arrays: for walks made many times over one mesh (the automatic
/// layout cuts the mesh into faces every repair round, `crate::field::faces::analyze`), which
/// then read arrays in order rather than following halfedges from table to table.
#[derive(Debug)]
pub struct Adjacency {
    /// Per triangle, per halfedge of it in order: the triangle across ([`NONE`] on the
    /// boundary) and the edge between.
    across: Vec<[(u32, u32); 3]>,
    /// The triangles of each vertex's outgoing halfedges, in [`Mesh::outgoing`]'s order (the
    /// boundary's none): vertex `v`'s are `triangles[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    triangles: Vec<u32>,
}

impl Adjacency {
    pub fn new(mesh: &Mesh) -> Adjacency {
        let across = (0..mesh.n_faces() as u32)
            .map(|t| {
                std::array::from_fn(|k| {
                    let h = mesh.face_halfedge(t, k);
                    (mesh.face(mesh.twin(h)), mesh.edge(h))
                })
            })
            .collect();
        let mut start = Vec::with_capacity(mesh.n_vertices() + 1);
        let mut triangles = Vec::with_capacity(mesh.n_faces() * 3);
        start.push(0);
        for v in 0..mesh.n_vertices() as u32 {
            triangles.extend(mesh.outgoing(v).map(|h| mesh.face(h)).filter(|&f| f != NONE));
            start.push(triangles.len() as u32);
        }
        Adjacency { across, start, triangles }
    }

    /// The triangles round `v`, in [`Mesh::outgoing`]'s order.
    pub fn round(&self, v: u32) -> &[u32] {
        &self.triangles[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// The connected regions of the triangles, joined across the edges for which `cut` does
    /// not hold: the region of each triangle and their count, numbered in the order of their
    /// first triangle.
    pub fn regions(&self, cut: impl Fn(u32) -> bool) -> (Vec<u32>, usize) {
        let mut region = vec![NONE; self.across.len()];
        let mut count = 0u32;
        let mut stack = Vec::new();
        for seed in 0..self.across.len() {
            if region[seed] != NONE {
                continue;
            }
            region[seed] = count;
            stack.push(seed as u32);
            while let Some(t) = stack.pop() {
                for &(u, e) in &self.across[t as usize] {
                    if u != NONE && region[u as usize] == NONE && !cut(e) {
                        region[u as usize] = count;
                        stack.push(u);
                    }
                }
            }
            count += 1;
        }
        (region, count as usize)
    }
}
