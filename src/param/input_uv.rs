//! Parameter coordinates of the input's own triangles (`quadlay remesh --param-out`).
//!
//! We solve on the mesh refined along the curves ([`super::cut`]), where every triangle lies
//! in one face. The input's triangles that a curve crosses are split there between charts;
//! the paper parameterizes such a triangle in one chart, with the corners across the curve
//! brought in by the transition (eq. 4, Fig. 6a). This module does exactly that: each input
//! triangle in the chart of its face (`SurfaceLayout::triangle_face`), each corner's
//! coordinates from a refined triangle that holds it, carried across the curves inside the
//! triangle by their transitions.

use super::transition::Affine;
use super::ParamSession;
use crate::layout::SurfaceLayout;
use crate::mesh::{Mesh, NONE};

/// Per input triangle, its three corners' coordinates in the chart it is parameterized in.
/// Triangles no refined triangle covers (zero area) get their chart's origin.
pub fn input_corner_uv(mesh: &Mesh, layout: &SurfaceLayout, param: &ParamSession) -> Vec<[[f64; 2]; 3]> {
    let cut = param.cut();
    let uv = &param.solution().corner_uv;
    let frames = param.frames();
    let mut pieces: Vec<Vec<u32>> = vec![Vec::new(); mesh.n_faces()];
    for (t, &o) in cut.triangle_origin.iter().enumerate() {
        pieces[o as usize].push(t as u32);
    }
    mesh.triangles()
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            let chart = layout.triangle_face[t];
            let own = &pieces[t];
            // The curves inside this triangle: those of its refined vertices.
            let mut curves: Vec<u32> = own
                .iter()
                .flat_map(|&p| cut.triangles[p as usize])
                .map(|v| cut.vertex_curve[v as usize])
                .filter(|&c| c != NONE)
                .collect();
            curves.sort_unstable();
            curves.dedup();
            tri.map(|v| {
                // Prefer a refined triangle in the chart itself; else carry the coordinates
                // over from another face, crossing the triangle's curves (breadth first).
                let holders = || own.iter().flat_map(|&p| (0..3).map(move |k| (p, k)));
                let mut found: Vec<(u32, [f64; 2])> = holders()
                    .filter(|&(p, k)| cut.triangles[p as usize][k] == v)
                    .map(|(p, k)| (cut.triangle_face[p as usize], uv[p as usize][k]))
                    .collect();
                found.sort_by_key(|&(f, _)| f != chart);
                let Some(&(face, x)) = found.first() else { return [0.0, 0.0] };
                let mut frontier = vec![(face, Affine::IDENTITY)];
                let mut seen = vec![face];
                while let Some((f, map)) = frontier.pop() {
                    if f == chart {
                        return map.apply(x);
                    }
                    for &c in &curves {
                        if let Some((g, step)) = frames.across(c, f) {
                            if !seen.contains(&g) {
                                seen.push(g);
                                frontier.insert(0, (g, step.after(&map)));
                            }
                        }
                    }
                }
                x
            })
        })
        .collect()
}
