//! Small vectors and 2×2 matrices, the cotangent of eq. 2, and the tolerances that several
//! modules share: the one home of the arithmetic every stage repeats.
//!
//! Points are plain arrays (`[f64; 3]` on the surface, `[f64; 2]` in a chart), so they cross
//! module and wasm boundaries without conversion. The 2D helpers end in `2`; the 3D ones have
//! the plain names.

/// A point or vector on the surface.
pub type Vec3 = [f64; 3];
/// A point or vector in a chart.
pub type Vec2 = [f64; 2];
/// A 2×2 matrix, row-major: `m[row][col]`.
pub type Mat2 = [[f64; 2]; 2];

/// Points within this fraction of an element's size from a vertex or a side are on it: a
/// curve crossing that close to an edge's end is that vertex (method-notes §0), two curves
/// that close meet, a chart point that close to a triangle lies in it. Far above rounding
/// (1e-16), far below any feature a mesh resolves.
pub const SNAP: f64 = 1e-9;

pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn scale(s: f64, a: Vec3) -> Vec3 {
    [s * a[0], s * a[1], s * a[2]]
}
/// `a` with unit length, or zero if `a` is (nearly) zero.
pub fn unit(a: Vec3) -> Vec3 {
    let l = norm(a);
    if l > 1e-300 {
        scale(1.0 / l, a)
    } else {
        [0.0; 3]
    }
}

/// Two orthogonal unit directions spanning the plane normal to the unit vector `n`, the
/// second `n × first`; the first is the coordinate axis x (or y, where `n` is nearly along
/// x) made normal to `n`.
pub fn tangent_basis(n: Vec3) -> [Vec3; 2] {
    let a = if n[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let t1 = unit(sub(a, scale(dot(a, n), n)));
    [t1, cross(n, t1)]
}

/// The angle between `u` and `w`, in [0, π]. `atan2` stays accurate near 0 and π, unlike
/// `acos`.
pub fn angle(u: Vec3, w: Vec3) -> f64 {
    norm(cross(u, w)).atan2(dot(u, w))
}

/// Cotangent of the triangle's angle at `corner` (eq. 2's weights are sums of these halved):
/// `u·w / |u × w|` with `u`, `w` the edges to the other two corners. A triangle without area
/// gets a huge or infinite value (or 0 where an edge has no length), never NaN.
pub fn cotangent(corner: Vec3, a: Vec3, b: Vec3) -> f64 {
    let (u, w) = (sub(a, corner), sub(b, corner));
    dot(u, w) / norm(cross(u, w)).max(f64::MIN_POSITIVE)
}

pub fn sub2(p: Vec2, q: Vec2) -> Vec2 {
    [p[0] - q[0], p[1] - q[1]]
}
pub fn add2(p: Vec2, q: Vec2) -> Vec2 {
    [p[0] + q[0], p[1] + q[1]]
}
pub fn scale2(s: f64, p: Vec2) -> Vec2 {
    [s * p[0], s * p[1]]
}
pub fn dot2(p: Vec2, q: Vec2) -> f64 {
    p[0] * q[0] + p[1] * q[1]
}
/// The z component of the cross product: positive when `q` turns left of `p`.
pub fn cross2(p: Vec2, q: Vec2) -> f64 {
    p[0] * q[1] - p[1] * q[0]
}
/// Length, as `√(p·p)`: not `hypot`, which is exact to the last bit but several times
/// slower (chart coordinates are far from overflow). [`dist2`] uses `hypot`.
pub fn norm2(p: Vec2) -> f64 {
    dot2(p, p).sqrt()
}
/// The distance between `a` and `b`, by `hypot` (exact to the last bit).
pub fn dist2(a: Vec2, b: Vec2) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
/// `p` turned by 90° counter-clockwise.
pub fn perp2(p: Vec2) -> Vec2 {
    [-p[1], p[0]]
}
/// Twice the signed area of (o, a, b): positive when `b` lies left of the ray o→a.
pub fn orient2(o: Vec2, a: Vec2, b: Vec2) -> f64 {
    cross2(sub2(a, o), sub2(b, o))
}
/// The angle between `a` and `b`, in [0, π].
pub fn angle2(a: Vec2, b: Vec2) -> f64 {
    cross2(a, b).abs().atan2(dot2(a, b))
}

/// `a b`.
pub fn mat_mul(a: &Mat2, b: &Mat2) -> Mat2 {
    [
        [a[0][0] * b[0][0] + a[0][1] * b[1][0], a[0][0] * b[0][1] + a[0][1] * b[1][1]],
        [a[1][0] * b[0][0] + a[1][1] * b[1][0], a[1][0] * b[0][1] + a[1][1] * b[1][1]],
    ]
}
/// `m x`.
pub fn mat_vec(m: &Mat2, x: Vec2) -> Vec2 {
    [m[0][0] * x[0] + m[0][1] * x[1], m[1][0] * x[0] + m[1][1] * x[1]]
}
pub fn transpose(a: &Mat2) -> Mat2 {
    [[a[0][0], a[1][0]], [a[0][1], a[1][1]]]
}
pub fn det(m: &Mat2) -> f64 {
    m[0][0] * m[1][1] - m[0][1] * m[1][0]
}
/// `a + s b`.
pub fn add_scaled(a: &Mat2, s: f64, b: &Mat2) -> Mat2 {
    [[a[0][0] + s * b[0][0], a[0][1] + s * b[0][1]], [a[1][0] + s * b[1][0], a[1][1] + s * b[1][1]]]
}
/// Frobenius inner product `⟨A, B⟩ = Σ Aᵢⱼ Bᵢⱼ`.
pub fn inner(a: &Mat2, b: &Mat2) -> f64 {
    a[0][0] * b[0][0] + a[0][1] * b[0][1] + a[1][0] * b[1][0] + a[1][1] * b[1][1]
}
/// Squared Frobenius norm `‖A‖²_F`.
pub fn frob2(a: &Mat2) -> f64 {
    inner(a, a)
}
/// `m⁻¹` for a matrix with determinant `det` (the caller has checked it is usable).
pub fn inverse_with(m: &Mat2, det: f64) -> Mat2 {
    [[m[1][1] / det, -m[0][1] / det], [-m[1][0] / det, m[0][0] / det]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cotangents_of_a_right_triangle() {
        let (o, a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(cotangent(o, a, b), 0.0);
        assert!((cotangent(b, o, a) - 0.5).abs() < 1e-15);
        assert!((cotangent(a, b, o) - 2.0).abs() < 1e-15);
        assert!(!cotangent(o, a, a).is_nan() && cotangent(o, o, a) == 0.0);
    }

    #[test]
    fn matrix_identities() {
        let m = [[2.0, 1.0], [0.5, 3.0]];
        let inv = inverse_with(&m, det(&m));
        let id = mat_mul(&m, &inv);
        assert!(frob2(&add_scaled(&id, -1.0, &[[1.0, 0.0], [0.0, 1.0]])) < 1e-30);
        assert_eq!(mat_vec(&transpose(&m), [1.0, 0.0]), [2.0, 1.0]);
        assert_eq!(orient2([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1.0);
        assert_eq!(perp2([1.0, 0.0]), [0.0, 1.0]);
    }
}
