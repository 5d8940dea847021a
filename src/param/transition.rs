//! Affine transition functions between neighbouring charts (paper eq. 4, Fig. 4;
//! method-notes §3).
//!
//! Faces α and β share a curve from node p to node q. With `pα, qα` their positions in chart
//! α and `pβ, qβ` in chart β, `φαβ = Tβ⁻¹ Rβ⁻¹ S Rα Tα`: translate pα to the origin, rotate
//! qα − pα onto +x, scale along x by |qβ − pβ| / |qα − pα|, then undo β's rotation and
//! translation. Both charts are oriented like the surface, so no reflection is needed.

use crate::geom::{add2, det, dist2, inverse_with, mat_mul, mat_vec, Mat2, Vec2};

/// An affine map of the plane: `x ↦ m·x + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    pub m: Mat2,
    pub t: Vec2,
}

impl Affine {
    pub const IDENTITY: Affine = Affine { m: [[1.0, 0.0], [0.0, 1.0]], t: [0.0, 0.0] };

    pub fn apply(&self, x: Vec2) -> Vec2 {
        add2(mat_vec(&self.m, x), self.t)
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn after(&self, other: &Affine) -> Affine {
        Affine { m: mat_mul(&self.m, &other.m), t: self.apply(other.t) }
    }

    /// The inverse map; `None` if the linear part is singular.
    pub fn inverse(&self) -> Option<Affine> {
        let det = det(&self.m);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = inverse_with(&self.m, det);
        let [x, y] = mat_vec(&inv, self.t);
        Some(Affine { m: inv, t: [-x, -y] })
    }

    /// Rotation by `angle` about the origin, then translation by `t`.
    fn rigid(angle: f64, t: [f64; 2]) -> Affine {
        let (s, c) = angle.sin_cos();
        Affine { m: [[c, -s], [s, c]], t }
    }

    /// The frame of an edge seen from one chart: `R T`, taking `p` to the origin and `q` onto
    /// the +x axis (method-notes §6).
    pub fn edge_frame(p: [f64; 2], q: [f64; 2]) -> Affine {
        let angle = (q[1] - p[1]).atan2(q[0] - p[0]);
        let r = Affine::rigid(-angle, [0.0, 0.0]);
        r.after(&Affine { m: Affine::IDENTITY.m, t: [-p[0], -p[1]] })
    }

    /// φαβ of eq. 4: maps chart α to chart β along the shared edge p → q.
    ///
    /// Precondition: p ≠ q in both charts.
    pub fn transition(p_a: [f64; 2], q_a: [f64; 2], p_b: [f64; 2], q_b: [f64; 2]) -> Affine {
        let s = dist2(q_b, p_b) / dist2(q_a, p_a);
        let scale = Affine { m: [[s, 0.0], [0.0, 1.0]], t: [0.0, 0.0] };
        let frame_b_inv = Affine::edge_frame(p_b, q_b).inverse().unwrap_or(Affine::IDENTITY);
        frame_b_inv.after(&scale).after(&Affine::edge_frame(p_a, q_a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn transition_maps_the_shared_edge_and_inverts() {
        let (pa, qa) = ([0.3, -0.2], [1.7, 0.9]);
        let (pb, qb) = ([2.0, 5.0], [-1.0, 4.5]);
        let phi = Affine::transition(pa, qa, pb, qb);
        assert!(close(phi.apply(pa), pb));
        assert!(close(phi.apply(qa), qb));
        let back = Affine::transition(pb, qb, pa, qa);
        let id = back.after(&phi);
        for x in [[0.0, 0.0], [3.0, -2.0], [0.5, 7.0]] {
            assert!(close(id.apply(x), x));
        }
        assert_eq!(phi.inverse().map(|i| close(i.apply(pb), pa)), Some(true));
        // Orientation is kept: a point left of p→q in α stays left of p→q in β.
        let left = |p: [f64; 2], q: [f64; 2], x: [f64; 2]| (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]);
        let x = [0.5, 1.0];
        assert!(left(pa, qa, x) > 0.0 && left(pb, qb, phi.apply(x)) > 0.0);
    }
}
