//! Quad mesh extraction (paper Section 4): sample counts per edge piece that agree on
//! opposite chart sides, a grid per chart, grid points mapped back to the surface.

use crate::mesh::NONE;

/// A pure quad mesh, welded: samples on layout edges and nodes are shared by the faces on
/// both sides.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct QuadMesh {
    pub positions: Vec<[f64; 3]>,
    /// Corners counter-clockwise seen from outside (the input's orientation).
    pub quads: Vec<[u32; 4]>,
    /// The layout node (corner or T-vertex) at each vertex, or [`NONE`].
    pub vertex_node: Vec<u32>,
}

impl QuadMesh {
    /// Vertices that are layout nodes (chart corners or T-vertices).
    pub fn node_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.vertex_node.len() as u32).filter(|&v| self.vertex_node[v as usize] != NONE)
    }
}
