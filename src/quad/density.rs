//! Desired sample counts that follow each face's surface area (method-notes §10).
//!
//! The paper (Section 4) asks each curve for `length / h` segments. The isometry energy that
//! shapes the charts (Section 3.1) charges compression at most 2 per triangle but stretch
//! without bound, so where the surface bulges (a head, an ear, a whole bunny in one face)
//! the optimized chart ends up smaller than the surface, and a grid of chart-sized quads has
//! far fewer quads than `area / h²`: a one-face disk 24–91 % fewer, bunny-cube 3014 where
//! `area / h²` is 4000. Here each face's chart is first scaled to the face's surface area, and
//! the desired count of a side is its length in the scaled chart over `h`; a curve between
//! two faces takes the mean of its two desires. The least squares and rounding of
//! [`super::counts`] then run unchanged, with one unknown per face and piece
//! ([`IncidenceCounts`]).
//!
//! "Scaled to the face's surface area" is meant for the face's *grid*: a face gets n × m
//! quads, n from its sides 0 and 2, m from its sides 1 and 3, so its grid covers
//! w̄ · h̄ (the mean lengths of opposite sides) in quads of h². That equals the chart's area
//! only for a rectangle; a parallelogram chart of angle θ holds 1/sin θ times more grid
//! cells than area / h². Scaling by s = √(surface area / (w̄ · h̄)) (method-notes §10 says
//! chart area) makes the count what was asked: with the chart's own area the sample layouts
//! got up to 30 % more quads than asked (fandisk-cube, whose charts are trapezoids and
//! rhombi), with w̄ · h̄ they are within 10 % (tests/quad_density.rs).
//!
//! The price: quads spread evenly over the area, where the paper's rule spent more of them
//! on long curves round thin parts. bunny-ears' ear curves got 20 segments at h = 0.014
//! (4324 quads, Hausdorff 1.35 % of the diagonal); at 4000 quads by area they get 11 and the
//! ear tips set the Hausdorff distance (1.62 %).

use crate::layout::SurfaceLayout;
use crate::geom::{cross, norm, sub};
use crate::mesh::geometry::triangle_areas;
use crate::mesh::Mesh;
use crate::param::cut::CutMesh;
use crate::param::ParamSession;
use super::counts::Equation;

/// The surface area of every layout face: the areas of the refined triangles parameterized
/// in its chart.
pub fn face_areas(cut: &CutMesh, faces: usize) -> Vec<f64> {
    let mut area = vec![0.0; faces];
    for (t, &f) in cut.triangles.iter().zip(&cut.triangle_face) {
        let p = t.map(|v| cut.positions[v as usize]);
        if let Some(a) = area.get_mut(f as usize) {
            *a += 0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
        }
    }
    area
}

/// The edge length that gives about `quads` quads on `mesh`: √(surface area / quads)
/// (cli.md, `--quads`). Not finite when `quads` is 0 or the mesh has no area.
pub fn edge_length_for_quads(mesh: &Mesh, quads: f64) -> f64 {
    (triangle_areas(mesh).iter().sum::<f64>() / quads).sqrt()
}

/// The area a face's grid covers in its chart: the mean length of sides 0 and 2 times the mean
/// length of sides 1 and 3 (see the module documentation).
pub fn grid_area(corners: [[f64; 2]; 4]) -> f64 {
    let side = |s: usize| {
        let (a, b) = (corners[s], corners[(s + 1) % 4]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    0.25 * (side(0) + side(2)) * (side(1) + side(3))
}

/// Each face's desired (real) number of segments of each of its pieces at edge length `h`,
/// `[face][piece]` in the order of `Face::pieces`: the chart scaled by
/// s = √(surface area / [`grid_area`]), each piece's scaled chart length over `h`. A face
/// whose chart has no area (a degenerate chart) falls back to the curves' surface lengths,
/// the paper's rule.
pub fn face_desires(layout: &SurfaceLayout, param: &ParamSession, h: f64) -> Vec<Vec<f64>> {
    let areas = face_areas(param.cut(), layout.faces.len());
    let nodes = param.frames().nodes;
    layout
        .faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let chart_area = grid_area(param.charts()[f].corners());
            let s = (areas[f] / chart_area).sqrt();
            (0..face.pieces.len())
                .map(|k| {
                    let (p, q) = (face.nodes[k], face.nodes[(k + 1) % face.nodes.len()]);
                    let length = match (nodes[f].get(&p), nodes[f].get(&q)) {
                        (Some(a), Some(b)) if s.is_finite() && chart_area > 0.0 => s * (b[0] - a[0]).hypot(b[1] - a[1]),
                        _ => layout.curves[face.pieces[k].curve as usize].curve.length,
                    };
                    length / h
                })
                .collect()
        })
        .collect()
}

/// The desired count of every curve: the mean of its faces' desires ([`face_desires`]).
pub fn desired_counts(layout: &SurfaceLayout, desires: &[Vec<f64>]) -> Vec<f64> {
    let mut sum = vec![0.0; layout.curves.len()];
    let mut faces = vec![0u32; layout.curves.len()];
    for (face, wants) in layout.faces.iter().zip(desires) {
        for (d, &w) in face.pieces.iter().zip(wants) {
            sum[d.curve as usize] += w;
            faces[d.curve as usize] += 1;
        }
    }
    sum.iter().zip(&faces).map(|(&s, &n)| if n == 0 { 0.0 } else { s / n as f64 }).collect()
}

/// The sample-count problem of Section 4 with one unknown per (face, piece) incidence rather
/// than per curve: each face's equations on its own incidences, and an equation tying the
/// two incidences of a curve between two faces. Its least squares weighs every face's wish
/// for each of its sides alike, so a curve between two faces weighs twice: once per grid it
/// sizes. With one unknown per curve, a boundary piece would weigh as much as an inner curve
/// shared by two faces, and a layout whose boundary pieces are short and its inner curves
/// long (four faces round a centre on a disk: 8 boundary pieces, 4 spokes twice as long)
/// got 20–28 % fewer quads than its faces asked for. The tied incidences come out equal, at
/// the mean of the faces' desires where nothing else pulls.
pub struct IncidenceCounts {
    /// The curve of every incidence.
    pub curve: Vec<u32>,
    /// Its face's desire.
    pub desired: Vec<f64>,
    pub equations: Vec<Equation>,
}

impl IncidenceCounts {
    /// The problem of `layout` with the faces' `desires` ([`face_desires`]).
    pub fn new(layout: &SurfaceLayout, desires: &[Vec<f64>]) -> IncidenceCounts {
        let mut curve = Vec::new();
        let mut desired = Vec::new();
        let mut equations = Vec::new();
        let mut first: Vec<Option<u32>> = vec![None; layout.curves.len()];
        for (face, wants) in layout.faces.iter().zip(desires) {
            let base = curve.len() as u32;
            for (d, &w) in face.pieces.iter().zip(wants) {
                let at = curve.len() as u32;
                match first[d.curve as usize] {
                    Some(other) => equations.push(vec![(other, 1), (at, -1)]),
                    None => first[d.curve as usize] = Some(at),
                }
                curve.push(d.curve);
                desired.push(w);
            }
            for s in 0..2 {
                let side = |s: usize| {
                    let start = face.corners[s] as u32;
                    (0..face.side(s).len() as u32).map(move |k| base + start + k)
                };
                let mut eq: Equation = side(s).map(|i| (i, 1)).collect();
                eq.extend(side(s + 2).map(|i| (i, -1)));
                equations.push(eq);
            }
        }
        IncidenceCounts { curve, desired, equations }
    }

    /// Counts per curve from counts per incidence (the tied incidences are equal); curves on
    /// no face get one segment.
    pub fn per_curve(&self, counts: &[u32], curves: usize) -> Vec<u32> {
        let mut out = vec![1; curves];
        for (&c, &n) in self.curve.iter().zip(counts).rev() {
            out[c as usize] = n;
        }
        out
    }
}
