//! Known answers of the parameterization (paper Section 3, Fig. 8): flat and developable
//! surfaces whose faces are quadrilaterals come out isometric with 5-DOF charts, and not with
//! rectangles or unit squares. The distortion after each iteration is printed
//! (`cargo test --test param_known_answers -- --nocapture`).

mod common;

use common::layout_json;
use quadlay::layout::{build_layout, parse_layout, SurfaceLayout};
use quadlay::mesh::primitives::quad_grid;
use quadlay::mesh::Mesh;
use quadlay::param::{ParamOptions, ParamSession};

/// Runs `iterations` chart optimizations; returns the mean distortion per iteration and the
/// final solve's (mean, flipped).
fn run(mesh: &Mesh, layout: &str, iterations: usize) -> (Vec<f64>, f64, usize) {
    run_placed(mesh, &build_layout(mesh, &parse_layout(layout).unwrap()).unwrap(), iterations)
}

fn run_placed(mesh: &Mesh, layout: &SurfaceLayout, iterations: usize) -> (Vec<f64>, f64, usize) {
    let mut s = ParamSession::new(mesh, layout, &ParamOptions::default()).unwrap();
    for _ in 0..iterations {
        s.step().unwrap();
    }
    let d = s.finish().unwrap();
    (s.history().iter().map(|h| h.distortion.mean).collect(), d.mean, d.flipped)
}

fn sci(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:.2e}")).collect::<Vec<_>>().join(" ")
}

const Q: [[f64; 2]; 4] = [[0.0, 0.0], [2.0, 0.0], [2.4, 1.3], [0.3, 1.1]];

#[test]
fn a_planar_quadrilateral_becomes_an_isometry_with_quad_charts_only() {
    let n = 16;
    let mesh = quad_grid(Q, n);
    let corners = [0, n, (n + 1) * (n + 1) - 1, n * (n + 1)];
    let (quad, final_quad, flips) = run(&mesh, &layout_json(&corners, &[], "quad"), 30);
    println!("quad chart, mean distortion per iteration: {}", sci(&quad));
    assert_eq!(flips, 0);
    assert!(final_quad < 1e-9, "quad chart: final distortion {final_quad:e}");
    assert!(quad[0] > 1e-2, "the unit chart should be far from isometric: {}", quad[0]);
    let (rect, final_rect, _) = run(&mesh, &layout_json(&corners, &[], "rect"), 12);
    println!("rect chart, mean distortion per iteration: {}", sci(&rect));
    assert!(final_rect > 1e3 * final_quad.max(1e-12), "rect should stay distorted: {final_rect:e}");
    let (_, final_unit, _) = run(&mesh, &layout_json(&corners, &[], "unit"), 3);
    println!("unit chart: {final_unit:.3e}");
    assert!(final_unit > final_rect, "unit {final_unit:e} vs rect {final_rect:e}");
}

#[test]
fn a_planar_quadrilateral_cut_into_2x2_faces_by_curves_across_triangles() {
    // Odd n: the curves between side midpoints run across triangles, not along edges.
    let n = 17;
    let mesh = quad_grid(Q, n - 1);
    let m = n - 1;
    let id = |i: u32, j: u32| j * (m + 1) + i;
    let h = m / 2;
    // Midpoint nodes one vertex off the middle, so the inner curves are not grid lines.
    let nodes = [id(0, 0), id(m, 0), id(m, m), id(0, m), id(h + 1, 0), id(m, h - 1), id(h - 1, m), id(0, h + 1), id(h, h)];
    let edges = [[8, 4], [8, 5], [8, 6], [8, 7]];
    let (quad, final_quad, flips) = run(&mesh, &layout_json(&nodes, &edges, "quad"), 30);
    println!("2x2 quad charts, mean distortion per iteration: {}", sci(&quad));
    assert_eq!(flips, 0);
    assert!(final_quad < 1e-9, "final distortion {final_quad:e}");
    let (rect, final_rect, _) = run(&mesh, &layout_json(&nodes, &edges, "rect"), 15);
    println!("2x2 rect charts: {}", sci(&rect));
    assert!(final_rect > 1e-4, "rect charts should not be isometric here: {final_rect:e}");
}

#[test]
fn the_sheared_cube_is_isometric_with_quad_charts_and_not_with_rectangles() {
    // Paper Fig. 8: a parallelepiped with unit edges, its 12 edges as the layout.
    let (mesh, layout) = common::sheared_cube(8);
    let (quad, final_quad, flips) = run_placed(&mesh, &layout, 20);
    println!("sheared cube, quad charts: {}", sci(&quad));
    assert_eq!(flips, 0);
    assert!(final_quad < 1e-9, "quad charts: {final_quad:e}");
    let (mesh, layout) = common::sheared_cube_with_chart(8, "rect");
    let (rect, final_rect, _) = run_placed(&mesh, &layout, 10);
    println!("sheared cube, rect charts: {}", sci(&rect));
    assert!(final_rect > 1e-3, "rect charts: {final_rect:e}");
}
