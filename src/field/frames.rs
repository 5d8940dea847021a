//! Tangent frames at the vertices and the discrete Levi-Civita connection between them
//! (Knöppel, Crane, Pinkall, Schröder 2013, *Globally Optimal Direction Fields*, Section 6.1).
//!
//! Every vertex gets a unit normal (angle-weighted mean of its triangles' normals) and an
//! orthonormal tangent basis `(e1, e2)` with `e1 × e2 = n`. A tangent direction at a vertex is
//! an angle in that basis. Transport along an edge keeps the angle to the edge: a direction at
//! angle `α` in the frame of `i` becomes `α + ρ_ij` in the frame of `j`, with `ρ_ij` the angle
//! of the edge seen from `j` minus its angle seen from `i`.

use crate::geom::{add, cross, dot, scale, sub, tangent_basis, unit, Vec3};
use crate::mesh::geometry::{corner_angles, face_normals};
use crate::mesh::{Mesh, NONE};
use std::f64::consts::PI;

/// Per-vertex normal and tangent basis.
#[derive(Debug, Clone)]
pub struct Frames {
    pub normal: Vec<Vec3>,
    pub e1: Vec<Vec3>,
    pub e2: Vec<Vec3>,
}

/// `a` without its component along the unit vector `n`.
pub fn tangential(a: Vec3, n: Vec3) -> Vec3 {
    sub(a, scale(dot(a, n), n))
}

/// The angle in (−π, π] congruent to `a`.
pub fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI {
        r - 2.0 * PI
    } else {
        r
    }
}

impl Frames {
    /// Angle-weighted vertex normals and a tangent basis whose `e1` points along the vertex's
    /// first outgoing edge. Isolated vertices get an arbitrary frame.
    pub fn new(mesh: &Mesh) -> Frames {
        let angles = corner_angles(mesh);
        let face_normal = face_normals(mesh);
        let mut normal = vec![[0.0; 3]; mesh.n_vertices()];
        for (f, t) in mesh.triangles().iter().enumerate() {
            let n = face_normal[f];
            for k in 0..3 {
                normal[t[k] as usize] = add(normal[t[k] as usize], scale(angles[f][k], n));
            }
        }
        let mut e1 = vec![[0.0; 3]; mesh.n_vertices()];
        let mut e2 = vec![[0.0; 3]; mesh.n_vertices()];
        for v in 0..mesh.n_vertices() {
            let mut n = unit(normal[v]);
            if n == [0.0; 3] {
                n = [0.0, 0.0, 1.0];
            }
            normal[v] = n;
            let h = mesh.vertex_halfedge(v as u32);
            let mut a = if h == NONE { [0.0; 3] } else { unit(tangential(sub(mesh.position(mesh.to_vertex(h)), mesh.position(v as u32)), n)) };
            if a == [0.0; 3] {
                // Any direction not along n.
                a = tangent_basis(n)[0];
            }
            e1[v] = a;
            e2[v] = cross(n, a);
        }
        Frames { normal, e1, e2 }
    }

    /// Angle of the vector `a` (projected to the tangent plane) in the frame of `v`.
    pub fn angle(&self, v: u32, a: Vec3) -> f64 {
        let v = v as usize;
        dot(a, self.e2[v]).atan2(dot(a, self.e1[v]))
    }

    /// The unit tangent vector at angle `theta` in the frame of `v`.
    pub fn direction(&self, v: u32, theta: f64) -> Vec3 {
        let v = v as usize;
        add(scale(theta.cos(), self.e1[v]), scale(theta.sin(), self.e2[v]))
    }

    /// Transport angle `ρ` of halfedge `h` (from `i` to `j`): a direction at angle `α` at `i`
    /// corresponds to `α + ρ` at `j`. In (−π, π].
    pub fn transport(&self, mesh: &Mesh, h: u32) -> f64 {
        let (i, j) = (mesh.from_vertex(h), mesh.to_vertex(h));
        let e = sub(mesh.position(j), mesh.position(i));
        wrap(self.angle(j, e) - self.angle(i, e))
    }
}
