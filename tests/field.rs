//! The cross field on the shared meshes (issue 22): Poincaré–Hopf holds on every closed mesh,
//! and the counts of singularities and feature lines are printed (`--nocapture`).

mod common;

use common::load_mesh;
use quadlay::field::{compute_field, DEFAULT_FEATURE_ANGLE};
use quadlay::mesh::topology::topology;

#[test]
fn indices_sum_to_the_euler_characteristic() {
    for name in ["nefertiti.obj", "eight.obj", "bunny_1k8.obj", "mushroom.obj", "fandisk.obj", "bunny_28k.obj", "elephant_44k.obj"] {
        let mesh = load_mesh(name);
        let t0 = std::time::Instant::now();
        let field = compute_field(&mesh, DEFAULT_FEATURE_ANGLE).unwrap();
        let seconds = t0.elapsed().as_secs_f64();
        let topo = topology(&mesh);
        let chi: i64 = topo.components.iter().map(|c| c.euler_characteristic).sum();
        let sum: i64 = field.singularities.iter().map(|s| s.quarter_turns as i64).sum();
        let v3 = field.singularities.iter().filter(|s| s.valence() == 3).count();
        let v5 = field.singularities.iter().filter(|s| s.valence() == 5).count();
        println!(
            "{name}: chi {chi}, {} singularities ({v3} valence 3, {v5} valence 5, index sum {}/4), {} feature lines, {seconds:.3} s",
            field.singularities.len(),
            sum,
            field.features.lines.len()
        );
        if topo.boundary_loops.is_empty() {
            assert_eq!(sum, 4 * chi, "{name}: Poincaré–Hopf");
        }
    }
}
