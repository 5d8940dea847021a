//! Global steps of the quads toward rectangles, for the relaxation ([`super::relax`]).
//!
//! Each quad gets the rectangle that fits its corners best in the surface's tangent plane
//! (turned and stretched along its own axes; local); then the free vertices move, each in
//! its tangent plane, to where the quads' corners lie nearest their rectangles' in the
//! least-squares sense, all at once (one sparse solve; global). This is the local/global
//! alternation of as-rigid-as-possible shape matching (Sorkine, Alexa 2007; Bouaziz et al.,
//! *Shape-Up*, 2012), with a rectangle of free sides as each quad's shape.
//!
//! Why global: a chart the harmonic map sheared is skewed over its whole width. A vertex's
//! move on its own squares its corners and skews its neighbours', and one vertex at a time
//! takes about as many rounds as the shear is quads wide to undo it: on nefertiti's automatic
//! layout at --quads 4000, 300 rounds of [`super::relax`] alone still left a mean angle
//! deviation of 5.1°; 30 of these steps before 30 rounds leave 4.3°.

use super::quality::quad_centre;
use crate::geom::{add, cross, dot, norm, scale, sub, tangent_basis, unit, Vec3};
use crate::mesh::NONE;
use crate::solve::{SolveError, SpdSolver};

/// Weight of each free vertex's stay where it is, against the quads' pull (about 3/4 for each
/// quad round it): a little, so that a part of the quads no fixed vertex holds still has one
/// solution.
const STAY: f64 = 0.05;

/// How far each fitted rectangle is drawn toward a square: its aspect ratio (long side over
/// short) to the power 1 − this, its area kept. Rectangles of free sides square the corners
/// most (over the seven shared meshes' automatic layouts at --quads 4000, a mean angle
/// deviation lower by 0.1–1.6° than with 0.25), but they let strips of quads grow thinner:
/// fandisk's mean aspect ratio rose from 2.07 to 2.84, where with 0.25 it went to 2.28 and on
/// bunny_28k, nefertiti and elephant it fell (2.04 → 1.76, 1.61 → 1.49, 3.16 → 3.04); with
/// 0.5 the angles gained about half as much again as the aspects did.
const SQUARING: f64 = 0.25;

/// The factored least-squares system of the steps over one quad mesh and its free vertices,
/// each moving in the tangent plane it had when the steps began (the surface turns little
/// under a vertex's steps, and one factorization serves them all).
pub struct Rectify {
    quads: Vec<[u32; 4]>,
    /// The unknowns' index (two per vertex, `2k` and `2k + 1`) of each vertex, or [`NONE`] for
    /// one that stays.
    index: Vec<u32>,
    /// Each free vertex's two tangent directions.
    frames: Vec<[Vec3; 2]>,
    unknowns: usize,
    solver: SpdSolver,
}

impl Rectify {
    /// The steps for `quads`, moving the vertices that are `free` in the planes normal to
    /// `normals` (unit surface normals at the vertices).
    ///
    /// The energy of a quad is Σₖ |(pₖ − c) − dₖ|² over its corners, with c their mean and dₖ
    /// the fitted rectangle's corner offsets; its matrix is I − ¼ (the centring, its own
    /// square) on each pair of corners, projected on the corners' tangent planes.
    ///
    /// # Errors
    /// [`SolveError`] if the system cannot be factored (degenerate normals, too large).
    pub fn new(quads: &[[u32; 4]], free: &[bool], normals: &[Vec3]) -> Result<Rectify, SolveError> {
        let mut index = vec![NONE; free.len()];
        let mut unknowns = 0u32;
        for (slot, _) in index.iter_mut().zip(free).filter(|(_, &f)| f) {
            *slot = unknowns;
            unknowns += 1;
        }
        let frames: Vec<[Vec3; 2]> = normals.iter().zip(&index).map(|(&n, &k)| if k == NONE { [[0.0; 3]; 2] } else { tangent_basis(n) }).collect();
        let (mut pattern, mut values) = (Vec::new(), Vec::new());
        for q in quads {
            for (a, b) in (0..4).flat_map(|a| (0..4).map(move |b| (a, b))) {
                let (va, vb) = (q[a] as usize, q[b] as usize);
                if index[va] == NONE || index[vb] == NONE {
                    continue;
                }
                let weight = if a == b { 0.75 } else { -0.25 };
                for (s, t) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (row, col) = (2 * index[va] + s as u32, 2 * index[vb] + t as u32);
                    if row >= col {
                        pattern.push((row, col));
                        values.push(weight * dot(frames[va][s], frames[vb][t]));
                    }
                }
            }
        }
        for row in 0..2 * unknowns {
            pattern.push((row, row));
            values.push(STAY);
        }
        let mut solver = SpdSolver::new(2 * unknowns as usize, &pattern)?;
        solver.factor(&values)?;
        Ok(Rectify { quads: quads.to_vec(), index, frames, unknowns: unknowns as usize, solver })
    }

    /// Where the free vertices would go in one step from `positions` (the others stay), with
    /// `normals` the unit surface normals at the vertices now (each quad's rectangle lies in
    /// the plane normal to their mean at its corners).
    ///
    /// # Errors
    /// [`SolveError`] if the solve fails.
    pub fn step(&mut self, positions: &[Vec3], normals: &[Vec3]) -> Result<Vec<Vec3>, SolveError> {
        let mut rhs = vec![0.0; 2 * self.unknowns];
        for q in &self.quads {
            let p = q.map(|v| positions[v as usize]);
            let centre = quad_centre(&p);
            let target = rectangle(&p, centre, q.map(|v| normals[v as usize]));
            for k in 0..4 {
                let (v, i) = (q[k] as usize, self.index[q[k] as usize]);
                if i != NONE {
                    let pull = sub(target[k], sub(p[k], centre));
                    rhs[2 * i as usize] += dot(self.frames[v][0], pull);
                    rhs[2 * i as usize + 1] += dot(self.frames[v][1], pull);
                }
            }
        }
        self.solver.solve_in_place(&mut rhs)?;
        Ok(positions
            .iter()
            .enumerate()
            .map(|(v, &p)| match self.index[v] {
                NONE => p,
                k => {
                    let [t1, t2] = self.frames[v];
                    add(p, add(scale(rhs[2 * k as usize], t1), scale(rhs[2 * k as usize + 1], t2)))
                }
            })
            .collect())
    }
}

/// The offsets from `centre` of the corners of the rectangle nearest the quad `p`, in the
/// plane normal to the mean of `normals` (the surface's at its corners, so that a quad folded
/// against the surface is drawn back, not fitted as it is), drawn toward a square by
/// [`SQUARING`]. A degenerate quad is fitted by itself (no pull).
fn rectangle(p: &[Vec3; 4], centre: Vec3, normals: [Vec3; 4]) -> [Vec3; 4] {
    let n = unit(normals.iter().fold([0.0; 3], |s, &x| add(s, x)));
    let along = add(sub(p[1], p[0]), sub(p[2], p[3]));
    let e1 = unit(sub(along, scale(dot(along, n), n)));
    let e2 = cross(n, e1);
    let z = p.map(|x| {
        let d = sub(x, centre);
        [dot(d, e1), dot(d, e2)]
    });
    // The quad's two axes (corners 0→1 and 3→2 make the first, 0→3 and 1→2 the second). The
    // rectangle's first axis d₁ maximizes (d₁·m₁)² + (d₂·m₂)² with d₂ = d₁ turned by 90°: the
    // leading eigenvector of m₁m₁ᵀ + m₂'m₂'ᵀ, m₂' being m₂ turned back by 90°.
    let m1 = [z[1][0] + z[2][0] - z[0][0] - z[3][0], z[1][1] + z[2][1] - z[0][1] - z[3][1]];
    let m2 = [z[2][0] + z[3][0] - z[0][0] - z[1][0], z[2][1] + z[3][1] - z[0][1] - z[1][1]];
    let m2t = [m2[1], -m2[0]];
    let (sxx, sxy, syy) = (m1[0] * m1[0] + m2t[0] * m2t[0], m1[0] * m1[1] + m2t[0] * m2t[1], m1[1] * m1[1] + m2t[1] * m2t[1]);
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let mut d1 = [angle.cos(), angle.sin()];
    if d1[0] * m1[0] + d1[1] * m1[1] < 0.0 {
        d1 = [-d1[0], -d1[1]];
    }
    let d2 = [-d1[1], d1[0]];
    // Half sides: the projections of the axes, each the sum of two sides, so a quarter.
    let a = (d1[0] * m1[0] + d1[1] * m1[1]) / 4.0;
    let b = ((d2[0] * m2[0] + d2[1] * m2[1]) / 4.0).abs();
    let stretch = (b / a).powf(-SQUARING / 2.0);
    let (a, b) = (a / stretch, b * stretch);
    let corners = [[-a, -b], [a, -b], [a, b], [-a, b]];
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0 && norm(n) > 0.0 && norm(e1) > 0.0) {
        return p.map(|x| sub(x, centre));
    }
    corners.map(|[x, y]| add(scale(d1[0] * x + d2[0] * y, e1), scale(d1[1] * x + d2[1] * y, e2)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quad that is a rectangle, turned in its plane, is its own fit (when square), and a
    /// sheared one is fitted by a rectangle of its size.
    #[test]
    fn a_rectangle_is_its_own_fit_and_a_sheared_quad_gets_one() {
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let square = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]].map(|[x, y, z]: [f64; 3]| [c * x - s * y, s * x + c * y, z]);
        let up = [[0.0, 0.0, 1.0]; 4];
        let fit = rectangle(&square, [0.0; 3], up);
        for k in 0..4 {
            assert!(norm(sub(fit[k], square[k])) < 1e-12, "{fit:?}");
        }
        let sheared = [[-1.5, -1.0, 0.0], [0.5, -1.0, 0.0], [1.5, 1.0, 0.0], [-0.5, 1.0, 0.0]];
        let fit = rectangle(&sheared, [0.0; 3], up);
        for k in 0..4 {
            let (u, v) = (sub(fit[(k + 1) % 4], fit[k]), sub(fit[(k + 3) % 4], fit[k]));
            assert!(dot(u, v).abs() < 1e-12 * norm(u) * norm(v), "corner {k} of {fit:?} is not right");
        }
        let area = norm(cross(sub(fit[2], fit[0]), sub(fit[3], fit[1]))) / 2.0;
        assert!((area - 4.0).abs() < 0.5, "{area}");
    }

    /// On a plane, steps from a sheared grid with its border fixed make the inner corners
    /// right: a uniform shear of the inside is what the steps undo in one go.
    #[test]
    fn steps_square_a_sheared_grid_inside_a_square_border() {
        let n = 6;
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let quads: Vec<[u32; 4]> = (0..n).flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])).collect();
        let border = |i: usize, j: usize| i == 0 || j == 0 || i == n || j == n;
        let mut positions: Vec<Vec3> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| (i, j)))
            .map(|(i, j)| {
                let shear = if border(i, j) { 0.0 } else { 0.3 * (j as f64 - n as f64 / 2.0) };
                [i as f64 + shear, j as f64, 0.0]
            })
            .collect();
        let free: Vec<bool> = (0..=n).flat_map(|j| (0..=n).map(move |i| !border(i, j))).collect();
        let normals = vec![[0.0, 0.0, 1.0]; positions.len()];
        let skew = |p: &[Vec3]| -> f64 {
            quads.iter().map(|q| super::super::quality::corner_angle_deviations(&q.map(|v| p[v as usize])).iter().sum::<f64>()).sum::<f64>() / (4.0 * quads.len() as f64)
        };
        let before = skew(&positions);
        let mut rectify = Rectify::new(&quads, &free, &normals).unwrap();
        for _ in 0..30 {
            positions = rectify.step(&positions, &normals).unwrap();
        }
        let after = skew(&positions);
        assert!(before > 5.0 && after < 0.5, "mean deviation {before}° -> {after}°");
    }
}
