//! Shared fixtures for the integration tests: the shared meshes and the `quadlay` binary.
#![allow(dead_code)] // each test crate uses its own subset

use std::path::{Path, PathBuf};
use std::process::Command;

/// `../shared/meshes/NAME`, beside the crate.
pub fn shared_mesh(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes").join(name)
}

/// Runs the `quadlay` binary with `args`; returns (exit code, stdout, stderr).
pub fn run_cli(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_quadlay"))
        .args(args)
        .output()
        .expect("cannot run the quadlay binary");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

// ---------------------------------------------------------------------------------------
// Meshes and layouts built in the tests (layout_errors.rs, layouts.rs).

use quadlay::layout::{build_layout, parse_layout, LayoutError, SurfaceLayout};
use quadlay::mesh::{build_mesh, Mesh, TriangleSoup};
use quadlay::quad::QuadMesh;
use serde_json::{json, Value};
use std::collections::{HashMap, HashSet};
use std::time::Duration;

/// A shared mesh read through the library, as the file gives it.
pub fn load_loaded(name: &str) -> quadlay::io::LoadedMesh {
    let bytes = std::fs::read(shared_mesh(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    quadlay::io::read_mesh(&bytes, name).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A shared mesh read through the library.
pub fn load_mesh(name: &str) -> Mesh {
    load_loaded(name).mesh
}

/// A shared mesh as the commands and the page work on it: refined where it is coarse
/// (`LoadedMesh::refined`), with the counts of the file, whose vertex numbering layout files
/// use.
pub fn load_working_mesh(name: &str) -> (Mesh, quadlay::layout::MeshCounts) {
    let loaded = load_loaded(name);
    let file = quadlay::layout::MeshCounts::of(&loaded.mesh);
    (loaded.refined().mesh, file)
}

pub fn mesh_of(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Mesh {
    build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).expect("test mesh").mesh
}

/// How the unit squares of a grid are split into triangles.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Diagonals {
    /// Square (i, j) split along (i, j)–(i+1, j+1) when i + j is even, else along
    /// (i+1, j)–(i, j+1).
    Alternating,
    /// Every square split along (i+1, j)–(i, j+1).
    Down,
}

/// Vertex of grid point (i, j) of an n×n grid: `j * (n + 1) + i`.
pub fn gid(n: u32, i: u32, j: u32) -> u32 {
    j * (n + 1) + i
}

/// Triangles of an n×n grid with vertex ids from `id`, counter-clockwise seen from +z,
/// leaving out the squares for which `skip(i, j)` holds.
fn grid_triangles(n: u32, diag: Diagonals, id: &dyn Fn(u32, u32) -> u32, skip: &dyn Fn(u32, u32) -> bool) -> Vec<[u32; 3]> {
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if skip(i, j) {
                continue;
            }
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if diag == Diagonals::Alternating && (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    triangles
}

fn grid_positions(n: u32, offset: [f64; 3]) -> Vec<[f64; 3]> {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push([offset[0] + i as f64 / n as f64, offset[1] + j as f64 / n as f64, offset[2]]);
        }
    }
    positions
}

/// The planar n×n grid on [0,1]² (z = 0), diagonals as `diag`; vertex ids from [`gid`].
pub fn grid_with(n: u32, diag: Diagonals) -> Mesh {
    mesh_of(grid_positions(n, [0.0; 3]), grid_triangles(n, diag, &|i, j| gid(n, i, j), &|_, _| false))
}

/// [`grid_with`] alternating diagonals.
pub fn grid(n: u32) -> Mesh {
    grid_with(n, Diagonals::Alternating)
}

/// The n×n grid without the squares (i, j) with `lo <= i, j < hi`: an annulus with two
/// boundary loops; grid points strictly inside the hole stay as unreferenced vertices.
pub fn grid_with_hole(n: u32, lo: u32, hi: u32) -> Mesh {
    let skip = |i: u32, j: u32| (lo..hi).contains(&i) && (lo..hi).contains(&j);
    mesh_of(grid_positions(n, [0.0; 3]), grid_triangles(n, Diagonals::Alternating, &|i, j| gid(n, i, j), &skip))
}

/// Two n×n grids, the second moved by (3, 0, 0): two components. The second grid's point
/// (i, j) is vertex `(n + 1)² + gid(n, i, j)`.
pub fn two_grids(n: u32) -> Mesh {
    let mut positions = grid_positions(n, [0.0; 3]);
    positions.extend(grid_positions(n, [3.0, 0.0, 0.0]));
    let off = (n + 1) * (n + 1);
    let mut triangles = grid_triangles(n, Diagonals::Alternating, &|i, j| gid(n, i, j), &|_, _| false);
    triangles.extend(grid_triangles(n, Diagonals::Alternating, &|i, j| off + gid(n, i, j), &|_, _| false));
    mesh_of(positions, triangles)
}

/// The surface of the unit cube, each side an n×n grid, outward facing; the vertex of
/// lattice point (i, j, k) in 0..=n is `ids[&[i, j, k]]`.
pub fn cube(n: u32) -> (Mesh, HashMap<[u32; 3], u32>) {
    quadlay::mesh::primitives::parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], n)
}

/// A torus of revolution about the z axis (radii 2 and 0.7), `nu` steps around the axis
/// and `nv` around the tube; the vertex at steps (i, j) is `i * nv + j`; (0, 0) is on the
/// outer equator, (0, nv/2) on the inner one.
pub fn torus(nu: u32, nv: u32) -> Mesh {
    use std::f64::consts::TAU;
    let (big, small) = (2.0, 0.7);
    let profile: Vec<[f64; 2]> = (0..nv).map(|j| TAU * j as f64 / nv as f64).map(|v| [big + small * v.cos(), small * v.sin()]).collect();
    revolved(nu, &profile)
}

/// A washer: the rectangle 1 ≤ r ≤ 2, 0 ≤ z ≤ 0.5 revolved about the z axis in `nu` steps,
/// `m` steps up each cylinder and `2m` across each flat ring. Two flat rings and two
/// cylinders, all developable, meet at four circular sharp rims that have no corner.
pub fn washer(nu: u32, m: u32) -> Mesh {
    let side = |from: [f64; 2], to: [f64; 2], steps: u32| {
        (0..steps).map(move |k| {
            let t = k as f64 / steps as f64;
            [from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])]
        })
    };
    let (a, b, c, d) = ([2.0, 0.0], [2.0, 0.5], [1.0, 0.5], [1.0, 0.0]);
    let profile: Vec<[f64; 2]> = side(a, b, m).chain(side(b, c, 2 * m)).chain(side(c, d, m)).chain(side(d, a, 2 * m)).collect();
    revolved(nu, &profile)
}

/// The closed profile `profile` (points (r, z), counter-clockwise in the r–z plane) revolved
/// about the z axis in `nu` steps; the vertex at steps (i, j) is `i * profile.len() + j`.
pub fn revolved(nu: u32, profile: &[[f64; 2]]) -> Mesh {
    use std::f64::consts::TAU;
    let nv = profile.len() as u32;
    let mut positions = Vec::new();
    for i in 0..nu {
        let u = TAU * i as f64 / nu as f64;
        positions.extend(profile.iter().map(|&[r, z]| [r * u.cos(), r * u.sin(), z]));
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let triangles = grid_triangles(nu.max(nv), Diagonals::Alternating, &id, &|i, j| i >= nu || j >= nv);
    mesh_of(positions, triangles)
}

/// The mesh as OBJ text (for the command line).
pub fn obj_text(mesh: &Mesh) -> String {
    let mut s = String::new();
    for p in mesh.positions() {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in mesh.triangles() {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// `{"vertex": v}`
pub fn at(v: u32) -> Value {
    json!({ "vertex": v })
}

/// `{"nodes": [a, b]}`
pub fn edge(a: u32, b: u32) -> Value {
    json!({ "nodes": [a, b] })
}

/// A version 1 layout document.
pub fn doc(nodes: Vec<Value>, edges: Vec<Value>) -> Value {
    json!({ "format": "quad-layout", "version": 1, "nodes": nodes, "edges": edges })
}

/// Reads `doc` as a layout file and places it on `mesh`.
pub fn build(mesh: &Mesh, doc: &Value) -> Result<SurfaceLayout, LayoutError> {
    let layout = parse_layout(&doc.to_string())?;
    build_layout(mesh, &layout)
}

/// Runs `f` on its own thread; panics if it panics or takes longer than `limit`.
pub fn within<T: Send + 'static>(limit: Duration, what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(limit) {
        Ok(v) => v,
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("{what}: still running after {limit:?}"),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => panic!("{what}: panicked"),
    }
}

/// A small deterministic generator (xorshift64*).
pub struct XorShift(pub u64);
impl XorShift {
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

/// V − E + F of the mesh, counting only vertices that triangles use.
pub fn mesh_euler(mesh: &Mesh) -> i64 {
    let used = (0..mesh.n_vertices() as u32).filter(|&v| !mesh.is_isolated(v)).count();
    used as i64 - mesh.n_edges() as i64 + mesh.n_faces() as i64
}

/// Every structural invariant of a [`SurfaceLayout`] (see tests/layouts.rs); `layout` is the
/// file it was built from. `connected` also checks that each face's vertices are connected
/// over uncrossed mesh edges (true of fine meshes, not of every coarse one).
pub fn check_invariants(name: &str, mesh: &Mesh, layout: &quadlay::layout::Layout, s: &SurfaceLayout, connected: bool) {
    use quadlay::layout::curve::CurvePoint;
    use quadlay::layout::CurveSource;
    use quadlay::mesh::NONE;
    let nf = s.faces.len();
    assert_eq!(s.node_vertex.len(), layout.nodes.len(), "{name}");
    assert_eq!(s.vertex_face.len(), mesh.n_vertices(), "{name}");
    assert_eq!(s.triangle_face.len(), mesh.n_faces(), "{name}");

    // Vertex faces: nodes NONE, every other used vertex some face.
    let mut is_node = vec![false; mesh.n_vertices()];
    for &v in &s.node_vertex {
        is_node[v as usize] = true;
    }
    for v in 0..mesh.n_vertices() {
        let f = s.vertex_face[v];
        if is_node[v] || mesh.is_isolated(v as u32) {
            assert_eq!(f, NONE, "{name}: vertex {v} (a node or unused) has face {f}");
        } else {
            assert!((f as usize) < nf, "{name}: vertex {v} has face {f} of {nf}");
        }
    }
    // Triangle faces: the face of the first corner that is not a node, else a face around
    // the triangle's nodes.
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let f = s.triangle_face[t];
        assert!((f as usize) < nf, "{name}: triangle {t} has face {f} of {nf}");
        match tri.iter().find(|&&v| !is_node[v as usize]) {
            Some(&v) => assert_eq!(f, s.vertex_face[v as usize], "{name}: triangle {t}"),
            None => {
                let nodes: Vec<u32> =
                    tri.iter().map(|&v| s.node_vertex.iter().position(|&x| x == v).unwrap() as u32).collect();
                assert!(nodes.iter().all(|n| s.faces[f as usize].nodes.contains(n)), "{name}: triangle {t} of nodes {nodes:?} in face {f}");
            }
        }
    }

    // Faces: at least four nodes, corners at increasing positions from 0, pieces chained.
    let ends = |d: &quadlay::layout::embedding::Directed| {
        let n = s.curves[d.curve as usize].nodes;
        if d.forward { (n[0], n[1]) } else { (n[1], n[0]) }
    };
    let mut uses = vec![(0usize, 0usize); s.curves.len()];
    // The angles of the faces around a node fill the angle around it.
    let corner_angles = quadlay::mesh::geometry::corner_angles(mesh);
    let mut total_angle = vec![0.0; s.node_vertex.len()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            if let Some(n) = s.node_vertex.iter().position(|&v| v == tri[k]) {
                total_angle[n] += corner_angles[t][k];
            }
        }
    }
    let mut angle_sum = vec![0.0; s.node_vertex.len()];
    for (fi, f) in s.faces.iter().enumerate() {
        let k = f.nodes.len();
        assert!(k >= 4, "{name}: face {fi} has {k} nodes");
        assert_eq!((f.pieces.len(), f.angles.len()), (k, k), "{name}: face {fi}");
        assert_eq!(f.corners[0], 0, "{name}: face {fi}");
        assert!(f.corners.windows(2).all(|w| w[0] < w[1]) && f.corners[3] < k, "{name}: face {fi} corners {:?}", f.corners);
        assert_eq!(f.t_vertices().count(), k - 4, "{name}: face {fi}");
        for (p, d) in f.pieces.iter().enumerate() {
            let (from, to) = ends(d);
            assert_eq!(from, f.nodes[p], "{name}: face {fi} piece {p} starts elsewhere");
            let (next_from, _) = ends(&f.pieces[(p + 1) % k]);
            assert_eq!(to, next_from, "{name}: face {fi}: piece {p} does not end where piece {} starts", (p + 1) % k);
            if d.forward { uses[d.curve as usize].0 += 1 } else { uses[d.curve as usize].1 += 1 }
        }
        for (k, a) in f.angles.iter().enumerate() {
            let total = total_angle[f.nodes[k] as usize];
            assert!(*a > 0.0 && *a <= total + 1e-9, "{name}: face {fi}: angle {a} at node {} of total angle {total}", f.nodes[k]);
            angle_sum[f.nodes[k] as usize] += a;
        }
        let mut sorted = f.nodes.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), k, "{name}: face {fi} passes a node twice: {:?}", f.nodes);
        for s_ in 0..4 {
            assert!(!f.side(s_).is_empty(), "{name}: face {fi} side {s_} empty");
        }
    }
    for (n, (&sum, &total)) in angle_sum.iter().zip(&total_angle).enumerate() {
        assert!((sum - total).abs() < 1e-9 * total.max(1.0), "{name}: node {n}: face angles sum to {sum}, the angle around it is {total}");
    }
    // Each layout edge bounds two faces (one on each side), each boundary piece one.
    for (c, u) in uses.iter().enumerate() {
        match s.curves[c].source {
            CurveSource::Edge(_) => assert_eq!(*u, (1, 1), "{name}: curve {c} (forward, backward) uses"),
            CurveSource::Boundary { .. } => {
                assert_eq!(*u, (1, 0), "{name}: curve {c} (forward, backward) uses");
                assert!(s.curves[c].align, "{name}: boundary curve {c} not aligned");
            }
        }
    }
    let n_edges = s.curves.iter().filter(|c| matches!(c.source, CurveSource::Edge(_))).count();
    assert_eq!(n_edges, layout.edges.len(), "{name}");
    for (i, e) in layout.edges.iter().enumerate() {
        assert_eq!(s.curves[i].source, CurveSource::Edge(i), "{name}");
        assert_eq!((s.curves[i].nodes, s.curves[i].align), (e.nodes, e.align), "{name}: curve {i}");
    }
    for c in &s.curves {
        let p = &c.curve.points;
        assert_eq!(p.first(), Some(&CurvePoint::Vertex(s.node_vertex[c.nodes[0] as usize])), "{name}");
        assert_eq!(p.last(), Some(&CurvePoint::Vertex(s.node_vertex[c.nodes[1] as usize])), "{name}");
    }

    // Euler: nodes − curves + faces = V − E + F.
    let chi = s.node_vertex.len() as i64 - s.curves.len() as i64 + nf as i64;
    assert_eq!(chi, mesh_euler(mesh), "{name}: nodes {} − curves {} + faces {nf}", s.node_vertex.len(), s.curves.len());

    // Faces without a patches entry have their four smallest angles at the corners; faces
    // with one have its corners in its cyclic order.
    let mut named = vec![false; nf];
    for p in &layout.patches {
        let fi = s
            .faces
            .iter()
            .position(|f| {
                let c = f.corner_nodes();
                (0..4).any(|r| (0..4).all(|k| c[(k + r) % 4] == p.corners[k]))
            })
            .unwrap_or_else(|| panic!("{name}: no face has the corners {:?} in this order", p.corners));
        named[fi] = true;
        if let Some(chart) = p.chart {
            assert_eq!(s.faces[fi].chart, chart, "{name}: face {fi}");
        }
    }
    for (fi, f) in s.faces.iter().enumerate().filter(|(fi, _)| !named[*fi]) {
        assert_eq!(f.chart, layout.default_chart, "{name}: face {fi}");
        let worst_corner = f.corners.iter().map(|&k| f.angles[k]).fold(f64::MIN, f64::max);
        let best_t = (0..f.nodes.len()).filter(|k| !f.corners.contains(k)).map(|k| f.angles[k]).fold(f64::MAX, f64::min);
        assert!(worst_corner <= best_t, "{name}: face {fi}: a T-vertex has a smaller angle than a corner: {:?} {:?}", f.corners, f.angles);
    }

    // Vertices of different faces are kept apart by curves of those faces: an edge between
    // two vertices off the curves joins two faces only if it crosses a curve bounding each,
    // and a vertex a curve runs through belongs to a face that curve bounds.
    let mut crossed_by: Vec<Vec<u32>> = vec![Vec::new(); mesh.n_edges()];
    let mut on_curve = vec![NONE; mesh.n_vertices()];
    for (ci, c) in s.curves.iter().enumerate() {
        for p in &c.curve.points {
            match *p {
                CurvePoint::Edge { edge, .. } => crossed_by[edge as usize].push(ci as u32),
                CurvePoint::Vertex(v) if !is_node[v as usize] => on_curve[v as usize] = ci as u32,
                _ => {}
            }
        }
    }
    let bounds = |f: u32, c: u32| s.faces[f as usize].pieces.iter().any(|d| d.curve == c);
    for v in 0..mesh.n_vertices() {
        if on_curve[v] != NONE {
            assert!(bounds(s.vertex_face[v], on_curve[v]), "{name}: vertex {v} on curve {} is in face {}, which it does not bound", on_curve[v], s.vertex_face[v]);
        }
    }
    let off = |v: usize| s.vertex_face[v] != NONE && on_curve[v] == NONE;
    for e in 0..mesh.n_edges() as u32 {
        let (a, b) = (mesh.from_vertex(2 * e) as usize, mesh.to_vertex(2 * e) as usize);
        let (fa, fb) = (s.vertex_face[a], s.vertex_face[b]);
        if !off(a) || !off(b) || fa == fb {
            continue;
        }
        let cs = &crossed_by[e as usize];
        assert!(
            cs.iter().any(|&c| bounds(fa, c)) && cs.iter().any(|&c| bounds(fb, c)),
            "{name}: vertices {a} (face {fa}) and {b} (face {fb}) are joined by edge {e}, which crosses curves {cs:?}"
        );
    }

    flood_oracle(name, mesh, s, &is_node, &on_curve);

    if connected {
        // The vertices of each face are one piece over mesh edges no curve crosses, joined
        // also through the face's own nodes (a thin face may have its vertices only around a
        // node); except that in a corner sharper than 20° a vertex can be walled in by the
        // two curves.
        fn root(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        for (fi, f) in s.faces.iter().enumerate() {
            let mut member = vec![false; mesh.n_vertices()];
            for v in 0..mesh.n_vertices() {
                member[v] = s.vertex_face[v] == fi as u32;
            }
            for &n in &f.nodes {
                member[s.node_vertex[n as usize] as usize] = true;
            }
            let mut parent: Vec<usize> = (0..mesh.n_vertices()).collect();
            for e in 0..mesh.n_edges() as u32 {
                let (a, b) = (mesh.from_vertex(2 * e) as usize, mesh.to_vertex(2 * e) as usize);
                if crossed_by[e as usize].is_empty() && member[a] && member[b] {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    parent[ra] = rb;
                }
            }
            let mut pieces: HashMap<usize, usize> = HashMap::new();
            for v in 0..mesh.n_vertices() {
                if s.vertex_face[v] == fi as u32 {
                    *pieces.entry(root(&mut parent, v)).or_insert(0) += 1;
                }
            }
            assert!(!pieces.is_empty(), "{name}: face {fi} has no vertex");
            let sharp = f.angles.iter().any(|&a| a < 20f64.to_radians());
            if !sharp {
                assert_eq!(pieces.len(), 1, "{name}: face {fi}'s vertices fall apart into pieces of sizes {:?}", pieces.values().collect::<Vec<_>>());
            }
        }
    }
}

/// An independent check of the face of every vertex: cut each triangle into pieces along
/// the curve segments inside it, flood the pieces across the shared stretches of mesh edges
/// (never across an edge a curve runs along), and require that two vertices off the curves
/// lie in the same face exactly when they lie in the same flooded region.
fn flood_oracle(name: &str, mesh: &Mesh, s: &SurfaceLayout, is_node: &[bool], on_curve: &[u32]) {
    use quadlay::layout::curve::CurvePoint;
    use quadlay::mesh::NONE;
    let tris = mesh.triangles();
    // Position of a curve point on the perimeter of triangle t: k + u on side c_k → c_{k+1}.
    let perimeter = |t: usize, p: &CurvePoint| -> Option<f64> {
        let c = tris[t];
        match *p {
            CurvePoint::Vertex(v) => c.iter().position(|&x| x == v).map(|k| k as f64),
            CurvePoint::Edge { edge, t: u } => {
                let (a, b) = (mesh.from_vertex(2 * edge), mesh.to_vertex(2 * edge));
                (0..3).find_map(|k| {
                    let (x, y) = (c[k], c[(k + 1) % 3]);
                    if (x, y) == (a, b) {
                        Some(k as f64 + u)
                    } else if (x, y) == (b, a) {
                        Some(k as f64 + 1.0 - u)
                    } else {
                        None
                    }
                })
            }
        }
    };
    let faces_of = |p: &CurvePoint| -> Vec<usize> {
        match *p {
            CurvePoint::Vertex(v) => mesh.outgoing(v).map(|h| mesh.face(h)).filter(|&f| f != NONE).map(|f| f as usize).collect(),
            CurvePoint::Edge { edge, .. } => {
                [mesh.face(2 * edge), mesh.face(2 * edge + 1)].into_iter().filter(|&f| f != NONE).map(|f| f as usize).collect()
            }
        }
    };
    let mut wall = vec![false; mesh.n_edges()];
    let mut chords: Vec<Vec<(f64, f64)>> = vec![Vec::new(); tris.len()];
    let mut cuts_on_edge: Vec<Vec<f64>> = vec![Vec::new(); mesh.n_edges()];
    for c in &s.curves {
        for p in &c.curve.points {
            if let CurvePoint::Edge { edge, t } = *p {
                cuts_on_edge[edge as usize].push(t);
            }
        }
        for w in c.curve.points.windows(2) {
            let fq = faces_of(&w[1]);
            let common: Vec<usize> = faces_of(&w[0]).into_iter().filter(|f| fq.contains(f)).collect();
            let along = match (w[0], w[1]) {
                (CurvePoint::Vertex(a), CurvePoint::Vertex(b)) => mesh.find_halfedge(a, b).map(|h| mesh.edge(h)),
                _ if common.len() == 2 => {
                    // Both points on one mesh edge: the edge the two triangles share.
                    let (t0, t1) = (tris[common[0]], tris[common[1]]);
                    let shared: Vec<u32> = t0.iter().copied().filter(|v| t1.contains(v)).collect();
                    mesh.find_halfedge(shared[0], shared[1]).map(|h| mesh.edge(h))
                }
                _ => None,
            };
            if let Some(e) = along {
                wall[e as usize] = true;
                continue;
            }
            assert_eq!(common.len(), 1, "{name}: a curve segment {w:?} in no single triangle");
            let t = common[0];
            let (a, b) = (perimeter(t, &w[0]).unwrap(), perimeter(t, &w[1]).unwrap());
            chords[t].push((a, b));
        }
    }
    // Arcs of each triangle's perimeter between chord ends, and the piece of each arc.
    let in_open = |x: f64, a: f64, b: f64| {
        // x strictly inside the cyclic interval from a to b
        let (d, l) = ((x - a).rem_euclid(3.0), (b - a).rem_euclid(3.0));
        d > 1e-12 && d < l - 1e-12
    };
    let mut breaks: Vec<Vec<f64>> = Vec::with_capacity(tris.len());
    let mut piece_of_arc: Vec<Vec<usize>> = Vec::with_capacity(tris.len());
    let mut offset = vec![0usize; tris.len() + 1];
    for t in 0..tris.len() {
        let mut b: Vec<f64> = chords[t].iter().flat_map(|&(x, y)| [x, y]).collect();
        b.sort_by(f64::total_cmp);
        b.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
        let n_arcs = b.len().max(1);
        let mid = |i: usize| if b.is_empty() { 0.5 } else { let (x, y) = (b[i], b[(i + 1) % b.len()]); x + 0.5 * (y - x).rem_euclid(3.0) };
        let mut piece: Vec<usize> = (0..n_arcs).collect();
        for i in 0..n_arcs {
            for j in 0..i {
                let separated = chords[t].iter().any(|&(x, y)| in_open(mid(i), x, y) != in_open(mid(j), x, y));
                if !separated {
                    piece[i] = piece[j];
                    break;
                }
            }
        }
        offset[t + 1] = offset[t] + n_arcs;
        breaks.push(b);
        piece_of_arc.push(piece);
    }
    // The flood node of the arc of triangle t holding perimeter position x (not a break).
    let node_at = |t: usize, x: f64| -> usize {
        let b = &breaks[t];
        if b.is_empty() {
            return offset[t];
        }
        let i = (0..b.len()).find(|&i| in_open(x, b[i], b[(i + 1) % b.len()]) || (b.len() == 1)).unwrap_or(0);
        offset[t] + piece_of_arc[t][i]
    };
    let mut parent: Vec<usize> = (0..offset[tris.len()]).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for e in 0..mesh.n_edges() as u32 {
        let (f0, f1) = (mesh.face(2 * e), mesh.face(2 * e + 1));
        if wall[e as usize] || f0 == NONE || f1 == NONE {
            continue;
        }
        let mut ts = cuts_on_edge[e as usize].clone();
        ts.extend([0.0, 1.0]);
        ts.sort_by(f64::total_cmp);
        for w in ts.windows(2) {
            if w[1] - w[0] < 1e-12 {
                continue;
            }
            let m = CurvePoint::Edge { edge: e, t: 0.5 * (w[0] + w[1]) };
            let (a, b) = (node_at(f0 as usize, perimeter(f0 as usize, &m).unwrap()), node_at(f1 as usize, perimeter(f1 as usize, &m).unwrap()));
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra] = rb;
        }
    }
    let mut face_of_region: HashMap<usize, u32> = HashMap::new();
    let mut region_of_face: HashMap<u32, usize> = HashMap::new();
    for v in 0..mesh.n_vertices() as u32 {
        if is_node[v as usize] || on_curve[v as usize] != NONE || mesh.is_isolated(v) {
            continue;
        }
        let h = mesh.outgoing(v).find(|&h| mesh.face(h) != NONE).unwrap();
        let t = mesh.face(h) as usize;
        let k = tris[t].iter().position(|&x| x == v).unwrap();
        let r = root(&mut parent, node_at(t, k as f64));
        let f = s.vertex_face[v as usize];
        assert_eq!(*face_of_region.entry(r).or_insert(f), f, "{name}: vertex {v} in face {f} shares its region with another face");
        assert_eq!(*region_of_face.entry(f).or_insert(r), r, "{name}: face {f}: vertex {v} lies in a region apart from the face's other vertices");
    }
}

// ---------------------------------------------------------------------------------------
// The parameterization's and the extraction's fixtures.

/// The sample layouts of the page (www/layouts) and their meshes.
pub const SAMPLE_LAYOUTS: [(&str, &str); 8] = [
    ("mushroom-4", "mushroom.obj"),
    ("mushroom-grid", "mushroom.obj"),
    ("mushroom-t", "mushroom.obj"),
    ("eight-rims", "eight.obj"),
    ("fandisk-cube", "fandisk.obj"),
    ("fandisk-features", "fandisk.obj"),
    ("bunny-cube", "bunny_28k.obj"),
    ("bunny-ears", "bunny_28k.obj"),
];

/// Sample layout `name` (www/layouts/NAME.layout.json) placed on `mesh`.
pub fn sample_layout(mesh: &Mesh, name: &str) -> SurfaceLayout {
    let path = format!("{}/www/layouts/{name}.layout.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    build_layout(mesh, &parse_layout(&text).unwrap()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A layout file with nodes on `nodes` (vertex ids), edges between node indices, and
/// `chart` for every face.
pub fn layout_json(nodes: &[u32], edges: &[[u32; 2]], chart: &str) -> String {
    let nodes: Vec<Value> = nodes.iter().map(|&v| at(v)).collect();
    let edges: Vec<Value> = edges.iter().map(|e| edge(e[0], e[1])).collect();
    let mut d = doc(nodes, edges);
    d["defaults"] = json!({ "chart": chart });
    d.to_string()
}

/// Paper Fig. 8: a parallelepiped with unit edges, sampled n×n per face, with the cube's 12
/// edges as the layout and quad charts.
pub fn sheared_cube(n: u32) -> (Mesh, SurfaceLayout) {
    sheared_cube_with_chart(n, "quad")
}

pub fn sheared_cube_with_chart(n: u32, chart: &str) -> (Mesh, SurfaceLayout) {
    let a = [1.0, 0.0, 0.0];
    let b = [0.5, 0.75f64.sqrt(), 0.0];
    let c = [0.3, 0.2, (1.0f64 - 0.09 - 0.04).sqrt()];
    let (mesh, ids) = quadlay::mesh::primitives::parallelepiped(a, b, c, n);
    let corner = |i: u32, j: u32, k: u32| ids[&[i * n, j * n, k * n]];
    let nodes = [
        corner(0, 0, 0),
        corner(1, 0, 0),
        corner(1, 1, 0),
        corner(0, 1, 0),
        corner(0, 0, 1),
        corner(1, 0, 1),
        corner(1, 1, 1),
        corner(0, 1, 1),
    ];
    let edges = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]];
    let layout = build_layout(&mesh, &parse_layout(&layout_json(&nodes, &edges, chart)).unwrap()).unwrap();
    (mesh, layout)
}

/// Edges used by one quad only, chained into loops: the number of boundary loops. Also
/// checks that no edge has more than two quads (the mesh is a manifold, welded).
pub fn quad_boundary_loops(q: &QuadMesh) -> usize {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for f in &q.quads {
        for k in 0..4 {
            let (a, b) = (f[k], f[(k + 1) % 4]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    assert!(uses.values().all(|&u| u <= 2), "an edge has more than two quads");
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for (&(a, b), &u) in &uses {
        if u == 1 {
            next.entry(a).or_default().push(b);
            next.entry(b).or_default().push(a);
        }
    }
    let mut seen = HashSet::new();
    let mut loops = 0;
    for &start in next.keys() {
        if seen.insert(start) {
            loops += 1;
            let mut stack = vec![start];
            while let Some(v) = stack.pop() {
                for &w in &next[&v] {
                    if seen.insert(w) {
                        stack.push(w);
                    }
                }
            }
        }
    }
    loops
}
