//! Where things sit in the charts: every node's position in the chart of each face around
//! it, the faces on either side of every curve and the transitions between their charts
//! (paper eq. 4, Fig. 6a; method-notes §1, §3).
//!
//! One [`ChartFrames`] answers "vertex v in face f's chart" for every stage: the global
//! solves (each triangle's vertices in the chart of its face, [`ChartFrames::vertex_expr`]),
//! the quad extraction (grid points looked up across a side) and `--param-out` (input
//! triangles carried across curves), both through [`ChartFrames::across`].

use super::cut::CutMesh;
use super::system::{Expr, ParamError};
use super::transition::Affine;
use crate::geom::Vec2;
use crate::mesh::NONE;
use std::collections::HashMap;

/// Positions of the nodes in each face's chart (corners and T-vertices): `[face][&node]`.
pub type NodePositions = Vec<HashMap<u32, Vec2>>;

/// The charts' frames for one set of chart shapes.
#[derive(Debug, Clone)]
pub struct ChartFrames {
    /// Per face: its nodes' positions in its chart.
    pub nodes: NodePositions,
    /// Per curve: the faces on its left and on its right ([`NONE`] right of a boundary
    /// piece). A curve's vertices belong to the face on its left (`cut_mesh`).
    pub sides: Vec<[u32; 2]>,
    /// Per curve: the map from the chart on its left to the chart on its right (eq. 4; the
    /// identity for boundary pieces).
    pub transitions: Vec<Affine>,
}

impl ChartFrames {
    /// The frames of charts whose nodes sit at `nodes`, for curves with faces `sides`: each
    /// curve's transition takes its end nodes in the left chart to the same nodes in the
    /// right chart.
    pub fn new(cut: &CutMesh, nodes: NodePositions, sides: Vec<[u32; 2]>) -> ChartFrames {
        let transitions = cut
            .curve_vertices
            .iter()
            .zip(&sides)
            .map(|(verts, &[l, r])| {
                if r == NONE {
                    return Affine::IDENTITY;
                }
                let [p, q] = [verts[0], verts[verts.len() - 1]].map(|v| cut.vertex_node[v as usize]);
                let at = |f: u32, n: u32| nodes[f as usize].get(&n).copied().unwrap_or([0.0, 0.0]);
                Affine::transition(at(l, p), at(l, q), at(r, p), at(r, q))
            })
            .collect();
        ChartFrames { nodes, sides, transitions }
    }

    /// Node `node` in the chart of `face`.
    ///
    /// # Errors
    /// [`ParamError::NodeNotOnFace`] if the node is not on that face.
    pub fn node(&self, node: u32, face: u32) -> Result<Vec2, ParamError> {
        self.nodes[face as usize].get(&node).copied().ok_or(ParamError::NodeNotOnFace { node, face })
    }

    /// Curve `c`'s first and last node in the chart of the face on its left, which owns its
    /// vertices; `None` if it has no vertices or the nodes are not on that face.
    pub fn curve_ends(&self, cut: &CutMesh, c: u32) -> Option<(Vec2, Vec2)> {
        let verts = &cut.curve_vertices[c as usize];
        let (&first, &last) = (verts.first()?, verts.last()?);
        let chart = self.nodes.get(self.sides[c as usize][0] as usize)?;
        Some((*chart.get(&cut.vertex_node[first as usize])?, *chart.get(&cut.vertex_node[last as usize])?))
    }

    /// The face across curve `c` from face `from` and the map from `from`'s chart into its
    /// chart; `None` for a boundary piece, a curve that does not border `from`, or a
    /// transition that cannot be inverted.
    pub fn across(&self, c: u32, from: u32) -> Option<(u32, Affine)> {
        let [l, r] = self.sides[c as usize];
        if r == NONE {
            None
        } else if from == l {
            Some((r, self.transitions[c as usize]))
        } else if from == r {
            self.transitions[c as usize].inverse().map(|m| (l, m))
        } else {
            None
        }
    }

    /// The map from the chart of non-node vertex `v`'s own face into the chart of `face`:
    /// `None` when they are the same chart, else the transition of `v`'s curve.
    ///
    /// # Errors
    /// [`ParamError::NotNeighbours`] if `face` is neither `v`'s face nor across its curve.
    pub fn to_face(&self, cut: &CutMesh, v: u32, face: u32) -> Result<Option<Affine>, ParamError> {
        let home = cut.vertex_face[v as usize];
        if home == face {
            return Ok(None);
        }
        let c = cut.vertex_curve[v as usize];
        if c != NONE && self.sides[c as usize] == [home, face] {
            return Ok(Some(self.transitions[c as usize]));
        }
        Err(ParamError::NotNeighbours { vertex: v, face })
    }

    /// Vertex `v` of a triangle of `face`, in that face's chart: a node at its position
    /// there; any other vertex as `own[v]` (its expression in its own face's chart, `None`
    /// for a vertex no triangle uses), carried across its curve by the transition where the
    /// triangle lies on the other side (method-notes §1).
    ///
    /// # Errors
    /// [`ParamError::NodeNotOnFace`] / [`ParamError::NotNeighbours`] on a mesh too coarse for
    /// the layout.
    pub(super) fn vertex_expr(&self, cut: &CutMesh, own: &[Option<Expr>], v: u32, face: u32) -> Result<Expr, ParamError> {
        let node = cut.vertex_node[v as usize];
        if node != NONE {
            return Ok(Expr::fixed(self.node(node, face)?));
        }
        let Some(base) = own[v as usize] else {
            return Ok(Expr::fixed([0.0, 0.0]));
        };
        Ok(match self.to_face(cut, v, face)? {
            None => base,
            Some(phi) => base.transformed(&phi),
        })
    }
}
