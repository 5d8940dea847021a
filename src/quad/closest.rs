//! Closest points on a set of triangles: the exact point-to-triangle projection of Ericson,
//! *Real-Time Collision Detection* (2005), Section 5.1.5, and an axis-aligned bounding-box
//! tree that finds the nearest triangle of many without visiting most of them.
//!
//! The tree is split at the median of the triangle centroids along their longest extent,
//! so its depth is ⌈log₂ n⌉ whatever the triangles' distribution; a query descends the
//! nearer child first and skips every box farther than the best triangle found so far.
//! [`quality`](super::quality) uses it for Hausdorff distances and for the input normal under
//! each quad.
//!
//! ```
//! use quadlay::quad::closest::TriangleTree;
//! let tree = TriangleTree::new([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
//! let hit = tree.closest([0.25, 0.25, 2.0]).unwrap();
//! assert_eq!((hit.triangle, hit.point), (0, [0.25, 0.25, 0.0]));
//! assert_eq!(hit.distance_squared, 4.0);
//! ```

use crate::geom::{dot, sub, Vec3};

/// Triangles per leaf: below this a linear scan beats descending further.
const LEAF_SIZE: usize = 4;

/// Room for the traversal stack. Each level of the tree adds at most one pending node and
/// median splits keep the depth at ⌈log₂(n / LEAF_SIZE)⌉ + 1 < 32 for n < 2³².
const STACK_SIZE: usize = 64;

/// The point of triangle `(a, b, c)` closest to `p` (Ericson's Voronoi-region walk: vertex
/// regions, then edge regions, then the face). Degenerate triangles (collinear or coincident
/// corners) are handled as the union of their edges.
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    // va, vb, vc are the barycentric coordinates of p's projection scaled by twice the
    // triangle's squared area (Lagrange's identity), so their signs pick the region.
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let area = va + vb + vc;
    if area > 0.0 {
        let (v, w) = (vb / area, vc / area);
        return std::array::from_fn(|k| a[k] + v * ab[k] + w * ac[k]);
    }
    // Only reachable through rounding on a (nearly) degenerate triangle: the face region
    // has no width, so the answer lies on an edge.
    [(a, b), (b, c), (c, a)]
        .map(|(s, t)| closest_point_on_segment(p, s, t))
        .into_iter()
        .min_by(|x, y| distance_squared(p, *x).total_cmp(&distance_squared(p, *y)))
        .unwrap_or(a)
}

/// The point of segment `[a, b]` closest to `p`.
fn closest_point_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    nearest_on_segment(p, a, b).1
}

/// The point of segment `[a, b]` closest to `p`, and where it is along the segment (0 at `a`,
/// 1 at `b`; 0 on a segment of no length).
pub fn nearest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> (f64, Vec3) {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    if len2 > 0.0 {
        let t = (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0);
        (t, along(a, ab, t))
    } else {
        (0.0, a)
    }
}

fn along(a: Vec3, d: Vec3, t: f64) -> Vec3 {
    std::array::from_fn(|k| a[k] + t * d[k])
}

fn distance_squared(a: Vec3, b: Vec3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

/// The nearest triangle to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Position of the triangle in the sequence the tree was built from.
    pub triangle: u32,
    /// The closest point on that triangle.
    pub point: Vec3,
    /// Squared distance from the query point to `point`.
    pub distance_squared: f64,
}

/// A bounding box and what it holds: triangles `start..start + count` of the tree's order
/// when `count > 0` (a leaf); otherwise two children, the first right after this node and
/// the second at `start`.
#[derive(Debug, Clone, Copy)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    start: u32,
    count: u32,
}

impl Node {
    /// Squared distance from `p` to the box (0 inside).
    fn distance_squared(&self, p: Vec3) -> f64 {
        (0..3)
            .map(|k| {
                let d = (self.lo[k] - p[k]).max(p[k] - self.hi[k]).max(0.0);
                d * d
            })
            .sum()
    }
}

/// A bounding-box tree over triangles for nearest-triangle queries.
#[derive(Debug, Clone, Default)]
pub struct TriangleTree {
    nodes: Vec<Node>,
    /// Triangle corners in leaf order, copied so a leaf reads contiguous memory.
    triangles: Vec<[Vec3; 3]>,
    /// The position in the input sequence of each entry of `triangles`.
    ids: Vec<u32>,
}

impl TriangleTree {
    /// Builds the tree over `triangles`, given by their corner positions; a [`Hit`] names a
    /// triangle by its position in this sequence.
    ///
    /// Triangles with a non-finite coordinate are left out: they have no closest point.
    /// Precondition: fewer than 2³² triangles.
    pub fn new(triangles: impl IntoIterator<Item = [Vec3; 3]>) -> Self {
        let (ids, corners): (Vec<u32>, Vec<[Vec3; 3]>) = triangles
            .into_iter()
            .enumerate()
            .filter(|(_, t)| t.iter().flatten().all(|x| x.is_finite()))
            .map(|(i, t)| (i as u32, t))
            .unzip();
        // Each triangle's centroid beside its index: the median selections below then read
        // contiguous memory.
        let mut order: Vec<(Vec3, u32)> = corners
            .iter()
            .enumerate()
            .map(|(i, t)| (std::array::from_fn(|k| (t[0][k] + t[1][k] + t[2][k]) / 3.0), i as u32))
            .collect();
        let mut nodes = Vec::with_capacity(2 * corners.len() / LEAF_SIZE + 1);
        if !order.is_empty() {
            split(&mut nodes, &mut order, 0, &corners);
        }
        TriangleTree {
            nodes,
            triangles: order.iter().map(|&(_, i)| corners[i as usize]).collect(),
            ids: order.iter().map(|&(_, i)| ids[i as usize]).collect(),
        }
    }

    /// Number of triangles held (the finite ones given to [`TriangleTree::new`]).
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the tree holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The triangle nearest to `p` and the closest point on it; `None` for an empty tree or
    /// a non-finite `p`. Among equally near triangles any one may be returned.
    pub fn closest(&self, p: Vec3) -> Option<Hit> {
        self.search(p, -1.0, &mut 0)
    }

    /// [`closest`](Self::closest), looking first in the leaf `leaf` (the one a query near
    /// `p` ended in) and leaving there the leaf of the answer: a run of queries that each move
    /// a little mostly end where they start.
    pub fn closest_from(&self, p: Vec3, leaf: &mut u32) -> Option<Hit> {
        self.search(p, -1.0, leaf)
    }

    /// The squared distance from `p` to the nearest triangle if it is larger than `floor`;
    /// `None` as soon as a triangle within `floor` is found (or for an empty tree or a
    /// non-finite `p`). For the Hausdorff distance, a max of min distances: a sample nearer
    /// than the largest distance found so far cannot raise it. `leaf` carries the leaf
    /// where the last query ended; it is looked at first, so a run of neighbouring samples
    /// mostly ends there without descending the tree.
    pub fn distance_squared_beyond(&self, p: Vec3, floor: f64, leaf: &mut u32) -> Option<f64> {
        self.search(p, floor, leaf).map(|hit| hit.distance_squared)
    }

    /// [`closest`](Self::closest), giving up (`None`) at a triangle within `floor`
    /// (squared distance; negative: never), starting with the leaf node `leaf` (if it is one)
    /// and leaving there the leaf of the answer.
    fn search(&self, p: Vec3, floor: f64, leaf: &mut u32) -> Option<Hit> {
        if self.nodes.is_empty() || !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut best = Hit {
            triangle: 0,
            point: p,
            distance_squared: f64::INFINITY,
        };
        let hint = *leaf;
        if self.nodes.get(hint as usize).is_some_and(|n| n.count > 0) && self.scan(hint, p, floor, &mut best, leaf) {
            return None;
        }
        let mut stack = [(0u32, 0.0f64); STACK_SIZE];
        let mut top = 1;
        stack[0] = (0, self.nodes[0].distance_squared(p));
        while top > 0 {
            top -= 1;
            let (index, box_distance) = stack[top];
            // The best distance may have shrunk since this node was pushed.
            if box_distance >= best.distance_squared {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count > 0 {
                if index != hint && self.scan(index, p, floor, &mut best, leaf) {
                    return None;
                }
                continue;
            }
            let first = index + 1;
            let second = node.start;
            let d_first = self.nodes[first as usize].distance_squared(p);
            let d_second = self.nodes[second as usize].distance_squared(p);
            // Pushed last, popped first: the nearer child shrinks `best` before the other
            // is looked at.
            let (near, far) = if d_first <= d_second {
                ((first, d_first), (second, d_second))
            } else {
                ((second, d_second), (first, d_first))
            };
            for entry in [far, near] {
                if entry.1 < best.distance_squared {
                    stack[top] = entry;
                    top += 1;
                }
            }
        }
        best.distance_squared.is_finite().then_some(best)
    }

    /// Looks at the triangles of leaf `index`: updates `best` (and `leaf`) with a nearer one;
    /// true when one is within `floor` (the search can stop).
    fn scan(&self, index: u32, p: Vec3, floor: f64, best: &mut Hit, leaf: &mut u32) -> bool {
        let node = &self.nodes[index as usize];
        for i in node.start as usize..(node.start + node.count) as usize {
            let [a, b, c] = self.triangles[i];
            let q = closest_point_on_triangle(p, a, b, c);
            let d = distance_squared(p, q);
            if d <= floor {
                *leaf = index;
                return true;
            }
            if d < best.distance_squared {
                *best = Hit { triangle: self.ids[i], point: q, distance_squared: d };
                *leaf = index;
            }
        }
        false
    }
}

/// Appends the subtree over `order` (the triangles `offset..offset + order.len()` of the
/// final order, each with its centroid) to `nodes` and returns its root index. A node's box
/// is the union of its children's, so each level looks at the centroids only (to choose the
/// split axis).
fn split(nodes: &mut Vec<Node>, order: &mut [(Vec3, u32)], offset: u32, corners: &[[Vec3; 3]]) -> u32 {
    let index = nodes.len() as u32;
    if order.len() <= LEAF_SIZE {
        let mut node = Node { lo: [f64::INFINITY; 3], hi: [f64::NEG_INFINITY; 3], start: offset, count: order.len() as u32 };
        for p in order.iter().flat_map(|&(_, t)| corners[t as usize]) {
            node.lo = std::array::from_fn(|k| node.lo[k].min(p[k]));
            node.hi = std::array::from_fn(|k| node.hi[k].max(p[k]));
        }
        nodes.push(node);
        return index;
    }
    let mut c_lo = [f64::INFINITY; 3];
    let mut c_hi = [f64::NEG_INFINITY; 3];
    for &(c, _) in order.iter() {
        for k in 0..3 {
            c_lo[k] = c_lo[k].min(c[k]);
            c_hi[k] = c_hi[k].max(c[k]);
        }
    }
    let axis = (0..3).fold(0, |best, k| {
        if c_hi[k] - c_lo[k] > c_hi[best] - c_lo[best] {
            k
        } else {
            best
        }
    });
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |a, b| a.0[axis].total_cmp(&b.0[axis]));
    nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], start: 0, count: 0 }); // filled below
    let (left, right) = order.split_at_mut(mid);
    let first = split(nodes, left, offset, corners);
    let second = split(nodes, right, offset + mid as u32, corners);
    let (a, b) = (nodes[first as usize], nodes[second as usize]);
    nodes[index as usize] = Node {
        lo: std::array::from_fn(|k| a.lo[k].min(b.lo[k])),
        hi: std::array::from_fn(|k| a.hi[k].max(b.hi[k])),
        start: second,
        count: 0,
    };
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{cross, norm};

    /// A seeded linear congruential generator (Knuth's MMIX constants): reproducible
    /// random numbers without a dependency.
    struct Lcg(u64);
    impl Lcg {
        /// Uniform in [0, 1).
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn point(&mut self, scale: f64) -> Vec3 {
            std::array::from_fn(|_| scale * (2.0 * self.next() - 1.0))
        }
    }

    #[test]
    fn closest_point_is_on_the_triangle_and_no_sample_of_it_is_closer() {
        let mut rng = Lcg(42);
        let steps = 60;
        for round in 0..300 {
            let [a, b, c] = [rng.point(1.0), rng.point(1.0), rng.point(1.0)];
            // Every region of the walk is hit: points far out reach vertex and edge regions.
            let p = rng.point(if round % 2 == 0 { 0.7 } else { 3.0 });
            let q = closest_point_on_triangle(p, a, b, c);
            // On the triangle: in its plane, with non-negative barycentric coordinates.
            let n = cross(sub(b, a), sub(c, a));
            let area2 = dot(n, n);
            let bary =
                [(b, c), (c, a), (a, b)].map(|(s, t)| dot(cross(sub(s, q), sub(t, q)), n) / area2);
            assert!(bary.iter().all(|&w| w >= -1e-12), "{bary:?}");
            assert!((bary.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            // Brute force over a barycentric lattice: nothing beats the answer.
            let d = distance_squared(p, q);
            for i in 0..=steps {
                for j in 0..=steps - i {
                    let (u, v) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    let s: Vec3 =
                        std::array::from_fn(|k| a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]));
                    assert!(distance_squared(p, s) >= d - 1e-12, "round {round}");
                }
            }
        }
    }

    #[test]
    fn degenerate_triangles_project_onto_their_edges() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]);
        assert_eq!(
            closest_point_on_triangle([2.0, 1.0, 0.0], a, b, c),
            [2.0, 0.0, 0.0]
        );
        assert_eq!(closest_point_on_triangle([5.0, 1.0, 0.0], a, b, c), c);
        assert_eq!(closest_point_on_triangle([5.0, 1.0, 0.0], a, a, a), a);
        let q = closest_point_on_triangle([0.5, -2.0, 1.0], b, a, c);
        assert!(norm(sub(q, [0.5, 0.0, 0.0])) < 1e-15, "{q:?}");
    }

    #[test]
    fn tree_agrees_with_a_linear_scan() {
        let mut rng = Lcg(7);
        for &count in &[1usize, 3, 5, 17, 400] {
            // Small triangles scattered in a box, like a mesh's, plus a few long slivers.
            let triangles: Vec<[Vec3; 3]> = (0..count)
                .map(|i| {
                    let a = rng.point(1.0);
                    let size = if i % 50 == 0 { 1.0 } else { 0.1 };
                    [
                        a,
                        std::array::from_fn(|k| a[k] + size * rng.point(1.0)[k]),
                        std::array::from_fn(|k| a[k] + size * rng.point(1.0)[k]),
                    ]
                })
                .collect();
            let tree = TriangleTree::new(triangles.iter().copied());
            assert_eq!(tree.len(), count);
            for _ in 0..500 {
                let p = rng.point(1.5);
                let hit = tree.closest(p).unwrap();
                let brute = triangles
                    .iter()
                    .map(|t| distance_squared(p, closest_point_on_triangle(p, t[0], t[1], t[2])))
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(hit.distance_squared, brute);
                // Beyond a floor: the distance when larger, nothing when within, whatever
                // leaf the search starts with.
                for mut leaf in [0, 1, 3, u32::MAX] {
                    assert_eq!(tree.distance_squared_beyond(p, 0.5 * brute, &mut leaf), Some(brute));
                    assert_eq!(tree.distance_squared_beyond(p, brute, &mut leaf), None);
                }
                let t = triangles[hit.triangle as usize];
                assert_eq!(hit.point, closest_point_on_triangle(p, t[0], t[1], t[2]));
            }
        }
    }

    #[test]
    fn non_finite_triangles_and_points_are_ignored() {
        let nan = f64::NAN;
        let tree = TriangleTree::new([
            [[nan, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
        ]);
        assert_eq!(tree.len(), 1);
        assert_eq!(tree.closest([0.1, 0.1, 0.0]).map(|h| h.triangle), Some(1));
        assert_eq!(tree.closest([nan, 0.0, 0.0]), None);
        assert_eq!(TriangleTree::new([]).closest([0.0; 3]), None);
    }
}
