//! Hostile layouts: every error of shared/spec/layout-format.md ("Errors") raised as its own
//! typed error that names the entry at fault; reading a layout never panics or hangs
//! (truncated and mutated files, random layouts on a real mesh); `quadlay check --layout`
//! turns each into one `error:` line and exit status 2.

mod common;

use common::*;
use quadlay::layout::file::Problem;
use quadlay::layout::{build_layout, parse_layout, CurveSource, LayoutError, LayoutFileError};
use quadlay::mesh::Mesh;
use serde_json::{json, Value};
use std::sync::Arc;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------------------
// Helpers

/// The file error of a layout text that must not parse.
fn parse_err(text: &str) -> LayoutFileError {
    match parse_layout(text) {
        Ok(l) => panic!("accepted: {text}\n{l:?}"),
        Err(e) => e,
    }
}

/// The error of a layout document that must not build on `mesh`.
fn build_err(mesh: &Mesh, d: &Value) -> LayoutError {
    match build(mesh, d) {
        Ok(s) => panic!("accepted ({} faces): {d}", s.faces.len()),
        Err(e) => e,
    }
}

/// The file error inside a build error.
fn file_problem(e: LayoutError) -> LayoutFileError {
    match e {
        LayoutError::File(f) => f,
        other => panic!("expected a file error, got {other:?}"),
    }
}

fn assert_file_error(e: &LayoutFileError, entry: &str, problem: Problem) {
    assert_eq!((e.entry.as_str(), &e.problem), (entry, &problem), "{e}");
    let msg = e.to_string();
    if !entry.is_empty() {
        assert!(msg.starts_with(&format!("{entry}: ")), "message does not name {entry}: {msg}");
    }
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
}

const N: u32 = 10;

/// Vertex of grid point (i, j) of the 10×10 grid.
fn g(i: u32, j: u32) -> u32 {
    gid(N, i, j)
}

/// A valid layout on `grid(10)`: the grid's corners (nodes 0–3), a square (2,2)–(8,8)
/// (nodes 4–7, edges 0–3) and the diagonals joining them (edges 4–7). Five faces.
fn frame() -> Value {
    let nodes = [(0, 0), (N, 0), (N, N), (0, N), (2, 2), (8, 2), (8, 8), (2, 8)];
    let edges = [(4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)];
    doc(nodes.iter().map(|&(i, j)| at(g(i, j))).collect(), edges.iter().map(|&(a, b)| edge(a, b)).collect())
}

fn push_node(d: &mut Value, n: Value) {
    d["nodes"].as_array_mut().unwrap().push(n);
}

fn push_edge(d: &mut Value, e: Value) {
    d["edges"].as_array_mut().unwrap().push(e);
}

#[test]
fn the_frame_is_valid() {
    // Every hostile grid layout below is this one plus one fault.
    let s = build(&grid(N), &frame()).unwrap();
    assert_eq!((s.faces.len(), s.t_vertex_count(), s.curves.len()), (5, 0, 12));
}

// ---------------------------------------------------------------------------------------
// The file: keys, format, version, missing parts, indices, coordinates

#[test]
fn unknown_keys_name_their_object() {
    let mut d = frame();
    d["colour"] = json!("red");
    let e = parse_err(&d.to_string());
    assert_file_error(&e, "", Problem::UnknownKey("colour".into()));
    assert_eq!(e.to_string(), "unknown key 'colour'");

    let mut d = frame();
    d["nodes"][3]["weight"] = json!(2);
    assert_file_error(&parse_err(&d.to_string()), "nodes[3]", Problem::UnknownKey("weight".into()));

    let mut d = frame();
    d["edges"][5]["colour"] = json!(3);
    assert_file_error(&parse_err(&d.to_string()), "edges[5]", Problem::UnknownKey("colour".into()));

    let mut d = frame();
    d["edges"][2]["via"] = json!([{ "vertex": 5 }, { "vertex": 6, "snap": true }]);
    assert_file_error(&parse_err(&d.to_string()), "edges[2].via[1]", Problem::UnknownKey("snap".into()));

    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 5, 6, 7] }, { "corners": [0, 1, 5, 4], "name": "bottom" }]);
    assert_file_error(&parse_err(&d.to_string()), "patches[1]", Problem::UnknownKey("name".into()));

    let mut d = frame();
    d["defaults"] = json!({ "chart": "rect", "align": true });
    assert_file_error(&parse_err(&d.to_string()), "defaults", Problem::UnknownKey("align".into()));

    // Keys are case-sensitive.
    let mut d = frame();
    d["Patches"] = json!([]);
    assert_file_error(&parse_err(&d.to_string()), "", Problem::UnknownKey("Patches".into()));
}

#[test]
fn unknown_versions_and_formats() {
    for v in [json!(2), json!(0), json!(-1), json!("1"), json!(1.5), json!(null)] {
        let mut d = frame();
        d["version"] = v.clone();
        let e = parse_err(&d.to_string());
        assert_file_error(&e, "version", Problem::UnsupportedVersion(v.clone()));
        assert!(e.to_string().contains("is not supported"), "{e}");
    }
    let mut d = frame();
    d["format"] = json!("quad-layout-2");
    assert_file_error(&parse_err(&d.to_string()), "format", Problem::WrongFormat("quad-layout-2".into()));
    let mut d = frame();
    d["format"] = json!("Quad-Layout");
    assert_file_error(&parse_err(&d.to_string()), "format", Problem::WrongFormat("Quad-Layout".into()));
    let mut d = frame();
    d["format"] = json!(1);
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "format"));
}

#[test]
fn missing_parts() {
    for key in ["format", "version", "nodes"] {
        let mut d = frame();
        d.as_object_mut().unwrap().remove(key);
        let e = parse_err(&d.to_string());
        assert_file_error(&e, "", Problem::Missing(match key {
            "format" => "format",
            "version" => "version",
            _ => "nodes",
        }));
        assert_eq!(e.to_string(), format!("missing '{key}'"));
    }
    // `edges` is optional; an edge needs its nodes; a patch its corners.
    let mut d = frame();
    d.as_object_mut().unwrap().remove("edges");
    assert_eq!(parse_layout(&d.to_string()).unwrap().edges.len(), 0);
    let mut d = frame();
    d["edges"][1] = json!({ "align": true });
    assert_file_error(&parse_err(&d.to_string()), "edges[1]", Problem::Missing("nodes"));
    let mut d = frame();
    d["patches"] = json!([{ "chart": "rect" }]);
    assert_file_error(&parse_err(&d.to_string()), "patches[0]", Problem::Missing("corners"));
    // Wrong shapes name the entry too.
    let mut d = frame();
    d["nodes"] = json!({ "0": { "vertex": 1 } });
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "nodes"));
    let mut d = frame();
    d["edges"][0]["nodes"] = json!([4, 5, 6]);
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "edges[0].nodes"));
    let mut d = frame();
    d["nodes"][2] = json!({});
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "nodes[2]"));
    for top in ["[]", "3", "null", "\"quad-layout\""] {
        assert!(matches!(parse_err(top).problem, Problem::Expected(_)), "{top}");
    }
    for bad in ["", "{", "{\"format\":\"quad-layout\",}", "\u{feff}x"] {
        assert!(matches!(parse_err(bad).problem, Problem::Json(_)), "{bad:?}");
    }
}

#[test]
fn node_indices_out_of_range() {
    let mut d = frame();
    d["edges"][3] = edge(7, 8);
    let e = parse_err(&d.to_string());
    assert_file_error(&e, "edges[3]", Problem::NoSuchNode { node: 8, nodes: 8 });
    assert_eq!(e.to_string(), "edges[3]: node 8 does not exist (8 nodes)");

    let mut d = frame();
    d["edges"][0] = json!({ "nodes": [u64::MAX, 1] });
    assert_file_error(&parse_err(&d.to_string()), "edges[0]", Problem::NoSuchNode { node: u64::MAX, nodes: 8 });

    let mut d = frame();
    d["edges"][6] = json!({ "nodes": [-1, 1] });
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "edges[6]"));
    let mut d = frame();
    d["edges"][6] = json!({ "nodes": [1.5, 1] });
    assert!(matches!(parse_err(&d.to_string()), LayoutFileError { ref entry, problem: Problem::Expected(_) } if entry == "edges[6]"));

    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 5, 6, 7] }, { "corners": [0, 1, 5, 12] }]);
    let e = parse_err(&d.to_string());
    assert_file_error(&e, "patches[1]", Problem::NoSuchNode { node: 12, nodes: 8 });

    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 5, 4, 7] }]);
    assert_file_error(&parse_err(&d.to_string()), "patches[0]", Problem::RepeatedCorner(4));
    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 5, 6] }]);
    assert!(matches!(parse_err(&d.to_string()).problem, Problem::Expected(_)));
    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 5, 6, 7], "chart": "square" }]);
    assert_file_error(&parse_err(&d.to_string()), "patches[0].chart", Problem::UnknownChart("square".into()));
    let mut d = frame();
    d["defaults"] = json!({ "chart": "hex" });
    assert_file_error(&parse_err(&d.to_string()), "defaults.chart", Problem::UnknownChart("hex".into()));
}

#[test]
fn vertex_indices_beyond_the_mesh() {
    let m = grid(N);
    let nv = m.n_vertices(); // 121
    let mut d = frame();
    d["nodes"][6] = at(nv as u32);
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "nodes[6]", Problem::NoSuchVertex { vertex: nv as u64, vertices: nv });
    assert_eq!(e.to_string(), "nodes[6]: vertex 121 does not exist (the mesh has 121 vertices)");

    let mut d = frame();
    d["edges"][4]["via"] = json!([{ "vertex": g(1, 1) }, { "vertex": 5000 }]);
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "edges[4].via[1]", Problem::NoSuchVertex { vertex: 5000, vertices: nv });

    // Beyond u32: refused when placed like any other, with the mesh's real vertex count.
    let mut d = frame();
    d["nodes"][1] = json!({ "vertex": 1u64 << 32 });
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "nodes[1]", Problem::NoSuchVertex { vertex: 1u64 << 32, vertices: nv });

    // A vertex no triangle uses (the middle of a hole) cannot carry a node or a waypoint.
    let holed = grid_with_hole(6, 2, 4);
    let d = doc(vec![at(gid(6, 0, 0)), at(gid(6, 3, 3)), at(gid(6, 6, 6))], vec![]);
    let e = file_problem(build_err(&holed, &d));
    assert_file_error(&e, "nodes[1]", Problem::IsolatedVertex { vertex: gid(6, 3, 3) });
}

#[test]
fn non_finite_coordinates() {
    let mut d = frame();
    d["nodes"][5] = json!({ "point": [0.8, null, 0.0] });
    let e = parse_err(&d.to_string());
    assert_file_error(&e, "nodes[5].point", Problem::NotFinite);
    assert_eq!(e.to_string(), "nodes[5].point: coordinates must be finite numbers");

    let mut d = frame();
    d["edges"][1]["via"] = json!([{ "point": [null, null, null] }]);
    assert_file_error(&parse_err(&d.to_string()), "edges[1].via[0].point", Problem::NotFinite);

    // Wrong shapes of points.
    for p in [json!([0.1, 0.2]), json!([0.1, 0.2, 0.3, 0.4]), json!([0.1, "0.2", 0.3]), json!("0.1 0.2 0.3")] {
        let mut d = frame();
        d["nodes"][0] = json!({ "point": p });
        let e = parse_err(&d.to_string());
        assert!(matches!(e.problem, Problem::Expected(_)) && e.entry == "nodes[0].point", "{p}: {e}");
    }
    // Overflowing literals are not numbers at all (JSON has no infinity).
    let text = frame().to_string().replacen("{\"vertex\":0}", "{\"point\":[1e999,0,0]}", 1);
    assert!(text.contains("1e999"));
    assert!(matches!(parse_err(&text).problem, Problem::Json(_)));
}

#[test]
fn two_nodes_on_one_vertex() {
    let m = grid(N);
    let mut d = frame();
    d["nodes"][7] = at(g(8, 2));
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "nodes[7]", Problem::SameVertex { vertex: g(8, 2), other: 5 });
    assert_eq!(e.to_string(), format!("nodes[7]: on mesh vertex {}, like nodes[5]", g(8, 2)));

    // A point snaps to the vertex another node names.
    let mut d = frame();
    d["nodes"][6] = json!({ "point": [0.21, 0.19, 0.003] });
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "nodes[6]", Problem::SameVertex { vertex: g(2, 2), other: 4 });

    // Two points that snap to one vertex.
    let mut d = frame();
    push_node(&mut d, json!({ "point": [0.5, 0.52, 0.0] }));
    push_node(&mut d, json!({ "point": [0.49, 0.5, -0.01] }));
    let e = file_problem(build_err(&m, &d));
    assert_file_error(&e, "nodes[9]", Problem::SameVertex { vertex: g(5, 5), other: 8 });
}

#[test]
fn an_edge_from_a_node_to_itself() {
    let mut d = frame();
    push_edge(&mut d, edge(6, 6));
    let e = parse_err(&d.to_string());
    assert_file_error(&e, "edges[8]", Problem::SelfLoop);
    // Even with waypoints that would make it a loop on the surface.
    let mut d = frame();
    d["edges"][2] = json!({ "nodes": [3, 3], "via": [{ "vertex": g(1, 5) }, { "vertex": g(5, 9) }] });
    assert_file_error(&parse_err(&d.to_string()), "edges[2]", Problem::SelfLoop);
}

// ---------------------------------------------------------------------------------------
// Curves

/// The error must be `CurvesMeet` between `a` and `b` at `want`, and say so.
fn assert_meet(e: LayoutError, a: CurveSource, b: CurveSource, want: Option<[f64; 3]>) {
    let msg = e.to_string();
    match e {
        LayoutError::CurvesMeet { a: x, b: y, at } => {
            assert_eq!((x, y), (a, b), "{msg}");
            if let Some(w) = want {
                assert!(close(at, w, 1e-9), "met at {at:?}, expected {w:?}");
            }
            assert!(msg.starts_with(&format!("{a} and {b}: the curves meet")), "{msg}");
        }
        other => panic!("expected CurvesMeet, got {other:?}"),
    }
}

#[test]
fn crossing_diagonals_of_a_square() {
    // Grid corners as nodes (the boundary carries them), the two diagonals as edges. With n
    // even both diagonals run along mesh edges through the centre vertex; with n odd the
    // second crosses the mesh edge the first runs along.
    for n in [4, 5, 8, 9] {
        let m = grid(n);
        let nodes = vec![at(gid(n, 0, 0)), at(gid(n, n, 0)), at(gid(n, n, n)), at(gid(n, 0, n))];
        let d = doc(nodes, vec![edge(0, 2), edge(1, 3)]);
        assert_meet(build_err(&m, &d), CurveSource::Edge(0), CurveSource::Edge(1), Some([0.5, 0.5, 0.0]));
    }
    // Two chords through the insides of triangles: (0, 2/6)–(1, 5/6) and (0, 5/6)–(1, 1/6).
    let n = 6;
    let m = grid_with(n, Diagonals::Down);
    let nodes = vec![at(gid(n, 0, 2)), at(gid(n, n, 5)), at(gid(n, 0, 5)), at(gid(n, n, 1))];
    let d = doc(nodes, vec![edge(0, 1), edge(2, 3)]);
    // y = 2/6 + x/2 and y = 5/6 − (2/3) x meet at x = 3/7.
    let x = 3.0 / 7.0;
    assert_meet(build_err(&m, &d), CurveSource::Edge(0), CurveSource::Edge(1), Some([x, 2.0 / 6.0 + x / 2.0, 0.0]));
}

#[test]
fn curves_that_touch_or_share_a_vertex() {
    let m = grid(N);
    // A V whose tip (a waypoint) touches the middle line of the frame's square.
    let mut d = frame();
    push_node(&mut d, at(g(3, 5))); // 8
    push_node(&mut d, at(g(7, 5))); // 9
    push_node(&mut d, at(g(4, 7))); // 10
    push_node(&mut d, at(g(6, 7))); // 11
    push_edge(&mut d, edge(8, 9)); // 8: through (5, 5)
    push_edge(&mut d, json!({ "nodes": [10, 11], "via": [{ "vertex": g(5, 5) }] })); // 9
    assert_meet(build_err(&m, &d), CurveSource::Edge(8), CurveSource::Edge(9), Some([0.5, 0.5, 0.0]));

    // The same node pair twice without waypoints: one curve twice (overlap from a shared node).
    let mut d = frame();
    push_edge(&mut d, edge(5, 4));
    assert_meet(build_err(&m, &d), CurveSource::Edge(0), CurveSource::Edge(8), None);

    // An edge along the mesh boundary lies on the boundary piece between its nodes.
    let mut d = frame();
    push_edge(&mut d, edge(0, 1));
    assert_meet(build_err(&m, &d), CurveSource::Edge(8), CurveSource::Boundary { boundary_loop: 0 }, None);

    // Two edges sharing one node that leave it the same way: (2,2)→(5,5) and (2,2)→(8,8).
    let mut d = frame();
    push_node(&mut d, at(g(5, 5))); // 8
    push_node(&mut d, at(g(6, 4))); // 9, off the diagonal so the edges do not end on each other
    push_edge(&mut d, edge(4, 8)); // 8
    push_edge(&mut d, json!({ "nodes": [4, 9], "via": [{ "vertex": g(4, 4) }] })); // 9
    assert_meet(build_err(&m, &d), CurveSource::Edge(8), CurveSource::Edge(9), None);

    // The same pair twice, once with a waypoint: allowed (they differ), a two-node face.
    let (c, ids) = cube(4);
    let d = doc(
        vec![at(ids[&[0, 0, 4]]), at(ids[&[4, 4, 4]])],
        vec![
            json!({ "nodes": [0, 1], "via": [{ "vertex": ids[&[4, 0, 4]] }] }),
            json!({ "nodes": [0, 1], "via": [{ "vertex": ids[&[0, 4, 4]] }] }),
        ],
    );
    match build_err(&c, &d) {
        LayoutError::FaceTooFewNodes { nodes } => assert_eq!(sorted(nodes), vec![0, 1]),
        other => panic!("expected a two-node face, got {other:?}"),
    }
}

#[test]
fn curves_through_nodes_and_waypoints_on_nodes() {
    let m = grid(N);
    let mut d = frame();
    push_node(&mut d, at(g(3, 5))); // 8
    push_node(&mut d, at(g(5, 5))); // 9
    push_node(&mut d, at(g(7, 5))); // 10
    let mut through = d.clone();
    push_edge(&mut through, edge(8, 10)); // 8: its straight line runs through node 9
    match build_err(&m, &through) {
        LayoutError::NoPath { edge, reason } => {
            assert_eq!(edge, 8);
            assert!(reason.contains(&format!("vertex {}", g(5, 5))), "{reason}");
        }
        other => panic!("expected NoPath, got {other:?}"),
    }

    let mut via = d.clone();
    push_edge(&mut via, json!({ "nodes": [8, 10], "via": [{ "vertex": g(4, 7) }, { "vertex": g(5, 5) }] }));
    let e = build_err(&m, &via);
    assert_eq!(e.to_string(), "edges[8]: no path on the surface (waypoint 1 lies on node 9; curves may meet only at their own ends)");
    assert!(matches!(e, LayoutError::NoPath { edge: 8, .. }));

    // A waypoint given as a point that snaps onto a node, and one on a corner of the square.
    let mut via = d.clone();
    push_edge(&mut via, json!({ "nodes": [8, 10], "via": [{ "point": [0.51, 0.49, 0.0] }] }));
    assert!(matches!(build_err(&m, &via), LayoutError::NoPath { edge: 8, ref reason } if reason.contains("lies on node 9")));
    let mut via = frame();
    via["edges"][5]["via"] = json!([{ "vertex": g(8, 8) }]);
    assert!(matches!(build_err(&m, &via), LayoutError::NoPath { edge: 5, ref reason } if reason.contains("lies on node 6")));

    // No path at all: the two ends on different components.
    let two = two_grids(4);
    let off = 25;
    let nodes = [gid(4, 0, 0), gid(4, 4, 0), gid(4, 4, 4), off + gid(4, 0, 0), off + gid(4, 4, 0), off + gid(4, 0, 4)];
    let d = doc(nodes.iter().map(|&v| at(v)).collect(), vec![edge(0, 1), edge(2, 3)]);
    let e = build_err(&two, &d);
    assert!(matches!(e, LayoutError::NoPath { edge: 1, .. }), "{e:?}");
    assert!(e.to_string().starts_with("edges[1]: no path on the surface"), "{e}");
}

// ---------------------------------------------------------------------------------------
// Faces

fn sorted(mut v: Vec<u32>) -> Vec<u32> {
    v.sort_unstable();
    v
}

/// The error must be `FaceNotDisk` for a face with one of the node sets `any_of`.
fn assert_not_disk(e: LayoutError, any_of: &[Vec<u32>], reasons: &[&str]) {
    let msg = e.to_string();
    match e {
        LayoutError::FaceNotDisk { nodes, reason } => {
            assert!(any_of.contains(&sorted(nodes.clone())), "{msg}");
            assert!(reasons.iter().any(|r| reason.contains(r)), "{msg}");
            let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
            assert!(msg.starts_with(&format!("the face with nodes {} is not a disk", list.join(", "))), "{msg}");
        }
        other => panic!("expected FaceNotDisk, got {other:?}"),
    }
}

/// An annulus is found either by its Euler characteristic or by being inside two faces,
/// depending on which of its two boundary cycles is looked at first.
const ANNULUS: &[&str] = &["Euler characteristic 0", "also inside another face"];

#[test]
fn an_annulus_is_not_a_disk() {
    // The frame without its diagonals: the square's outside reaches the grid's boundary.
    let m = grid(N);
    let mut d = frame();
    d["edges"].as_array_mut().unwrap().truncate(4);
    assert_not_disk(build_err(&m, &d), &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]], ANNULUS);

    // On a closed cube two loops around it leave a band between them.
    let (c, ids) = cube(4);
    let ring = |k: u32| [[0, 0, k], [4, 0, k], [4, 4, k], [0, 4, k]].map(|p| ids[&p]);
    let nodes: Vec<Value> = ring(1).into_iter().chain(ring(3)).map(at).collect();
    let edges = vec![edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0), edge(4, 5), edge(5, 6), edge(6, 7), edge(7, 4)];
    assert_not_disk(build_err(&c, &doc(nodes.clone(), edges.clone())), &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]], ANNULUS);
    // One loop alone cuts the cube into two disks.
    let s = build(&c, &doc(nodes[..4].to_vec(), edges[..4].to_vec())).unwrap();
    assert_eq!(s.faces.len(), 2);
}

/// Nodes on the one-ring of `v`, joined in ring order: a small disk around `v` and the rest
/// of the surface.
fn one_ring_layout(m: &Mesh, v: u32) -> (Value, Vec<u32>) {
    let ring: Vec<u32> = m.neighbors(v).collect();
    let k = ring.len() as u32;
    let edges = (0..k).map(|i| edge(i, (i + 1) % k)).collect();
    (doc(ring.iter().map(|&w| at(w)).collect(), edges), ring)
}

#[test]
fn a_face_with_a_handle_is_not_a_disk() {
    // Torus: the outside of a small disk is a torus with a hole, χ = −1.
    let t = torus(24, 12);
    let v = 5 * 12 + 3;
    let (d, ring) = one_ring_layout(&t, v);
    assert!(ring.len() >= 4);
    let all: Vec<u32> = (0..ring.len() as u32).collect();
    assert_not_disk(build_err(&t, &d), &[all], &["Euler characteristic -1"]);

    // eight.obj, genus 2: χ = 2 − 4 − 1 = −3.
    let eight = load_mesh("eight.obj");
    let v = (0..eight.n_vertices() as u32).find(|&v| (5..=7).contains(&eight.valence(v))).unwrap();
    let (d, ring) = one_ring_layout(&eight, v);
    let all: Vec<u32> = (0..ring.len() as u32).collect();
    assert_not_disk(build_err(&eight, &d), &[all], &["Euler characteristic -3"]);

    // The same kind of layout on a sphere (bunny, genus 0) is two disks.
    let bunny = load_mesh("bunny_1k8.obj");
    let v = (0..bunny.n_vertices() as u32).find(|&v| (5..=7).contains(&bunny.valence(v))).unwrap();
    let (d, ring) = one_ring_layout(&bunny, v);
    let s = build(&bunny, &d).unwrap();
    assert_eq!(s.faces.len(), 2);
    assert_eq!(s.faces.iter().map(|f| f.nodes.len()).collect::<Vec<_>>(), vec![ring.len(); 2]);

    // A loop around the tube of the torus leaves a cylinder: both sides are one region.
    let nodes: Vec<Value> = [0, 3, 6, 9].map(at).into_iter().collect();
    let d = doc(nodes, vec![edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0)]);
    assert_not_disk(build_err(&t, &d), &[vec![0, 1, 2, 3]], ANNULUS);
}

#[test]
fn a_face_whose_boundary_passes_a_node_twice() {
    // Two squares on the cube's top touching at a corner: the rest of the surface runs
    // around both and passes the shared node twice.
    let (c, ids) = cube(6);
    let top = |i: u32, j: u32| at(ids[&[i, j, 6]]);
    let nodes = vec![top(1, 1), top(3, 1), top(3, 3), top(1, 3), top(5, 3), top(5, 5), top(3, 5)];
    let edges = [(0, 1), (1, 2), (2, 3), (3, 0), (2, 4), (4, 5), (5, 6), (6, 2)];
    let e = build_err(&c, &doc(nodes, edges.iter().map(|&(a, b)| edge(a, b)).collect()));
    match &e {
        LayoutError::FaceNotDisk { nodes, reason } => {
            assert_eq!(sorted(nodes.clone()), vec![0, 1, 2, 2, 3, 4, 5, 6]);
            assert_eq!(reason, "its boundary passes node 2 twice");
        }
        other => panic!("expected FaceNotDisk, got {other:?}"),
    }
    assert!(e.to_string().contains("is not a disk: its boundary passes node 2 twice"), "{e}");
}

#[test]
fn a_disk_with_two_or_three_boundary_nodes() {
    // Only the boundary pieces bound the one face: it has as many nodes as the loop.
    let m = load_mesh("mushroom.obj");
    let b: Vec<u32> = (0..m.n_vertices() as u32).filter(|&v| m.is_boundary_vertex(v)).collect();
    for k in [2usize, 3] {
        let nodes = (0..k).map(|i| at(b[i * b.len() / k])).collect();
        match build_err(&m, &doc(nodes, vec![])) {
            LayoutError::FaceTooFewNodes { nodes } => assert_eq!(sorted(nodes), (0..k as u32).collect::<Vec<_>>()),
            other => panic!("{k} nodes: expected FaceTooFewNodes, got {other:?}"),
        }
    }
    // Four make a face.
    let nodes = (0..4).map(|i| at(b[i * b.len() / 4])).collect();
    let s = build(&m, &doc(nodes, vec![])).unwrap();
    assert_eq!((s.faces.len(), s.curves.len()), (1, 4));
}

#[test]
fn faces_with_fewer_than_four_nodes() {
    // The grid's diagonal splits it into two triangles.
    let n = 4;
    let m = grid(n);
    let nodes = vec![at(gid(n, 0, 0)), at(gid(n, n, 0)), at(gid(n, n, n)), at(gid(n, 0, n))];
    let e = build_err(&m, &doc(nodes, vec![edge(0, 2)]));
    let msg = e.to_string();
    match e {
        LayoutError::FaceTooFewNodes { nodes } => {
            assert!(sorted(nodes.clone()) == vec![0, 1, 2] || sorted(nodes.clone()) == vec![0, 2, 3], "{nodes:?}");
            assert!(msg.starts_with("the face with nodes ") && msg.contains("has 3 node(s); a face needs at least 4"), "{msg}");
        }
        other => panic!("expected FaceTooFewNodes, got {other:?}"),
    }
    // A triangle of three edges on a closed cube.
    let (c, ids) = cube(4);
    let nodes = vec![at(ids[&[0, 0, 2]]), at(ids[&[4, 2, 2]]), at(ids[&[2, 4, 4]])];
    let e = build_err(&c, &doc(nodes, vec![edge(0, 1), edge(1, 2), edge(2, 0)]));
    assert!(matches!(e, LayoutError::FaceTooFewNodes { ref nodes } if sorted(nodes.clone()) == vec![0, 1, 2]), "{e:?}");
}

#[test]
fn a_face_with_no_mesh_vertex_inside() {
    // One grid square as a face: the mesh is too coarse for it.
    let m = grid(N);
    let nodes = [(0, 0), (1, 0), (N, 0), (N, N), (0, N), (0, 1), (1, 1)];
    let d = doc(nodes.iter().map(|&(i, j)| at(g(i, j))).collect(), vec![edge(1, 6), edge(6, 5)]);
    let e = build_err(&m, &d);
    assert!(matches!(e, LayoutError::TooCoarse { ref nodes } if sorted(nodes.clone()) == vec![0, 1, 5, 6]), "{e:?}");
    assert!(e.to_string().contains("too coarse"));
}

// ---------------------------------------------------------------------------------------
// Patches

fn assert_patch_error(e: LayoutError, patch: usize, reason_has: &str) {
    let msg = e.to_string();
    match e {
        LayoutError::PatchNotAFace { patch: p, reason } => {
            assert_eq!(p, patch, "{msg}");
            assert!(reason.contains(reason_has), "{msg}");
            assert!(msg.starts_with(&format!("patches[{patch}]: ")), "{msg}");
        }
        other => panic!("expected PatchNotAFace, got {other:?}"),
    }
}

#[test]
fn patches_that_name_no_face() {
    let m = grid(N);
    let with = |patches: Value| {
        let mut d = frame();
        d["patches"] = patches;
        d
    };
    // Counter-clockwise from any corner is fine.
    for corners in [[4, 5, 6, 7], [6, 7, 4, 5], [0, 1, 5, 4], [5, 4, 0, 1]] {
        build(&m, &with(json!([{ "corners": corners }]))).unwrap_or_else(|e| panic!("{corners:?}: {e}"));
    }
    // Nodes of the layout, but not of one face.
    assert_patch_error(build_err(&m, &with(json!([{ "corners": [4, 5, 6, 7] }, { "corners": [0, 1, 6, 7] }]))), 1, "no face");
    assert_patch_error(build_err(&m, &with(json!([{ "corners": [0, 1, 2, 3] }]))), 0, "no face");
    // Clockwise.
    assert_patch_error(build_err(&m, &with(json!([{ "corners": [4, 7, 6, 5] }]))), 0, "not listed counter-clockwise");
    assert_patch_error(build_err(&m, &with(json!([{ "corners": [0, 4, 5, 1] }]))), 0, "not listed counter-clockwise");
    // Twice the same face.
    assert_patch_error(
        build_err(&m, &with(json!([{ "corners": [4, 5, 6, 7] }, { "corners": [1, 5, 4, 0] }, { "corners": [6, 7, 4, 5] }]))),
        2,
        "another patches entry names the same face",
    );
}

// ---------------------------------------------------------------------------------------
// Parts of the surface without nodes

#[test]
fn a_component_without_nodes() {
    let m = two_grids(4);
    let nodes = vec![at(gid(4, 0, 0)), at(gid(4, 4, 0)), at(gid(4, 4, 4)), at(gid(4, 0, 4))];
    let e = build_err(&m, &doc(nodes, vec![]));
    assert_eq!(e, LayoutError::ComponentWithoutNodes { component: 1, first_vertex: 25 });
    assert!(e.to_string().starts_with("mesh component 1 (with vertex 25) has no nodes"), "{e}");
    // Nodes on the second only.
    let nodes = vec![at(25 + gid(4, 0, 0)), at(25 + gid(4, 4, 4))];
    assert_eq!(build_err(&m, &doc(nodes, vec![])), LayoutError::ComponentWithoutNodes { component: 0, first_vertex: 0 });
    // No nodes at all.
    assert!(matches!(build_err(&m, &doc(vec![], vec![])), LayoutError::ComponentWithoutNodes { component: 0, .. }));
}

#[test]
fn boundary_loops_with_fewer_than_two_nodes() {
    let m = grid(N);
    let boundary = |v: u32| m.is_boundary_vertex(v);
    // The frame's square alone, inside: no node on the boundary.
    let square = [(2, 2), (8, 2), (8, 8), (2, 8)];
    let loop4 = vec![edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0)];
    let d = doc(square.iter().map(|&(i, j)| at(g(i, j))).collect(), loop4);
    let e = build_err(&m, &d);
    match e {
        LayoutError::BoundaryLoopNodes { boundary_loop: 0, nodes: 0, first_vertex } => assert!(boundary(first_vertex)),
        ref other => panic!("expected BoundaryLoopNodes, got {other:?}"),
    }
    assert!(e.to_string().starts_with("boundary loop 0 (through vertex "), "{e}");
    assert!(e.to_string().contains("carries 0 node(s); it needs at least 2"), "{e}");

    // One corner node, joined to the square.
    let mut nodes = vec![at(g(0, 0))];
    nodes.extend(square.iter().map(|&(i, j)| at(g(i, j))));
    let d = doc(nodes, vec![edge(1, 2), edge(2, 3), edge(3, 4), edge(4, 1), edge(0, 1)]);
    match build_err(&m, &d) {
        LayoutError::BoundaryLoopNodes { boundary_loop: 0, nodes: 1, first_vertex } => assert!(boundary(first_vertex)),
        other => panic!("expected BoundaryLoopNodes, got {other:?}"),
    }

    // An annulus: nodes on the outer loop only.
    let n = 6;
    let holed = grid_with_hole(n, 2, 4);
    let nodes = vec![at(gid(n, 0, 0)), at(gid(n, n, 0)), at(gid(n, n, n)), at(gid(n, 0, n))];
    match build_err(&holed, &doc(nodes, vec![])) {
        LayoutError::BoundaryLoopNodes { nodes: 0, first_vertex, .. } => {
            let p = holed.position(first_vertex);
            assert!((0..2).all(|k| (2.0 / 6.0 - 1e-12..=4.0 / 6.0 + 1e-12).contains(&p[k])), "{p:?} is not on the hole");
        }
        other => panic!("expected BoundaryLoopNodes, got {other:?}"),
    }
}

#[test]
fn dangling_edges_and_lonely_nodes() {
    let m = grid(N);
    // An edge into the square that ends at a node of its own.
    let mut d = frame();
    push_node(&mut d, at(g(5, 5)));
    let lonely = d.clone();
    push_edge(&mut d, edge(4, 8));
    let e = build_err(&m, &d);
    assert_eq!(e, LayoutError::SameFaceBothSides { curve: CurveSource::Edge(8) });
    assert!(e.to_string().starts_with("edges[8]: the same face lies on both sides"), "{e}");

    // A slit from the boundary: node (5, 0) on the boundary, dangling edge up to (5, 1).
    let mut d = frame();
    push_node(&mut d, at(g(5, 0))); // 8
    push_node(&mut d, at(g(5, 1))); // 9
    push_edge(&mut d, edge(8, 9));
    assert_eq!(build_err(&m, &d), LayoutError::SameFaceBothSides { curve: CurveSource::Edge(8) });

    // A node no edge reaches.
    let e = build_err(&m, &lonely);
    assert_eq!(e, LayoutError::NodeOnNoEdge { node: 8 });
    assert_eq!(e.to_string(), "nodes[8]: no edge or boundary reaches this node");
    // On a closed mesh, nodes and no edges at all.
    let (c, ids) = cube(2);
    let d = doc(vec![at(ids[&[0, 0, 0]]), at(ids[&[2, 2, 2]])], vec![]);
    assert_eq!(build_err(&c, &d), LayoutError::NodeOnNoEdge { node: 0 });
}

// ---------------------------------------------------------------------------------------
// Never a panic, never a hang

/// A layout with every kind of entry, valid on `grid(10)`.
fn rich() -> String {
    let mut d = frame();
    d["edges"][4]["via"] = json!([{ "vertex": g(1, 1) }]);
    d["edges"][5]["align"] = json!(true);
    d["edges"][6]["via"] = json!([{ "point": [0.9, 0.9, 0.0] }]);
    d["nodes"][7] = json!({ "point": [0.2, 0.8, 0.0] });
    d["patches"] = json!([{ "corners": [4, 5, 6, 7], "chart": "rect" }, { "corners": [0, 1, 5, 4] }]);
    d["defaults"] = json!({ "chart": "unit" });
    serde_json::to_string_pretty(&d).unwrap() + "\n"
}

#[test]
fn truncated_files_are_errors() {
    let m = grid(N);
    let full = rich();
    build(&m, &serde_json::from_str(&full).unwrap()).unwrap();
    let sample = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/www/layouts/mushroom-t.layout.json")).unwrap();
    let start = Instant::now();
    for text in [full.as_str(), sample.as_str()] {
        let end = text.trim_end().len();
        for cut in (0..text.len()).filter(|&k| text.is_char_boundary(k)) {
            let r = parse_layout(&text[..cut]);
            if cut < end {
                assert!(r.is_err(), "a prefix of {cut} bytes parsed");
            } else {
                assert!(r.is_ok(), "the file with {cut} bytes did not parse");
            }
        }
    }
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());
}

#[test]
fn mutated_files_never_panic() {
    let mesh = Arc::new(grid(N));
    let base = rich().into_bytes();
    let alphabet = b"0123456789-+.eE\"{}[],: nul\\tx\x00\xff";
    let outcome = within(Duration::from_secs(120), "mutated layouts", move || {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let (mut parsed, mut built) = (0, 0);
        for round in 0..400 {
            let mut bytes = base.clone();
            for _ in 0..1 + rng.below(3) {
                let k = rng.below(bytes.len() as u64) as usize;
                match rng.below(4) {
                    0 => bytes[k] = alphabet[rng.below(alphabet.len() as u64) as usize],
                    1 => bytes[k] ^= 1 << rng.below(8),
                    2 => {
                        bytes.remove(k);
                    }
                    _ => bytes.insert(k, alphabet[rng.below(alphabet.len() as u64) as usize]),
                }
            }
            let text = String::from_utf8_lossy(&bytes);
            let t0 = Instant::now();
            if let Ok(layout) = parse_layout(&text) {
                parsed += 1;
                if build_layout(&mesh, &layout).is_ok() {
                    built += 1;
                }
            }
            assert!(t0.elapsed() < Duration::from_secs(5), "round {round} took {:?}:\n{text}", t0.elapsed());
        }
        (parsed, built)
    });
    // Most single-byte changes break the JSON or a rule; some (digits) keep a valid layout.
    assert!(outcome.0 > 10 && outcome.0 < 400, "{outcome:?}");
    assert!(outcome.1 > 0, "{outcome:?}");
}

#[test]
fn deeply_nested_or_huge_files_are_errors() {
    let deep = "[".repeat(100_000);
    assert!(matches!(parse_err(&deep).problem, Problem::Json(_)));
    let deep = format!("{{\"format\":\"quad-layout\",\"version\":1,\"nodes\":[{}]}}", "{\"point\":".repeat(50_000));
    assert!(parse_layout(&deep).is_err());
    // Many nodes on a small mesh: the 122nd on the 121-vertex grid must repeat a vertex.
    let m = grid(N);
    let nodes: Vec<Value> = (0..200).map(|k| json!({ "point": [(k % 11) as f64 / 10.0, (k / 11 % 11) as f64 / 10.0, 0.0] })).collect();
    let e = file_problem(build_err(&m, &doc(nodes, vec![])));
    assert!(matches!(e.problem, Problem::SameVertex { .. }) && e.entry == "nodes[121]", "{e}");
}

#[test]
fn random_layouts_on_the_bunny_never_panic() {
    let mesh = Arc::new(load_mesh("bunny_1k8.obj"));
    let nv = mesh.n_vertices() as u64;
    let mut rng = XorShift(2008);
    let mut outcomes = std::collections::BTreeMap::new();
    for round in 0..40 {
        let k = 2 + rng.below(9);
        let nodes: Vec<Value> = (0..k)
            .map(|_| match rng.below(4) {
                0 => {
                    let p = mesh.position(rng.below(nv) as u32);
                    json!({ "point": [p[0] + 1e-3, p[1] - 1e-3, p[2]] })
                }
                1 if round % 4 == 0 => at(0), // sometimes twice: two nodes on one vertex
                _ => at(rng.below(nv) as u32),
            })
            .collect();
        let edges: Vec<Value> = (0..rng.below(2 * k + 1))
            .map(|_| {
                let (a, b) = (rng.below(k), rng.below(k));
                let b = if a == b { (b + 1) % k } else { b };
                if rng.below(5) == 0 {
                    json!({ "nodes": [a, b], "via": [{ "vertex": rng.below(nv) }] })
                } else {
                    json!({ "nodes": [a, b] })
                }
            })
            .collect();
        let d = doc(nodes, edges);
        let m = mesh.clone();
        let text = d.to_string();
        let r = within(Duration::from_secs(30), &format!("round {round}: {text}"), move || {
            let layout = parse_layout(&d.to_string()).map_err(|e| format!("File {e}"));
            build(&m, &d).map(|s| {
                check_invariants("random", &m, &layout.unwrap(), &s, false);
                s.faces.len()
            }).map_err(|e| {
                // Every error names what is at fault.
                let msg = e.to_string();
                assert!(!msg.is_empty());
                format!("{e:?}").split(['{', '(', ' ']).next().unwrap_or("").to_string()
            })
        });
        *outcomes.entry(r.map(|_| "Ok".to_string()).unwrap_or_else(|e| e)).or_insert(0) += 1;
    }
    println!("{outcomes:?}");
    assert_eq!(outcomes.values().sum::<i32>(), 40);
    // Random layouts hit several different rules.
    assert!(outcomes.len() >= 3, "{outcomes:?}");
}

/// Layouts from growing a random planar-ish graph on the bunny: more of them get to the
/// face stage. Ok or Err, within time.
#[test]
fn random_layouts_with_fewer_crossings() {
    let mesh = Arc::new(load_mesh("bunny_1k8.obj"));
    let nv = mesh.n_vertices() as u64;
    let mut rng = XorShift(42);
    let mut ok = 0;
    for round in 0..20 {
        // Nodes along a random walk over mesh vertices, each edge a short hop.
        let k = 4 + rng.below(6) as usize;
        let mut vs = vec![rng.below(nv) as u32];
        while vs.len() < k {
            let mut v = *vs.last().unwrap();
            for _ in 0..6 {
                let ring: Vec<u32> = mesh.neighbors(v).collect();
                v = ring[rng.below(ring.len() as u64) as usize];
            }
            if !vs.contains(&v) {
                vs.push(v);
            } else {
                vs.push(rng.below(nv) as u32);
                vs.dedup();
            }
        }
        let mut edges: Vec<Value> = (0..k as u32).map(|i| edge(i, (i + 1) % k as u32)).collect();
        if rng.below(2) == 0 {
            edges.push(edge(0, (k / 2) as u32));
        }
        let d = doc(vs.iter().map(|&v| at(v)).collect(), edges);
        let m = mesh.clone();
        let text = d.to_string();
        let built = within(Duration::from_secs(30), &format!("round {round}: {text}"), move || match build(&m, &d) {
            Ok(s) => {
                check_invariants("random walk", &m, &parse_layout(&d.to_string()).unwrap(), &s, false);
                true
            }
            Err(_) => false,
        });
        ok += built as usize;
    }
    println!("{ok} of 20 built");
    assert!(ok > 0, "no random loop built: the invariants were never checked");
}

// ---------------------------------------------------------------------------------------
// Command line

fn tmp(name: &str, text: &str) -> String {
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// Exit 2 and exactly one `error:` line naming the layout file and `names`.
fn assert_cli_error(mesh: &str, layout: &str, names: &str) {
    let (code, out, err) = run_cli(&["check", mesh, "--layout", layout]);
    assert_eq!(code, 2, "stdout: {out}\nstderr: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with(&format!("error: {layout}: ")), "{err}");
    assert!(lines[0].contains(names), "{err} does not name {names}");
}

#[test]
fn check_reports_bad_layouts() {
    let mushroom = shared_mesh("mushroom.obj").to_string_lossy().into_owned();
    let good = concat!(env!("CARGO_MANIFEST_DIR"), "/www/layouts/mushroom-4.layout.json");
    let (code, out, err) = run_cli(&["check", &mushroom, "--layout", good]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("faces:          1\n") && out.contains("t-vertices:     0\n"), "{out}");

    let mut d: Value = serde_json::from_str(&std::fs::read_to_string(good).unwrap()).unwrap();
    d["edges"] = json!([{ "nodes": [0, 7] }]);
    assert_cli_error(&mushroom, &tmp("bad-edge.layout.json", &d.to_string()), "edges[0]: node 7 does not exist (4 nodes)");
    let mut d2 = d.clone();
    d2["edges"] = json!([]);
    d2["nodes"][1] = at(99_999);
    assert_cli_error(&mushroom, &tmp("bad-vertex.layout.json", &d2.to_string()), "nodes[1]: vertex 99999 does not exist (the mesh has 2337 vertices)");
    d2["nodes"][1] = json!({ "point": [0.0, null, 0.0] });
    assert_cli_error(&mushroom, &tmp("bad-point.layout.json", &d2.to_string()), "nodes[1].point: coordinates must be finite");
    assert_cli_error(&mushroom, &tmp("bad-json.layout.json", "{\"format\": \"quad-layout\""), "not valid JSON");
    let missing = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such.layout.json");
    assert_cli_error(&mushroom, &missing.to_string_lossy(), "cannot read");

    // Errors found on the surface, on a grid written as OBJ.
    let obj = tmp("grid10.obj", &obj_text(&grid(N)));
    let (code, out, err) = run_cli(&["check", &obj, "--layout", &tmp("frame.layout.json", &frame().to_string())]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("faces:          5\n") && out.contains("t-vertices:     0\n"), "{out}");
    let mut d = frame();
    push_edge(&mut d, edge(4, 6));
    push_edge(&mut d, edge(5, 7));
    assert_cli_error(&obj, &tmp("crossing.layout.json", &d.to_string()), "edges[8] and edges[9]: the curves meet");
    let mut d = frame();
    push_node(&mut d, at(g(5, 5)));
    push_edge(&mut d, edge(4, 8));
    assert_cli_error(&obj, &tmp("dangling.layout.json", &d.to_string()), "edges[8]: the same face lies on both sides");
    let mut d = frame();
    d["patches"] = json!([{ "corners": [4, 7, 6, 5] }]);
    assert_cli_error(&obj, &tmp("clockwise.layout.json", &d.to_string()), "patches[0]: the corners are nodes of a face, but not listed counter-clockwise");
}
