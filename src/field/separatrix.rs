//! The directions in which separatrices leave a singular vertex (method-notes §11).
//!
//! Around the vertex's one-ring (angles scaled to a full turn, as if the ring were flattened)
//! the field's angle `ψ` is followed continuously, each arm matched to the nearest one of the
//! previous neighbour. A separatrix leaves where an arm points straight away from the vertex:
//! where `4(ψ − φ)` passes a multiple of 2π, `φ` the direction of the ray. Around a valence-k
//! vertex that happens k times (4 at a regular vertex).

use super::frames::wrap;
use super::CrossField;
use crate::geom::{sub, unit, Vec3};
use crate::mesh::geometry::corner_angle;
use crate::mesh::Mesh;
use std::f64::consts::PI;

/// Unit tangent directions (in space) of the separatrices leaving interior vertex `v`; empty
/// on the boundary.
pub fn separatrix_directions(mesh: &Mesh, field: &CrossField, v: u32) -> Vec<Vec3> {
    if mesh.is_boundary_vertex(v) || mesh.is_isolated(v) {
        return Vec::new();
    }
    let hs: Vec<u32> = mesh.outgoing(v).collect();
    // Corner angle at v of the face of each outgoing halfedge (between h and the next ring
    // edge); of v's own triangles only: this runs once per singularity.
    let corner = |h: u32| corner_angle(mesh, h);
    let total: f64 = hs.iter().map(|&h| corner(h)).sum();
    let p = mesh.position(v);
    let m = hs.len();
    // f_j = 4 (ψ_j − φ_j) at ring neighbour j, j = 0..=m (m is neighbour 0 again after a turn).
    let mut phi = 0.0;
    let mut psi_prev = 0.0;
    let mut f = Vec::with_capacity(m + 1);
    let mut dirs = Vec::with_capacity(m + 1);
    for j in 0..=m {
        let h = hs[j % m];
        let u = mesh.to_vertex(h);
        let e = sub(mesh.position(u), p);
        let alpha = field.frames.angle(v, e);
        // The arm of u seen from v, relative to the ray to u, then placed in the flat ring.
        let arm = field.frames.angle(v, field.arms(u)[0]);
        let mut psi = phi + (arm - alpha);
        if j > 0 {
            // Nearest representative to the previous neighbour's (4-fold symmetry).
            let d = wrap(4.0 * (psi - psi_prev)) / 4.0;
            psi = psi_prev + d;
        }
        f.push(4.0 * (psi - phi));
        dirs.push(unit(e));
        psi_prev = psi;
        phi += 2.0 * PI * corner(h) / total;
    }
    // Each multiple of 2π between consecutive samples (the start of an interval excluded,
    // as the interval before counts it) is one separatrix.
    let mut out = Vec::new();
    for j in 0..m {
        let (a, b) = (f[j], f[j + 1]);
        let (lo, hi) = (a.min(b), a.max(b));
        let (k0, k1) = ((lo / (2.0 * PI)).ceil() as i64, (hi / (2.0 * PI)).floor() as i64);
        for k in k0..=k1 {
            let x = k as f64 * 2.0 * PI;
            if x == a {
                continue;
            }
            let t = (x - a) / (b - a);
            out.push(unit([
                (1.0 - t) * dirs[j][0] + t * dirs[j + 1][0],
                (1.0 - t) * dirs[j][1] + t * dirs[j + 1][1],
                (1.0 - t) * dirs[j][2] + t * dirs[j + 1][2],
            ]));
        }
    }
    out
}
