//! Affine transition functions between neighbouring charts (paper eq. 4, Fig. 4;
//! method-notes §3).
//!
//! Faces α and β share a curve from node p to node q. With `pα, qα` their positions in chart
//! α and `pβ, qβ` in chart β, `φαβ = Tβ⁻¹ Rβ⁻¹ S Rα Tα`: translate pα to the origin, rotate
//! qα − pα onto +x, scale along x by |qβ − pβ| / |qα − pα|, then undo β's rotation and
//! translation. Both charts are oriented like the surface, so no reflection is needed.

/// An affine map of the plane: `x ↦ m·x + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    pub m: [[f64; 2]; 2],
    pub t: [f64; 2],
}

impl Affine {
    pub const IDENTITY: Affine = Affine { m: [[1.0, 0.0], [0.0, 1.0]], t: [0.0, 0.0] };

    pub fn apply(&self, x: [f64; 2]) -> [f64; 2] {
        let m = &self.m;
        [m[0][0] * x[0] + m[0][1] * x[1] + self.t[0], m[1][0] * x[0] + m[1][1] * x[1] + self.t[1]]
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn after(&self, other: &Affine) -> Affine {
        let (a, b) = (&self.m, &other.m);
        let m = [
            [a[0][0] * b[0][0] + a[0][1] * b[1][0], a[0][0] * b[0][1] + a[0][1] * b[1][1]],
            [a[1][0] * b[0][0] + a[1][1] * b[1][0], a[1][0] * b[0][1] + a[1][1] * b[1][1]],
        ];
        let t = self.apply(other.t);
        Affine { m, t }
    }

    /// The inverse map; `None` if the linear part is singular.
    pub fn inverse(&self) -> Option<Affine> {
        let m = &self.m;
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = [[m[1][1] / det, -m[0][1] / det], [-m[1][0] / det, m[0][0] / det]];
        let t = [-(inv[0][0] * self.t[0] + inv[0][1] * self.t[1]), -(inv[1][0] * self.t[0] + inv[1][1] * self.t[1])];
        Some(Affine { m: inv, t })
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
        let len = |p: [f64; 2], q: [f64; 2]| (q[0] - p[0]).hypot(q[1] - p[1]);
        let s = len(p_b, q_b) / len(p_a, q_a);
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
