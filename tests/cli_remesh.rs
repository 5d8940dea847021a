//! `quadlay remesh` as shared/spec/cli.md states it: outputs in every format, the report's
//! fields, `--param-out`, exit status 2 with one `error:` line for bad input, and no output
//! file left behind when a run fails.

mod common;

use common::{run_cli, shared_mesh};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn layout(name: &str) -> String {
    format!("{}/www/layouts/{name}.layout.json", env!("CARGO_MANIFEST_DIR"))
}

/// A fresh scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_remesh").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn mushroom() -> String {
    shared_mesh("mushroom.obj").to_string_lossy().into_owned()
}

/// The report of `quadlay remesh MESH --layout LAYOUT EXTRA... --report -`, which succeeds.
fn remesh_report(mesh: &str, layout: &str, extra: &[&str]) -> Value {
    let mut args = vec!["remesh", mesh, "--layout", layout, "--report", "-"];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = run_cli(&args);
    assert_eq!(code, 0, "{stderr}");
    serde_json::from_str(&stdout).unwrap()
}

#[test]
fn remesh_writes_quads_param_uvs_and_the_report() {
    let dir = scratch("outputs");
    let out = dir.join("q.obj");
    let param = dir.join("p.obj");
    let (code, stdout, stderr) = run_cli(&[
        "remesh",
        &mushroom(),
        "--layout",
        &layout("mushroom-grid"),
        "--iterations",
        "2",
        "-o",
        out.to_str().unwrap(),
        "--param-out",
        param.to_str().unwrap(),
        "--report",
        "-",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).expect("the report alone on standard output");
    // Every field of cli.md's report.
    for path in [
        "/input/vertices", "/input/triangles", "/layout/nodes", "/layout/edges", "/layout/faces", "/layout/t_vertices",
        "/parameterization/distortion_mean", "/parameterization/distortion_max", "/parameterization/flipped_triangles",
        "/quads/vertices", "/quads/faces", "/quads/irregular_vertices", "/quads/hausdorff",
        "/parameterization/length_error", "/seconds/load", "/seconds/layout",
        "/seconds/parameterize", "/seconds/mesh", "/seconds/total",
    ] {
        assert!(report.pointer(path).is_some_and(|v| v.is_number()), "report misses {path}: {report}");
    }
    assert_eq!(report["input"]["vertices"], 2337);
    assert_eq!(report["layout"]["faces"], 4);
    let iterations = report["iterations"].as_array().unwrap();
    assert_eq!(iterations.len(), 3, "initial + 2 iterations");
    for (k, it) in iterations.iter().enumerate() {
        assert_eq!(it["iteration"], k);
        assert!(it["distortion"].as_f64().unwrap() >= 0.0 && it["seconds"].as_f64().unwrap() >= 0.0);
    }

    let quads = std::fs::read_to_string(&out).unwrap();
    let faces: Vec<&str> = quads.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(faces.len() as u64, report["quads"]["faces"].as_u64().unwrap());
    assert!(faces.iter().all(|f| f.split_whitespace().count() == 5), "every face a quad");
    assert_eq!(quads.lines().filter(|l| l.starts_with("v ")).count() as u64, report["quads"]["vertices"].as_u64().unwrap());

    // The input mesh with one vt per triangle corner, each triangle in one chart.
    let p = std::fs::read_to_string(&param).unwrap();
    assert_eq!(p.lines().filter(|l| l.starts_with("v ")).count(), 2337);
    assert_eq!(p.lines().filter(|l| l.starts_with("f ")).count(), 4608);
    assert_eq!(p.lines().filter(|l| l.starts_with("vt ")).count(), 3 * 4608);
    let uv_ok = p
        .lines()
        .filter(|l| l.starts_with("vt "))
        .all(|l| l.split_whitespace().skip(1).all(|x| x.parse::<f64>().is_ok_and(f64::is_finite)));
    assert!(uv_ok);
    // Nothing else was left in the directory (no temporary files).
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
}

#[test]
fn every_output_format_reads_back_with_the_same_surface() {
    let dir = scratch("formats");
    let mut faces = Vec::new();
    for name in ["q.obj", "q.ply", "q.glb", "q.gltf"] {
        let out = dir.join(name);
        let (code, _, stderr) =
            run_cli(&["remesh", &mushroom(), "--layout", &layout("mushroom-4"), "--iterations", "0", "-o", out.to_str().unwrap()]);
        assert_eq!(code, 0, "{name}: {stderr}");
        let bytes = std::fs::read(&out).unwrap();
        let mesh = quadlay::io::read_mesh(&bytes, name).unwrap_or_else(|e| panic!("{name}: {e}")).mesh;
        faces.push(mesh.n_faces());
    }
    // OBJ and PLY keep quads (read back as two triangles each), GLB/glTF split them: the same.
    assert!(faces.iter().all(|&f| f == faces[0] && f > 100), "{faces:?}");
}

#[test]
fn bad_input_gives_exit_2_and_one_error_line_and_no_output() {
    let dir = scratch("errors");
    let out = dir.join("q.obj");
    let out = out.to_str().unwrap();
    let broken = dir.join("broken.layout.json");
    std::fs::write(&broken, r#"{"format":"quad-layout","version":1,"nodes":[{"vertex":0}],"edges":[{"nodes":[0,7]}]}"#).unwrap();
    let m = mushroom();
    let l = layout("mushroom-grid");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["remesh", &m], "--layout"),
        (vec!["remesh", &m, "--layout", broken.to_str().unwrap(), "-o", out], "edges[0]"),
        (vec!["remesh", &m, "--layout", &l, "--edge-length", "0", "-o", out], "--edge-length"),
        (vec!["remesh", &m, "--layout", &l, "--edge-length", "NaN", "-o", out], "--edge-length"),
        (vec!["remesh", &m, "--layout", &l, "--edge-length", "abc", "-o", out], "not a number"),
        (vec!["remesh", &m, "--layout", &l, "--edge-length", "1e-7", "-o", out], "quads"),
        (vec!["remesh", &m, "--layout", &l, "--quads", "0", "-o", out], "--quads"),
        (vec!["remesh", &m, "--layout", &l, "--quads", "1.5", "-o", out], "--quads: '1.5' is not a whole number"),
        (vec!["remesh", &m, "--layout", &l, "--quads", "100", "--edge-length", "0.1", "-o", out], "not both"),
        (vec!["remesh", &m, "--layout", &l, "--chart", "hexagon", "-o", out], "--chart"),
        (vec!["remesh", &m, "--layout", &l, "--iterations", "-1", "-o", out], "--iterations"),
        (vec!["remesh", &m, "--layout", &l, "-o", "q.xyz"], "q.xyz"),
        (vec!["remesh", &m, "--layout", &l, "--param-out", "p.ply"], "p.ply"),
        (vec!["remesh", &m, "--layout", &l, "--bogus"], "--bogus"),
        (vec!["remesh", "no-such-mesh.obj", "--layout", &l, "-o", out], "no-such-mesh.obj"),
    ];
    for (args, names) in cases {
        let (code, stdout, stderr) = run_cli(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stdout.is_empty(), "{args:?}: {stdout}");
        let lines: Vec<&str> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
        assert!(lines[0].starts_with("error: ") && lines[0].contains(names), "{args:?}: {stderr}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "only the broken layout is there");
}

/// `--quads N` asks for a count (cli.md): the mushroom's 2×2 grid gets it within 10 %.
#[test]
fn quads_option_asks_for_a_number_of_quads() {
    let (m, l) = (mushroom(), layout("mushroom-grid"));
    for asked in [400u64, 2500] {
        let n = asked.to_string();
        let (code, stdout, stderr) = run_cli(&["remesh", &m, "--layout", &l, "--quads", &n, "--report", "-"]);
        assert_eq!(code, 0, "{stderr}");
        let report: Value = serde_json::from_str(&stdout).unwrap();
        let got = report["quads"]["faces"].as_u64().unwrap();
        println!("mushroom-grid --quads {asked}: {got} quads");
        assert!((got as f64 / asked as f64 - 1.0).abs() < 0.1, "asked {asked}, got {got}");
    }
}

/// The verdict (cli.md, "Report"): a clean result has no warnings; the bunny in a cube at the
/// default density misses the surface (its ears and head bulge far out of the cube's faces,
/// 21 % of the diagonal) and says where, on the bunny's surface.
#[test]
fn warnings_say_what_to_look_at_and_a_clean_result_has_none() {
    let run = |mesh: &str, layout_name: &str| remesh_report(mesh, &layout(layout_name), &[]);
    let clean = run(&mushroom(), "mushroom-grid");
    assert_eq!(clean["warnings"], serde_json::json!([]), "{}", clean["warnings"]);
    let faces = clean["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 4);
    for f in faces {
        for key in ["area", "curvature_deg", "distortion", "length_error"] {
            assert!(f[key].is_number(), "faces[].{key}: {f}");
        }
        assert_eq!(f["needs_node"], false, "{f}");
    }

    let bunny = shared_mesh("bunny_28k.obj").to_string_lossy().into_owned();
    let bad = run(&bunny, "bunny-cube");
    let warnings = bad["warnings"].as_array().unwrap();
    println!("bunny-cube: {}", serde_json::to_string_pretty(warnings).unwrap());
    let missed = warnings.iter().find(|w| w["kind"] == "surface_missed").expect("surface_missed");
    assert!(missed["message"].as_str().unwrap().contains("miss the surface"));
    let at: Vec<f64> = missed["at"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let mesh = quadlay::io::read_mesh(&std::fs::read(&bunny).unwrap(), "bunny_28k.obj").unwrap().mesh;
    let nearest = mesh
        .positions()
        .iter()
        .map(|p| ((p[0] - at[0]).powi(2) + (p[1] - at[1]).powi(2) + (p[2] - at[2]).powi(2)).sqrt())
        .fold(f64::INFINITY, f64::min);
    assert!(nearest < 0.01, "the point is on the bunny: {nearest} from its nearest vertex");
    assert!(bad["quads"]["hausdorff"].as_f64().unwrap() > 0.1);
    // The cube's faces each hold far more than the 45° that asks for a node (the bunny's
    // 720° spread over six faces), and most get a suggestion on the mesh.
    let suggested = bad["faces"].as_array().unwrap().iter().filter(|f| f["suggestion"]["vertex"].is_u64()).count();
    assert!(suggested >= 3, "{}", bad["faces"]);
}

/// Curves whose quads are forced far longer than their faces ask for are a warning
/// (`counts_stretched`) naming them, the most stretched first: bunny-ears at 4000 quads gives
/// its edge 36, on an ear, one segment where its faces ask for about five. At the default
/// density the same layout's counts follow its faces, and nothing is said.
#[test]
fn curves_whose_quads_are_stretched_are_named() {
    let (bunny, ears) = (shared_mesh("bunny_28k.obj").to_string_lossy().into_owned(), layout("bunny-ears"));
    let dense = remesh_report(&bunny, &ears, &["--quads", "4000"]);
    let warnings = dense["warnings"].as_array().unwrap();
    let stretched = warnings.iter().find(|w| w["kind"] == "counts_stretched").expect("counts_stretched");
    let edges: Vec<u64> = stretched["edges"].as_array().unwrap().iter().map(|e| e.as_u64().unwrap()).collect();
    assert_eq!(edges.first(), Some(&36), "{stretched}");
    assert_eq!(stretched["count"].as_u64(), Some(edges.len() as u64), "{stretched}");
    let counts = dense["sample_counts"].as_array().unwrap();
    assert_eq!(counts[36], 1, "the report's counts agree");
    assert!(stretched["message"].as_str().unwrap().contains("layout edge 36: 1 segment where"), "{stretched}");
    assert!(stretched["at"].as_array().is_some_and(|a| a.len() == 3), "{stretched}");
    let sparse = remesh_report(&bunny, &ears, &[]);
    assert!(sparse["warnings"].as_array().unwrap().iter().all(|w| w["kind"] != "counts_stretched"), "{}", sparse["warnings"]);
}

/// A quad count far from what was asked is a warning (`quad_count_off`): the mushroom's 2×2
/// grid at 3 quads must give each of its curves a segment at least, 4 quads; at 2000 it
/// lands within the tolerance and says nothing.
#[test]
fn a_quad_count_far_from_the_asked_one_is_a_warning() {
    let run = |quads: &str| remesh_report(&mushroom(), &layout("mushroom-grid"), &["--quads", quads]);
    let coarse = run("3");
    let off: Vec<&Value> = coarse["warnings"].as_array().unwrap().iter().filter(|w| w["kind"] == "quad_count_off").collect();
    assert_eq!(off.len(), 1, "{}", coarse["warnings"]);
    assert_eq!(off[0]["count"], coarse["quads"]["faces"]);
    assert_eq!(coarse["quads"]["faces"], 4);
    assert!(off[0]["message"].as_str().unwrap().contains("more"), "{}", off[0]["message"]);
    let fine = run("2000");
    assert!(fine["warnings"].as_array().unwrap().iter().all(|w| w["kind"] != "quad_count_off"), "{}", fine["warnings"]);
}

/// A layout made for another mesh (layout-format.md, `mesh`) is refused when it names
/// vertices by index, naming `mesh` and both counts; with points only it is placed.
#[test]
fn a_layout_for_another_mesh_is_refused() {
    let dir = scratch("other-mesh");
    let by_index = dir.join("by-index.layout.json");
    let text = r#"{"format":"quad-layout","version":1,"nodes":[{"vertex":0},{"vertex":1},{"vertex":2},{"vertex":3}],
                   "edges":[],"mesh":{"vertices":2337,"triangles":4608}}"#;
    std::fs::write(&by_index, text).unwrap();
    let nefertiti = shared_mesh("nefertiti.obj").to_string_lossy().into_owned();
    let (code, stdout, stderr) = run_cli(&["check", &nefertiti, "--layout", by_index.to_str().unwrap()]);
    assert_eq!((code, stdout.as_str()), (2, ""), "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{stderr}");
    for part in ["by-index.layout.json: mesh: ", "2337 vertices and 4608 triangles", "299 vertices and 562 triangles"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    // The sample layouts give points: their `mesh` says where they were drawn, nothing more
    // (on nefertiti the mushroom's layout fails for its own reasons, not for `mesh`).
    let (_, _, stderr) = run_cli(&["check", &nefertiti, "--layout", &layout("mushroom-grid")]);
    assert!(!stderr.contains("mesh: "), "{stderr}");
}

#[test]
fn chart_and_no_align_options_change_the_result() {
    let (m, l) = (mushroom(), layout("mushroom-grid"));
    let run = |extra: &[&str]| remesh_report(&m, &l, extra);
    let quad = run(&["--iterations", "3"]);
    let unit = run(&["--iterations", "3", "--chart", "unit"]);
    let d = |r: &Value| r["parameterization"]["distortion_mean"].as_f64().unwrap();
    println!("mushroom-grid: quad charts {:.4}, unit charts {:.4}", d(&quad), d(&unit));
    assert!(d(&quad) < d(&unit));
    let free = run(&["--no-align"]);
    assert_ne!(d(&free), d(&run(&[])), "--no-align releases the tagged edges");
}

/// `quadlay remesh ... --report - | head -1`: the reader is gone before the report is written.
/// The run fails with exit status 1 and one `error:` line, not a panic.
#[test]
fn a_closed_standard_output_is_an_error_not_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_quadlay"))
        .args(["remesh", &mushroom(), "--layout", &layout("mushroom-grid"), "--report", "-"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // close the pipe's reading end
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(stderr.lines().collect::<Vec<_>>(), ["error: standard output: cannot write: Broken pipe (os error 32)"]);
}
