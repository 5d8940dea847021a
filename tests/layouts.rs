//! Layouts that build: known answers on planar grids (straight curves, right angles, faces,
//! corners, T-vertices, the face of every vertex), every sample layout in www/layouts with
//! its face and T-vertex counts, the invariants every built layout satisfies, a coarse mesh
//! whose triangles are cut by two curves, and chart types from `patches` and `defaults`.

mod common;

use common::*;
use quadlay::layout::curve::position;
use quadlay::layout::{parse_layout, ChartType, SurfaceLayout};
use quadlay::mesh::{Mesh, NONE};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

fn dist_to_segment(a: [f64; 3], b: [f64; 3], x: [f64; 3]) -> f64 {
    let ab: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let ax: [f64; 3] = std::array::from_fn(|k| x[k] - a[k]);
    let l2: f64 = ab.iter().map(|c| c * c).sum();
    let t = (ab.iter().zip(&ax).map(|(p, q)| p * q).sum::<f64>() / l2).clamp(0.0, 1.0);
    (0..3).map(|k| (ax[k] - t * ab[k]).powi(2)).sum::<f64>().sqrt()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// Every curve of `s` lies on the straight segment between its end nodes and is as long.
fn assert_straight(mesh: &Mesh, s: &SurfaceLayout) {
    for (i, c) in s.curves.iter().enumerate() {
        let a = mesh.position(s.node_vertex[c.nodes[0] as usize]);
        let b = mesh.position(s.node_vertex[c.nodes[1] as usize]);
        for p in &c.curve.points {
            let x = position(mesh, p);
            assert!(dist_to_segment(a, b, x) < 1e-9, "curve {i} ({}) leaves its segment at {x:?}: {p:?}", c.source);
        }
        assert!((c.curve.length - dist(a, b)).abs() < 1e-9, "curve {i}: length {} vs {}", c.curve.length, dist(a, b));
    }
}

/// Does `cycle` equal `want` up to rotation?
fn same_cycle(cycle: &[u32], want: &[u32]) -> bool {
    cycle.len() == want.len() && (0..want.len()).any(|r| (0..want.len()).all(|k| cycle[(k + r) % want.len()] == want[k]))
}

/// The face whose node cycle is `want` (up to rotation).
fn face_with(s: &SurfaceLayout, want: &[u32]) -> usize {
    s.faces
        .iter()
        .position(|f| same_cycle(&f.nodes, want))
        .unwrap_or_else(|| panic!("no face {want:?}; faces {:?}", s.faces.iter().map(|f| &f.nodes).collect::<Vec<_>>()))
}

/// Orientation of (b − a) × (x − a) in the plane z = 0.
fn orient(a: [f64; 3], b: [f64; 3], x: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])
}

// ---------------------------------------------------------------------------------------
// A square with a plus sign on a planar grid

const N: u32 = 10;

fn g(i: u32, j: u32) -> u32 {
    gid(N, i, j)
}

/// Grid corners 0–3, a square 4–7 with side midpoints 8–11, its centre 12. Edges 0–7: the
/// square's sides in halves; 8–11: the plus sign from the centre; 12–15: diagonals from
/// the grid corners to the square's corners.
fn plus() -> Value {
    let nodes = [(0, 0), (N, 0), (N, N), (0, N), (2, 2), (8, 2), (8, 8), (2, 8), (5, 2), (8, 5), (5, 8), (2, 5), (5, 5)];
    let edges = [
        (4, 8), (8, 5), (5, 9), (9, 6), (6, 10), (10, 7), (7, 11), (11, 4),
        (12, 8), (12, 9), (12, 10), (12, 11),
        (0, 4), (1, 5), (2, 6), (3, 7),
    ];
    doc(nodes.iter().map(|&(i, j)| at(g(i, j))).collect(), edges.iter().map(|&(a, b)| edge(a, b)).collect())
}

/// The faces of [`plus`], counter-clockwise, with the expected angle at each node.
fn plus_faces() -> Vec<(Vec<u32>, Vec<f64>)> {
    let q = vec![FRAC_PI_2; 4];
    let t = vec![FRAC_PI_4, FRAC_PI_4, 3.0 * FRAC_PI_4, PI, 3.0 * FRAC_PI_4];
    vec![
        (vec![4, 8, 12, 11], q.clone()),
        (vec![8, 5, 9, 12], q.clone()),
        (vec![12, 9, 6, 10], q.clone()),
        (vec![11, 12, 10, 7], q),
        (vec![0, 1, 5, 8, 4], t.clone()),
        (vec![1, 2, 6, 9, 5], t.clone()),
        (vec![2, 3, 7, 10, 6], t.clone()),
        (vec![3, 0, 4, 11, 7], t),
    ]
}

#[test]
fn a_square_with_a_plus_sign_on_a_grid() {
    let m = grid(N);
    let d = plus();
    let layout = parse_layout(&d.to_string()).unwrap();
    let s = build(&m, &d).unwrap();
    assert_eq!((s.faces.len(), s.t_vertex_count()), (8, 4));
    assert_eq!(s.curves.len(), 16 + 4); // and the four sides of the grid
    assert_straight(&m, &s);
    check_invariants("plus", &m, &layout, &s, true);

    let expected = plus_faces();
    let mut face_of_expected = Vec::new();
    for (nodes, angles) in &expected {
        let fi = face_with(&s, nodes);
        face_of_expected.push(fi);
        let f = &s.faces[fi];
        for (k, &n) in f.nodes.iter().enumerate() {
            let want = angles[nodes.iter().position(|&x| x == n).unwrap()];
            assert!((f.angles[k] - want).abs() < 1e-9, "face {nodes:?}: angle {} at node {n}, expected {want}", f.angles[k]);
        }
        // The corners are the four smallest angles: the side midpoints are T-vertices.
        let t: Vec<u32> = f.t_vertices().collect();
        if nodes.len() == 5 {
            assert_eq!(t, vec![nodes[3]], "face {nodes:?}");
        } else {
            assert!(t.is_empty());
        }
    }

    // The face of every vertex: inside a face's polygon, that face; on a curve, one of the
    // faces it bounds.
    let pos = |n: u32| m.position(s.node_vertex[n as usize]);
    let mut inside_count = vec![0; 8];
    for v in 0..m.n_vertices() as u32 {
        let x = m.position(v);
        if s.node_vertex.contains(&v) {
            assert_eq!(s.vertex_face[v as usize], NONE);
            continue;
        }
        let side = |e: usize| {
            let nodes = &expected[e].0;
            let o: Vec<f64> = (0..nodes.len()).map(|k| orient(pos(nodes[k]), pos(nodes[(k + 1) % nodes.len()]), x)).collect();
            (o.iter().all(|&o| o > 1e-12), o.iter().all(|&o| o > -1e-12))
        };
        let strictly: Vec<usize> = (0..8).filter(|&e| side(e).0).collect();
        let closed: Vec<usize> = (0..8).filter(|&e| side(e).1).collect();
        let got = s.vertex_face[v as usize];
        if let [e] = strictly[..] {
            assert_eq!(got, face_of_expected[e] as u32, "vertex {v} at {x:?}");
            inside_count[e] += 1;
        } else {
            assert!(strictly.is_empty());
            assert!(closed.iter().any(|&e| face_of_expected[e] as u32 == got), "vertex {v} at {x:?} on a curve: face {got}, may be {closed:?}");
        }
    }
    // Inner squares hold the 2×2 grid points strictly inside; the trapezoids more.
    assert_eq!(&inside_count[..4], &[4, 4, 4, 4]);
    assert!(inside_count[4..].iter().all(|&c| c == inside_count[4] && c > 4), "{inside_count:?}");
}

#[test]
fn straight_curves_on_jagged_and_uniform_grids() {
    // The same layout on a grid with the other diagonals, and a waypoint on the line.
    let m = grid_with(N, Diagonals::Down);
    let mut d = plus();
    d["edges"][13]["via"] = json!([{ "vertex": g(9, 1) }]);
    d["edges"][9]["via"] = json!([{ "point": [0.7, 0.5, 0.0] }]);
    let s = build(&m, &d).unwrap();
    assert_eq!((s.faces.len(), s.t_vertex_count()), (8, 4));
    assert_straight(&m, &s);
    // Curves at slopes that cross the insides of mesh edges rather than running along them:
    // a skew quadrilateral joined to the grid's corners.
    let nodes = [(0, 0), (N, 0), (N, N), (0, N), (2, 1), (8, 4), (7, 9), (1, 6)];
    let edges = [(4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)];
    let d = doc(nodes.iter().map(|&(i, j)| at(g(i, j))).collect(), edges.iter().map(|&(a, b)| edge(a, b)).collect());
    for diag in [Diagonals::Alternating, Diagonals::Down] {
        let m = grid_with(N, diag);
        let s = build(&m, &d).unwrap();
        assert_eq!(s.faces.len(), 5);
        assert_straight(&m, &s);
        let crossings = s.curves[0].curve.points.iter().filter(|p| matches!(p, quadlay::layout::curve::CurvePoint::Edge { .. })).count();
        assert!(crossings > 0, "the skew curve crosses mesh edges");
        check_invariants("skew", &m, &parse_layout(&d.to_string()).unwrap(), &s, true);
    }
}

// ---------------------------------------------------------------------------------------
// Chart types

#[test]
fn chart_types_from_patches_and_defaults() {
    let m = grid(N);
    let mut d = plus();
    d["patches"] = json!([
        { "corners": [4, 8, 12, 11], "chart": "unit" },
        { "corners": [0, 1, 5, 8], "chart": "quad" },
        { "corners": [12, 9, 6, 10] },
    ]);
    d["defaults"] = json!({ "chart": "rect" });
    let layout = parse_layout(&d.to_string()).unwrap();
    assert_eq!(layout.default_chart, ChartType::Rect);
    let s = build(&m, &d).unwrap();
    check_invariants("charts", &m, &layout, &s, true);
    let faces = plus_faces();
    let chart_of = |k: usize| s.faces[face_with(&s, &faces[k].0)].chart;
    assert_eq!(chart_of(0), ChartType::Unit);
    assert_eq!(chart_of(4), ChartType::Quad);
    assert_eq!(chart_of(2), ChartType::Rect); // an entry without a chart takes the default
    for k in [1, 3, 5, 6, 7] {
        assert_eq!(chart_of(k), ChartType::Rect, "face {:?}", faces[k].0);
    }
    // The entry's corners win over the smallest angles: node 4 (3π/4) becomes the T-vertex
    // and the midpoint 8 (π) a corner.
    let bottom = &s.faces[face_with(&s, &faces[4].0)];
    assert!(same_cycle(&bottom.corner_nodes(), &[0, 1, 5, 8]), "{:?}", bottom.corner_nodes());
    assert_eq!(bottom.t_vertices().collect::<Vec<_>>(), vec![4]);
    assert_eq!(s.t_vertex_count(), 4);

    // Without defaults every other face is a general quad; with only defaults, all are unit.
    d.as_object_mut().unwrap().remove("defaults");
    let s = build(&m, &d).unwrap();
    let charts: Vec<ChartType> = faces.iter().map(|(n, _)| s.faces[face_with(&s, n)].chart).collect();
    use ChartType::*;
    assert_eq!(charts, vec![Unit, Quad, Quad, Quad, Quad, Quad, Quad, Quad]);
    let mut d = plus();
    d["defaults"] = json!({ "chart": "unit" });
    let s = build(&m, &d).unwrap();
    assert!(s.faces.iter().all(|f| f.chart == Unit));
    let s = build(&m, &plus()).unwrap();
    assert!(s.faces.iter().all(|f| f.chart == Quad));
}

// ---------------------------------------------------------------------------------------
// A coarse grid: curves leaving one node cut a triangle into three faces

#[test]
fn a_triangle_in_three_faces_on_a_coarse_grid() {
    let n = 4;
    let m = grid_with(n, Diagonals::Down);
    let p = |i: u32, j: u32| gid(n, i, j);
    // Centre C (node 0) with four curves: to (4,3) and (3,4), which both cross the triangle
    // (3,2) (3,3) (2,3), and along grid lines to (0,2) and (2,0). Boundary nodes at the
    // grid's corners and at (1,0), (0,1).
    let nodes = [(2, 2), (4, 3), (3, 4), (0, 2), (2, 0), (0, 0), (4, 0), (4, 4), (0, 4), (1, 0), (0, 1)];
    let d = doc(nodes.iter().map(|&(i, j)| at(p(i, j))).collect(), vec![edge(0, 1), edge(0, 2), edge(0, 3), edge(0, 4)]);
    let layout = parse_layout(&d.to_string()).unwrap();
    let s = build(&m, &d).unwrap();
    assert_straight(&m, &s);
    check_invariants("coarse", &m, &layout, &s, true);
    assert_eq!((s.faces.len(), s.t_vertex_count()), (4, 2));
    let f12 = face_with(&s, &[0, 1, 7, 2]) as u32;
    let f23 = face_with(&s, &[0, 2, 8, 3]) as u32;
    let f34 = face_with(&s, &[0, 3, 10, 5, 9, 4]) as u32;
    let f41 = face_with(&s, &[0, 4, 6, 1]) as u32;
    assert_eq!(s.faces[f34 as usize].t_vertices().collect::<Vec<_>>().len(), 2);

    let tri_of = |vs: [u32; 3]| {
        let mut want = vs;
        want.sort_unstable();
        m.triangles()
            .iter()
            .position(|t| {
                let mut t = *t;
                t.sort_unstable();
                t == want
            })
            .unwrap_or_else(|| panic!("no triangle {vs:?}"))
    };
    // Both curves cross this triangle: each corner in another face, all around node C.
    let t = tri_of([p(3, 2), p(3, 3), p(2, 3)]);
    let faces = [p(3, 2), p(3, 3), p(2, 3)].map(|v| s.vertex_face[v as usize]);
    assert_eq!(faces, [f41, f12, f23]);
    for f in faces {
        assert!(s.faces[f as usize].nodes.contains(&0));
    }
    assert!(faces.contains(&s.triangle_face[t]));
    // The curves really pass through it: one crossing on each of its two edges towards (3,3).
    let crosses = |c: usize, a: u32, b: u32| {
        let e = m.find_halfedge(a, b).map(|h| m.edge(h)).unwrap();
        s.curves[c].curve.points.iter().any(|q| matches!(q, quadlay::layout::curve::CurvePoint::Edge { edge, .. } if *edge == e))
    };
    assert!(crosses(0, p(3, 2), p(3, 3)) && crosses(0, p(3, 2), p(2, 3)));
    assert!(crosses(1, p(2, 3), p(3, 3)) && crosses(1, p(3, 2), p(2, 3)));

    // Vertices that curves run through join one of the faces beside them.
    assert!([f34, f23].contains(&s.vertex_face[p(1, 2) as usize]));
    assert!([f34, f41].contains(&s.vertex_face[p(2, 1) as usize]));
    assert_eq!(s.vertex_face[p(1, 1) as usize], f34);
    assert_eq!(s.vertex_face[p(3, 1) as usize], f41);
    assert_eq!(s.vertex_face[p(1, 3) as usize], f23);

    // Triangles whose corners are all nodes lie in the face of their sector.
    assert_eq!(s.triangle_face[tri_of([p(0, 0), p(1, 0), p(0, 1)])], f34);
    assert_eq!(s.triangle_face[tri_of([p(4, 3), p(4, 4), p(3, 4)])], f12);
    // A triangle at C cut by a curve: the face of its first non-node corner.
    let t = tri_of([p(2, 2), p(3, 2), p(2, 3)]);
    assert!([f41, f23].contains(&s.triangle_face[t]));
}

// ---------------------------------------------------------------------------------------
// Closed surfaces of genus 0 and 1

#[test]
fn layouts_on_a_cube_and_a_torus() {
    // The cube with its own edges as the layout: 6 faces, angles π/2 (three faces of 3π/2).
    let (c, ids) = cube(4);
    let corners: Vec<[u32; 3]> = (0..8).map(|k| [4 * (k & 1), 4 * (k >> 1 & 1), 4 * (k >> 2)]).collect();
    let nodes: Vec<Value> = corners.iter().map(|p| at(ids[p])).collect();
    let mut edges = Vec::new();
    for a in 0..8u32 {
        for b in a + 1..8 {
            if (a ^ b).count_ones() == 1 {
                edges.push(edge(a, b));
            }
        }
    }
    let d = doc(nodes, edges);
    let s = build(&c, &d).unwrap();
    check_invariants("cube", &c, &parse_layout(&d.to_string()).unwrap(), &s, true);
    assert_eq!((s.faces.len(), s.t_vertex_count()), (6, 0));
    for f in &s.faces {
        assert!(f.angles.iter().all(|a| (a - FRAC_PI_2).abs() < 1e-9), "{:?}", f.angles);
    }
    assert_straight(&c, &s);

    // Torus (24 × 12): two meridians and the two equators, each cut in halves by waypoints.
    let t = torus(24, 12);
    let id = |i: u32, j: u32| i * 12 + j;
    let nodes = vec![at(id(0, 0)), at(id(0, 6)), at(id(12, 0)), at(id(12, 6))];
    let via = |a: u32, b: u32, w: u32| json!({ "nodes": [a, b], "via": [{ "vertex": w }] });
    let edges = vec![
        via(0, 1, id(0, 3)),
        via(0, 1, id(0, 9)),
        via(2, 3, id(12, 3)),
        via(2, 3, id(12, 9)),
        via(0, 2, id(6, 0)),
        via(0, 2, id(18, 0)),
        via(1, 3, id(6, 6)),
        via(1, 3, id(18, 6)),
    ];
    let d = doc(nodes, edges);
    let s = build(&t, &d).unwrap_or_else(|e| panic!("torus: {e}"));
    check_invariants("torus", &t, &parse_layout(&d.to_string()).unwrap(), &s, true);
    assert_eq!((s.faces.len(), s.t_vertex_count()), (4, 0));
    assert_eq!(mesh_euler(&t), 0);
}

// ---------------------------------------------------------------------------------------
// The sample layouts

/// The mesh each sample layout is drawn on, by name.
fn sample_mesh(name: &str) -> Option<&'static str> {
    match name {
        _ if name.starts_with("fandisk-") => Some("fandisk.obj"),
        _ if name.starts_with("bunny-") => Some("bunny_28k.obj"),
        _ if name.starts_with("mushroom-") => Some("mushroom.obj"),
        _ if name.starts_with("eight-") => Some("eight.obj"),
        _ => None,
    }
}

/// Faces and T-vertices of each sample (as `quadlay check` prints them).
const SAMPLES: [(&str, usize, usize); 8] = [
    ("bunny-cube", 6, 0),
    ("bunny-ears", 28, 12),
    ("eight-rims", 12, 8),
    ("fandisk-cube", 6, 0),
    ("fandisk-features", 37, 18),
    ("mushroom-4", 1, 0),
    ("mushroom-grid", 4, 0),
    ("mushroom-t", 7, 2),
];

#[test]
fn every_sample_layout_builds_with_its_counts() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/www/layouts");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter_map(|f| f.strip_suffix(".layout.json").map(str::to_string))
        .collect();
    names.sort();
    let table: Vec<&str> = SAMPLES.iter().map(|s| s.0).collect();
    assert_eq!(names, table, "www/layouts and the SAMPLES table differ: add new layouts to the table");

    let mut meshes: HashMap<&str, Mesh> = HashMap::new();
    for (name, faces, t) in SAMPLES {
        let mesh_name = sample_mesh(name).unwrap_or_else(|| panic!("{name}: which mesh? add it to sample_mesh"));
        let mesh = meshes.entry(mesh_name).or_insert_with(|| load_mesh(mesh_name));
        let text = std::fs::read_to_string(format!("{dir}/{name}.layout.json")).unwrap();
        let layout = parse_layout(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let s = quadlay::layout::build_layout(mesh, &layout).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((s.faces.len(), s.t_vertex_count()), (faces, t), "{name}: (faces, T-vertices)");
        check_invariants(name, mesh, &layout, &s, true);
        // Written and read back, the layout builds the same faces.
        let again = parse_layout(&quadlay::layout::write_layout(&layout)).unwrap();
        assert_eq!(again, layout, "{name}");
    }
}

// ---------------------------------------------------------------------------------------
// The direction in which an edge is listed does not matter

#[test]
fn edge_direction_does_not_change_the_faces() {
    // A square along grid lines inside a frame of diagonals; its sides listed clockwise, so
    // the inner face runs every one of them backwards.
    let m = grid(N);
    let nodes = [(0, 0), (N, 0), (N, N), (0, N), (2, 2), (8, 2), (8, 8), (2, 8)];
    let ccw = [(4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)];
    let mut results = Vec::new();
    for flip in [false, true] {
        let edges = ccw.iter().map(|&(a, b)| if flip { edge(b, a) } else { edge(a, b) }).collect();
        let d = doc(nodes.iter().map(|&(i, j)| at(g(i, j))).collect(), edges);
        let s = build(&m, &d).unwrap_or_else(|e| panic!("flip {flip}: {e}"));
        check_invariants("flip", &m, &parse_layout(&d.to_string()).unwrap(), &s, true);
        let inner = face_with(&s, &[4, 5, 6, 7]);
        // Vertices a curve runs through may join either side (the spec leaves it open);
        // compare the others.
        let mut on_curve = vec![false; m.n_vertices()];
        for c in &s.curves {
            for p in &c.curve.points {
                if let quadlay::layout::curve::CurvePoint::Vertex(v) = *p {
                    on_curve[v as usize] = true;
                }
            }
        }
        let named: Vec<Vec<u32>> = (0..m.n_vertices())
            .map(|v| match s.vertex_face[v] {
                f if f == NONE || on_curve[v] => vec![],
                f => s.faces[f as usize].nodes.clone(),
            })
            .collect();
        let count = (0..m.n_vertices()).filter(|&v| !on_curve[v] && s.vertex_face[v] == inner as u32).count();
        assert_eq!(count, 5 * 5, "flip {flip}: the inner square holds the grid points (3..=7)²");
        results.push(named);
    }
    for v in 0..m.n_vertices() {
        let (a, b) = (&results[0][v], &results[1][v]);
        let rot = a.iter().position(|x| b.first() == Some(x));
        assert!(a.is_empty() && b.is_empty() || rot.is_some() && same_cycle(a, b), "vertex {v}: {a:?} vs {b:?}");
    }
}

// ---------------------------------------------------------------------------------------
// The invariants can fail

#[test]
fn the_invariants_catch_a_wrong_face() {
    let m = grid(N);
    let d = plus();
    let layout = parse_layout(&d.to_string()).unwrap();
    let s = build(&m, &d).unwrap();
    let inner = face_with(&s, &[4, 8, 12, 11]) as u32;
    let other = face_with(&s, &[12, 9, 6, 10]) as u32;
    let fails = |t: &SurfaceLayout, connected: bool| {
        let (m, layout, t) = (m.clone(), layout.clone(), t.clone());
        std::panic::catch_unwind(move || check_invariants("tampered", &m, &layout, &t, connected)).is_err()
    };
    assert!(!fails(&s, true));
    // A vertex inside the south-west square, moved to the north-east one: caught without the
    // connectivity check (by the flood of triangle pieces).
    let mut t = s.clone();
    assert_eq!(t.vertex_face[g(3, 3) as usize], inner);
    t.vertex_face[g(3, 3) as usize] = other;
    assert!(fails(&t, false));
    // A whole face's vertices given to its neighbour.
    let mut t = s.clone();
    for f in t.vertex_face.iter_mut().filter(|f| **f == inner) {
        *f = other;
    }
    assert!(fails(&t, false));
    // A triangle in the wrong face, a node with a face, corners out of order.
    let mut t = s.clone();
    t.triangle_face[0] = (t.triangle_face[0] + 1) % 8;
    assert!(fails(&t, false));
    let mut t = s.clone();
    t.vertex_face[g(5, 5) as usize] = inner;
    assert!(fails(&t, false));
    let mut t = s.clone();
    t.faces[0].corners = [0, 2, 1, 3];
    assert!(fails(&t, false));
    let mut t = s.clone();
    t.faces[0].pieces.swap(0, 1);
    assert!(fails(&t, false));
    let mut t = s;
    t.faces[0].angles[0] += 0.1;
    assert!(fails(&t, false));
}
