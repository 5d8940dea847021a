//! The repairs a user asks for (cli.md, "Repairs the user asks for") on a raw-scan-like
//! mesh: the bunny with three holes cut into it and a loose speck beside it, which `remesh`
//! refuses as it is (the speck has no layout nodes) and takes after `--keep-largest
//! --fill-holes N`.

mod common;

use common::{load_mesh, obj_text, run_cli};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_repairs").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).powi(2)).sum()
}

/// bunny_28k with the stars of three vertices far from the layout's nodes (and from each
/// other) removed, plus one triangle far away; and bunny-cube's layout without its `mesh`
/// entry (this is another mesh now). Returns the mesh and layout files.
fn raw_bunny(dir: &Path) -> (String, String) {
    let bunny = load_mesh("bunny_28k.obj");
    let layout_path = format!("{}/www/layouts/bunny-cube.layout.json", env!("CARGO_MANIFEST_DIR"));
    let mut layout: Value = serde_json::from_str(&std::fs::read_to_string(&layout_path).unwrap()).unwrap();
    layout.as_object_mut().unwrap().remove("mesh");
    let mut avoid: Vec<[f64; 3]> = layout["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| match n.get("point") {
            Some(p) => [0, 1, 2].map(|c| p[c].as_f64().unwrap()),
            None => bunny.position(n["vertex"].as_u64().unwrap() as u32),
        })
        .collect();
    let mut centres = Vec::new();
    for _ in 0..3 {
        let far = (0..bunny.n_vertices() as u32)
            .max_by(|&a, &b| {
                let d = |v: u32| avoid.iter().map(|&p| dist2(bunny.position(v), p)).fold(f64::INFINITY, f64::min);
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        centres.push(far);
        avoid.push(bunny.position(far));
    }
    let mut positions = bunny.positions().to_vec();
    let mut triangles: Vec<[u32; 3]> =
        bunny.triangles().iter().copied().filter(|t| !t.iter().any(|v| centres.contains(v))).collect();
    let s = positions.len() as u32;
    positions.extend([[5.0, 5.0, 5.0], [5.01, 5.0, 5.0], [5.0, 5.01, 5.0]]);
    triangles.push([s, s + 1, s + 2]);
    let raw = common::mesh_of(positions, triangles);
    let mesh_file = dir.join("raw.obj");
    std::fs::write(&mesh_file, obj_text(&raw)).unwrap();
    let layout_file = dir.join("cube.layout.json");
    std::fs::write(&layout_file, layout.to_string()).unwrap();
    (mesh_file.to_string_lossy().into_owned(), layout_file.to_string_lossy().into_owned())
}

#[test]
fn check_lists_the_repairs_and_the_mesh_they_give() {
    let dir = scratch("check");
    let (mesh, _) = raw_bunny(&dir);
    let (code, before, _) = run_cli(&["check", &mesh]);
    assert_eq!(code, 0);
    // Three holes in the bunny, and the speck's own rim.
    assert!(before.contains("boundary loops: 4") && before.contains("components:     2"), "{before}");
    let (code, after, stderr) = run_cli(&["check", &mesh, "--keep-largest", "--fill-holes", "30"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(after.contains("boundary loops: 0") && after.contains("components:     1"), "{after}");
    assert!(after.contains("1 other components (1 triangles) removed"), "{after}");
    assert!(after.contains("3 holes filled"), "{after}");
    // A limit below the holes' length (a vertex star's rim, 5 edges or more) leaves them open.
    let (_, small, _) = run_cli(&["check", &mesh, "--keep-largest", "--fill-holes", "4"]);
    assert!(small.contains("boundary loops: 3") && !small.contains("holes filled"), "{small}");
}

#[test]
fn remesh_takes_the_raw_scan_after_the_repairs_and_reports_them() {
    let dir = scratch("remesh");
    let (mesh, layout) = raw_bunny(&dir);
    let (code, _, stderr) = run_cli(&["remesh", &mesh, "--layout", &layout]);
    assert_eq!(code, 2, "the speck and the holes have no layout nodes: {stderr}");
    let (code, stdout, stderr) =
        run_cli(&["remesh", &mesh, "--layout", &layout, "--keep-largest", "--fill-holes", "30", "--report", "-"]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).unwrap();
    let repairs = &report["input"]["repairs"];
    assert_eq!(repairs["removed_components"], 1, "{repairs}");
    assert_eq!(repairs["filled_holes"], 3, "{repairs}");
    assert!(report["quads"]["faces"].as_u64().unwrap() > 100);
}

#[test]
fn a_bad_repair_option_is_an_error_line() {
    for args in [vec!["--fill-holes"], vec!["--fill-holes", "two"], vec!["--fill-holes", "2"]] {
        let mut all = vec!["check", "../shared/meshes/mushroom.obj"];
        all.extend(args.iter());
        let (code, _, stderr) = run_cli(&all);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: --fill-holes") && stderr.lines().count() == 1, "{stderr}");
    }
}
