//! Singularities of a cross field: the index of the field around each triangle from its
//! period jumps (method-notes §11; Ray, Vallet, Li, Lévy 2008, *N-symmetry direction field
//! design*).
//!
//! Around triangle `(i, j, k)` every halfedge `i → j` contributes the jump
//! `d_ij = wrap(u_j − u_i − 4ρ_ij)` of the field's angle `u = arg z` (four times the direction
//! angle), and the triangle's holonomy `Ω = wrap(Σ ρ_ij)` (the curvature the frames see).
//! `(Σ d_ij + 4Ω) / 2π` is an integer `k`: the index is `k / 4`, a valence `4 − k` vertex of the
//! quad layout. On a closed surface the indices sum to its Euler characteristic
//! (Poincaré–Hopf): the jumps cancel between neighbours and the holonomies sum to `2πχ`.

use super::frames::{wrap, Frames};
use super::Complex;
use crate::mesh::Mesh;
use std::f64::consts::PI;

/// A triangle around which the field turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singularity {
    pub triangle: u32,
    /// Four times the index: +1 is a valence-3 singularity, −1 valence 5.
    pub quarter_turns: i32,
}

impl Singularity {
    /// Number of quad-layout edges that meet at it (3 for index +1/4, 5 for −1/4).
    pub fn valence(&self) -> i32 {
        4 - self.quarter_turns
    }
}

/// Four times the field's index around every triangle.
pub fn triangle_indices(mesh: &Mesh, frames: &Frames, field: &[Complex]) -> Vec<i32> {
    (0..mesh.n_faces() as u32)
        .map(|f| {
            let (mut jumps, mut holonomy) = (0.0, 0.0);
            for k in 0..3 {
                let h = mesh.face_halfedge(f, k);
                let (i, j) = (mesh.from_vertex(h) as usize, mesh.to_vertex(h) as usize);
                let rho = frames.transport(mesh, h);
                holonomy += rho;
                jumps += wrap(field[j].arg() - field[i].arg() - 4.0 * rho);
            }
            ((jumps + 4.0 * wrap(holonomy)) / (2.0 * PI)).round() as i32
        })
        .collect()
}

/// The triangles with a nonzero index.
pub fn singularities(mesh: &Mesh, frames: &Frames, field: &[Complex]) -> Vec<Singularity> {
    triangle_indices(mesh, frames, field)
        .into_iter()
        .enumerate()
        .filter(|&(_, k)| k != 0)
        .map(|(f, k)| Singularity { triangle: f as u32, quarter_turns: k })
        .collect()
}
