//! Hostile input (issue 21): inputs that once wrapped counts, ran out of memory, hung, or
//! printed what they were given unescaped. Each must give exit status 2 and one `error:`
//! line naming the element (shared/spec/cli.md), quickly and in bounded memory. The inputs
//! are made here; the big ones are refused before anything of their size is allocated, so
//! every test runs in seconds.

mod common;

use common::{run_cli, shared_mesh};
use std::path::{Path, PathBuf};

fn layout(name: &str) -> String {
    format!("{}/www/layouts/{name}.layout.json", env!("CARGO_MANIFEST_DIR"))
}

fn mushroom() -> String {
    shared_mesh("mushroom.obj").to_string_lossy().into_owned()
}

/// A fresh scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hostile_input").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the command line and returns its one `error:` line, checking exit status 2 and that
/// standard error holds nothing else.
fn one_error_line(args: &[&str]) -> String {
    let (code, stdout, stderr) = run_cli(args);
    assert_eq!(code, 2, "{args:?}: exit {code}, stdout {stdout:.300}, stderr {stderr:.300}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line expected: {stderr:.600}");
    assert!(lines[0].starts_with("error: "), "{stderr:.300}");
    lines[0].to_string()
}

/// Item 1: per-side counts summed as u32 and products as usize wrapped past the cap (an
/// abort natively, a trap in wasm), and the message printed a wrapped number.
#[test]
fn edge_lengths_whose_counts_overflow_are_refused_with_the_real_count() {
    let grid = layout("mushroom-grid");
    for l in ["2e-10", "3e-7"] {
        let line = one_error_line(&["remesh", &mushroom(), "--layout", &grid, "--edge-length", l]);
        assert!(line.contains("mushroom-grid.layout.json") && line.contains("quads"), "{line}");
        assert!(line.contains("choose a longer edge length"), "{line}");
        // The estimate printed is the surface's area over the edge length squared, not a
        // wrapped remainder: the mushroom's area is of the order of one.
        let about = line.split("about ").nth(1).and_then(|s| s.split(' ').next()).expect(&line);
        let quads: f64 = about.parse().expect(&line);
        let h: f64 = l.parse().unwrap();
        assert!(quads > 1e-3 / (h * h) && quads < 1e3 / (h * h), "{l}: {line}");
    }
    // 1e600 quads: beyond any number a count holds, said so rather than wrapped.
    let line = one_error_line(&["remesh", &mushroom(), "--layout", &grid, "--edge-length", "1e-300"]);
    assert!(line.contains("more quads than can be counted"), "{line}");
}

/// Item 2: an edge length below ~1e-308 made every count infinite, and infinite counts were
/// taken as one: the coarsest mesh, exit 0.
#[test]
fn an_edge_length_so_small_that_counts_are_infinite_is_refused() {
    let line = one_error_line(&["remesh", &mushroom(), "--layout", &layout("mushroom-grid"), "--edge-length", "1e-320"]);
    assert!(line.contains("more quads than can be counted"), "{line}");
}

/// A layout document with `nodes` and no edges, as text.
fn layout_text(nodes: &str) -> String {
    format!(r#"{{"format": "quad-layout", "version": 1, "nodes": [{nodes}], "edges": []}}"#)
}

/// Item 7: a key, token or option value of megabytes became an error line of megabytes,
/// and control bytes (escape sequences) reached the terminal.
#[test]
fn error_lines_quote_input_cut_short_and_escaped() {
    let dir = scratch("quoting");
    let short_and_clean = |line: &str| {
        assert!(line.len() < 400, "{} bytes: {:.300}", line.len(), line);
        assert!(!line.chars().any(char::is_control), "{line:?}");
    };
    let huge = "k".repeat(5_000_000);
    // A layout key: of megabytes, and one holding an escape sequence and a newline.
    for (key, shows) in [(huge.as_str(), "… (5000000 bytes)"), ("\u{1b}[2J\u{1b}[31mred\nline", "\\u{1b}[2J")] {
        let path = dir.join("key.layout.json");
        let json_key = serde_json::to_string(key).unwrap();
        std::fs::write(&path, layout_text(&format!(r#"{{"vertex": 0, {json_key}: 1}}"#))).unwrap();
        let line = one_error_line(&["check", &mushroom(), "--layout", path.to_str().unwrap()]);
        short_and_clean(&line);
        assert!(line.contains("nodes[0]: unknown key 'k") || line.contains("nodes[0]: unknown key '\\u{1b}"), "{line}");
        assert!(line.contains(shows), "{line}");
    }
    // A mesh token.
    let obj = dir.join("token.obj");
    std::fs::write(&obj, format!("v 0 0 0\nv 1 {huge}\u{1b}[31m 0\n")).unwrap();
    let line = one_error_line(&["check", obj.to_str().unwrap()]);
    short_and_clean(&line);
    assert!(line.contains("OBJ line 2: 'kkk") && line.contains("is not a number"), "{line}");
    // An option value (as long as one argument may be) and a file name with control bytes.
    let long = &huge[..100_000];
    let line = one_error_line(&["remesh", &mushroom(), "--layout", "x.json", "--chart", &format!("\u{1b}]0;owned\u{7}{long}")]);
    short_and_clean(&line);
    assert!(line.contains("--chart: '\\u{1b}]0;owned\\u{7}kkk"), "{line}");
    let line = one_error_line(&["check", "no\u{1b}[31mfile.obj"]);
    short_and_clean(&line);
    assert!(line.contains("no\\u{1b}[31mfile.obj: cannot read"), "{line}");
}

/// Item 8: the zero-area test squared the cross product, which underflows (overflows) for
/// meshes in units near 1e-80 (1e80): every face was dropped, "a mesh with no faces".
#[test]
fn meshes_at_extreme_scales_keep_their_faces() {
    let dir = scratch("scales");
    let grid = common::grid(6);
    for scale in [1e-80, 1e-150, 1e80, 1e150, 1e300] {
        let mut text = String::new();
        for p in grid.positions() {
            text += &format!("v {:e} {:e} {:e}\n", p[0] * scale, p[1] * scale, (p[0] * p[1]) * scale);
        }
        for t in grid.triangles() {
            text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        let path = dir.join(format!("grid-{scale:e}.obj"));
        std::fs::write(&path, text).unwrap();
        let (code, stdout, stderr) = run_cli(&["check", path.to_str().unwrap()]);
        assert_eq!(code, 0, "{scale:e}: {stderr}");
        // Refined (a coarse mesh, mesh/refine.rs) from all 72 triangles, none dropped.
        assert!(stdout.contains("from 49 vertices and 72 triangles"), "{scale:e}: {stdout}");
        assert!(!stdout.contains("zero-area faces removed"), "{scale:e}: {stdout}");
    }
    // Flat triangles are still flat at any scale, and a mesh of nothing else is refused by
    // saying so.
    for scale in [1e-80, 1.0, 1e80] {
        let path = dir.join("flat.obj");
        let text = format!("v 0 0 0\nv {0:e} 0 0\nv {1:e} 0 0\nv {0:e} {0:e} 0\nf 1 2 3\nf 1 3 4\n", scale, 2.0 * scale);
        std::fs::write(&path, text).unwrap();
        let (code, stdout, stderr) = run_cli(&["check", path.to_str().unwrap()]);
        assert_eq!(code, 0, "{scale:e}: {stderr}");
        assert!(stdout.contains(" 1 zero-area faces removed"), "{scale:e}: {stdout}");
        std::fs::write(&path, format!("v 0 0 0\nv {0:e} 0 0\nv {1:e} 0 0\nf 1 2 3\n", scale, 2.0 * scale)).unwrap();
        let line = one_error_line(&["check", path.to_str().unwrap()]);
        assert!(line.contains("all 1 triangles") && line.contains("triangle 0"), "{line}");
    }
}

/// Item 9: a vertex index past u32 said "the mesh has 0 vertices".
#[test]
fn a_vertex_index_past_32_bits_is_told_the_real_vertex_count() {
    let dir = scratch("vertex-index");
    for v in ["4294967296", "18446744073709551615", "2337"] {
        let path = dir.join("v.layout.json");
        std::fs::write(&path, layout_text(&format!(r#"{{"vertex": {v}}}"#))).unwrap();
        let line = one_error_line(&["check", &mushroom(), "--layout", path.to_str().unwrap()]);
        assert!(line.ends_with(&format!("nodes[0]: vertex {v} does not exist (the mesh has 2337 vertices)")), "{line}");
    }
}

/// Item 3: edge lengths under the old cap of twenty million quads ran out of memory (about
/// 650 bytes a quad: an abort with a backtrace natively, a trap in the page). They are
/// refused up front, with the count and the memory they would take.
#[test]
fn an_edge_length_beyond_the_memory_budget_is_refused_up_front() {
    // mushroom-4 has about 576 quads at its default edge length of 0.035: 0.0003 asks for
    // about nine million.
    let line = one_error_line(&["remesh", &mushroom(), "--layout", &layout("mushroom-4"), "--edge-length", "0.0003"]);
    let number_after = |key: &str| -> f64 {
        let rest = line.split(key).nth(1).expect(&line);
        rest.split(' ').next().and_then(|x| x.parse().ok()).expect(&line)
    };
    let quads = number_after("about ");
    assert!((5e6..2e7).contains(&quads), "{line}");
    let gb = number_after("would take about ");
    assert!((gb - quads * quadlay::quad::BYTES_PER_QUAD as f64 / 1e9).abs() < 0.1, "{line}");
    assert!(line.contains(&format!("the budget is {} quads", quadlay::quad::MAX_QUADS)), "{line}");
}

/// Item 6: every waypoint is a geodesic leg traced over the mesh (about a millisecond each
/// on the bunny): a layout of 100,000 waypoints ran for minutes before failing. The count
/// is refused when the file is read, naming the edge where it passes the cap.
#[test]
fn a_layout_with_more_waypoints_than_the_cap_is_refused_when_read() {
    use quadlay::layout::{parse_layout, MAX_WAYPOINTS};
    let dir = scratch("waypoints");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(layout("mushroom-grid")).unwrap()).unwrap();
    // Half the cap on edges[1], the rest and one more on edges[3].
    let via = |n: usize| serde_json::Value::Array((0..n).map(|k| serde_json::json!({ "vertex": k % 2 })).collect());
    doc["edges"][1]["via"] = via(MAX_WAYPOINTS / 2);
    doc["edges"][3]["via"] = via(MAX_WAYPOINTS / 2);
    let at_cap = parse_layout(&doc.to_string()).expect("at the cap");
    assert_eq!(at_cap.edges.iter().map(|e| e.via.len()).sum::<usize>(), MAX_WAYPOINTS);
    doc["edges"][3]["via"] = via(MAX_WAYPOINTS / 2 + 1);
    let path = dir.join("many.layout.json");
    std::fs::write(&path, doc.to_string()).unwrap();
    let line = one_error_line(&["check", &mushroom(), "--layout", path.to_str().unwrap()]);
    assert!(line.contains(&format!("edges[3].via: the layout has more than {MAX_WAYPOINTS} waypoints")), "{line}");
}

/// The remesh of the mushroom with the 2 × 2 grid, once, with `extra` options.
fn remesh_mushroom(extra: &[&str]) -> (i32, String, String) {
    let mut args = vec!["remesh".to_string(), mushroom(), "--layout".into(), layout("mushroom-grid"), "--iterations".into(), "0".into()];
    args.extend(extra.iter().map(|s| s.to_string()));
    run_cli(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Also found: `--report` naming the `-o` file replaced the quad mesh with the JSON, and `-o`
/// naming the input overwrote it. Both are refused before anything runs.
#[test]
fn outputs_that_name_an_input_or_each_other_are_refused() {
    let dir = scratch("same-file");
    let out = dir.join("q.obj");
    let out = out.to_str().unwrap();
    std::fs::write(out, "old").unwrap();
    // The same file, also spelled differently.
    let other_spelling = format!("{}/./q.obj", dir.to_str().unwrap());
    for report in [out, other_spelling.as_str()] {
        let line = one_error_line(&["remesh", &mushroom(), "--layout", &layout("mushroom-grid"), "-o", out, "--report", report]);
        assert!(line.contains("--report and --out name the same file"), "{line}");
    }
    assert_eq!(std::fs::read_to_string(out).unwrap(), "old", "left alone");
    // The input mesh (a copy: a failing test must not overwrite the shared one).
    let input = dir.join("in.obj");
    std::fs::copy(shared_mesh("mushroom.obj"), &input).unwrap();
    let input = input.to_str().unwrap();
    let line = one_error_line(&["remesh", input, "--layout", &layout("mushroom-grid"), "-o", input]);
    assert!(line.contains("--out names the input mesh"), "{line}");
    assert_eq!(std::fs::read(input).unwrap(), std::fs::read(shared_mesh("mushroom.obj")).unwrap());
    let param = dir.join("p.obj");
    let line = one_error_line(&["remesh", input, "--layout", &layout("mushroom-grid"), "-o", param.to_str().unwrap(), "--param-out", param.to_str().unwrap()]);
    assert!(line.contains("--param-out and --out name the same file"), "{line}");
}

/// Also found: a report that could not be written (exit 1) left the new `-o` file behind,
/// and a killed run its hidden temporary file. All or nothing, stale temporaries removed.
#[test]
fn a_failed_run_leaves_no_output_and_stale_temporaries_are_removed() {
    let dir = scratch("all-or-nothing");
    let out = dir.join("q.obj");
    let report = dir.join("no such directory").join("r.json");
    let (code, _, stderr) = remesh_mushroom(&["-o", out.to_str().unwrap(), "--report", report.to_str().unwrap()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains("r.json: cannot write"), "{stderr}");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.file_name()).collect();
    assert!(left.is_empty(), "left behind: {left:?}");

    // A temporary of a run that was killed (no process has this id: ids stay below 2^22).
    let stale = dir.join(".q.obj.999999999.tmp");
    std::fs::write(&stale, "half a mesh").unwrap();
    let (code, _, stderr) = remesh_mushroom(&["-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!stale.exists(), "the stale temporary is removed");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("q.obj")]);
}

/// Also found: `--report -` into a closed standard output exited 0 and lost the report
/// (Rust takes writes to a closed descriptor for success).
#[cfg(unix)]
#[test]
fn a_report_to_a_closed_standard_output_is_an_error() {
    let dir = scratch("closed-stdout");
    let out = dir.join("q.obj");
    let out_arg = out.to_str().unwrap().to_string();
    let (mesh, grid) = (mushroom(), layout("mushroom-grid"));
    let args = ["remesh", &mesh, "--layout", &grid, "--iterations", "0", "-o", &out_arg, "--report", "-"];
    let result = std::process::Command::new("sh")
        .arg("-c")
        .arg(r#"exec "$0" "$@" >&-"#)
        .arg(env!("CARGO_BIN_EXE_quadlay"))
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains("standard output is closed"), "{stderr}");
    assert!(!out.exists(), "no quad mesh without its report");
}

/// Issue 22: the automatic layout of meshes too small, too thin or too odd for one, made
/// here. Each gives a layout that `check` accepts, or exit status 2 and one `error:` line
/// saying why and what to do (these are all too coarse), within seconds: never a panic, a
/// hang, or a layout the reader refuses.
#[test]
fn the_automatic_layout_of_odd_meshes_is_a_layout_or_one_error_line() {
    use common::{cube, grid, grid_with_hole, mesh_of, obj_text, torus, two_grids};
    let strip = {
        // 100:1, two triangles across.
        let positions = (0..=100).flat_map(|i| [[i as f64, 0.0, 0.0], [i as f64, 1.0, 0.0]]).collect();
        let triangles = (0..100).flat_map(|i| [[2 * i, 2 * i + 2, 2 * i + 3], [2 * i, 2 * i + 3, 2 * i + 1]]).collect();
        mesh_of(positions, triangles)
    };
    let meshes = [
        ("triangle", mesh_of(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]])),
        (
            "tetrahedron",
            mesh_of(
                vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
            ),
        ),
        ("cube of 12 triangles", cube(1).0),
        ("flat grid", grid(6)),
        ("annulus", grid_with_hole(8, 3, 5)),
        ("two components", two_grids(4)),
        ("coarse torus", torus(8, 4)),
        ("strip", strip),
    ];
    let dir = scratch("automatic_layout");
    for (name, mesh) in meshes {
        let path = dir.join(format!("{}.obj", name.replace(' ', "_")));
        std::fs::write(&path, obj_text(&mesh)).unwrap();
        let (mesh_path, out) = (path.to_string_lossy().into_owned(), path.with_extension("layout.json"));
        let out = out.to_string_lossy().into_owned();
        let (code, _, stderr) = common::within(std::time::Duration::from_secs(60), name, {
            let (m, o) = (mesh_path.clone(), out.clone());
            move || run_cli(&["layout", &m, "-o", &o])
        });
        match code {
            0 => {
                let (check, _, err) = run_cli(&["check", &mesh_path, "--layout", &out]);
                assert_eq!(check, 0, "{name}: the layout written is refused: {err}");
            }
            2 => {
                let lines: Vec<&str> = stderr.lines().collect();
                assert!(lines.len() == 1 && lines[0].starts_with("error: "), "{name}: {stderr}");
                // What to do about it, too.
                assert!(lines[0].contains("split its triangles"), "{name}: {stderr}");
                assert!(!Path::new(&out).exists(), "{name}: a refused layout leaves no file");
            }
            _ => panic!("{name}: exit {code}: {stderr}"),
        }
        println!("{name}: exit {code} {}", stderr.trim());
    }
}
