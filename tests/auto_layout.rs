//! The automatic layout (issue 22) on the generated sphere and torus and on every shared mesh,
//! then remeshed at about 4000 quads. Prints the target table
//! (`cargo test --release --test auto_layout -- --nocapture`); asserts only what must hold: a
//! valid layout or a clear refusal (the reader places it, it reads back as written), a welded pure quad mesh
//! with the input's boundary loops, about the quads asked for. Folded quads are printed, not yet asserted: the
//! proposals still fold some on most meshes (see the table).

mod common;

use common::{load_mesh, load_working_mesh};
use quadlay::field::{propose_layout, LayoutOptions, ProposeError};
use quadlay::layout::{build_layout_on, parse_layout, write_layout, Location, Numbering};
use quadlay::mesh::geometry::triangle_areas;
use quadlay::mesh::topology::topology;
use quadlay::param::{ParamOptions, ParamSession};
use quadlay::quad::quality::measure;
use quadlay::quad::{extract, QuadOptions};
use quadlay::verdict::MISSED_DIAGONAL;
use std::time::Instant;

#[test]
fn shared_meshes_get_valid_layouts_and_quads() {
    let mut table = Vec::new();
    let mut failures = Vec::new();
    for name in ["nefertiti.obj", "eight.obj", "bunny_1k8.obj", "mushroom.obj", "fandisk.obj", "bunny_28k.obj", "elephant_44k.obj"] {
        let (mesh, file) = load_working_mesh(name);
        let t0 = Instant::now();
        let p = match propose_layout(&mesh, &LayoutOptions::default()) {
            Ok(p) => p,
            // A clear refusal is allowed (never an invalid layout); it is printed in the table.
            Err(e @ ProposeError::NoValidLayout(_)) => {
                table.push(format!("| {name} | no layout: {e} |"));
                continue;
            }
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let seconds = t0.elapsed().as_secs_f64();
        // The file reads back as written, and on the mesh it was made on (refined where
        // coarse) the file's numbering puts every node where the proposal put it.
        let numbering = Numbering { as_read: file, numbered: file };
        let text = write_layout(&p.layout.in_numbering(&mesh, numbering));
        let read = parse_layout(&text).unwrap();
        assert_eq!((read.edges.len(), read.mesh), (p.layout.edges.len(), Some(file)), "{name}");
        assert!(read.nodes.iter().all(|l| !matches!(l, Location::Vertex(v) if *v >= file.vertices as u64)), "{name}");
        let placed = build_layout_on(&mesh, &read, numbering).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(placed.node_vertex, p.surface.node_vertex, "{name}");
        let s = &p.surface;
        let layout_line = format!(
            "{} nodes, {} edges ({} tagged), {} faces, {} T-vertices, {} singularities",
            s.node_vertex.len(),
            p.layout.edges.len(),
            p.layout.edges.iter().filter(|e| e.align).count(),
            s.faces.len(),
            s.t_vertex_count(),
            p.field.singularities.len()
        );
        let area: f64 = triangle_areas(&mesh).iter().sum();
        let h = (area / 4000.0).sqrt();
        let mut param = ParamSession::new(&mesh, s, &ParamOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        for _ in 0..ParamOptions::default().iterations {
            param.step().unwrap();
        }
        let flipped = param.finish().unwrap().flipped;
        // No chart collapses (eight's and nefertiti's did, to side ratios 1e9 off their
        // curves', before chart optimization was bounded): its proportions stay near its face's.
        for (f, face) in s.faces.iter().enumerate() {
            let curves: [f64; 4] = std::array::from_fn(|k| face.side(k).iter().map(|d| s.curves[d.curve as usize].curve.length).sum());
            let deviation = param.charts()[f].shape_deviation(&curves);
            assert!(deviation < 100.0, "{name}: face {f}'s chart is {deviation:.3e} times off its curves' proportions");
        }
        let (quads, _) = extract(s, &param, &QuadOptions::with_edge_length(h)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let q = measure(&mesh, &quads);
        table.push(format!(
            "| {name} | {} | {:.2} % | {:.2}° | {} | {} | {flipped} | {:.3} s | {layout_line} |",
            q.faces,
            100.0 * q.hausdorff,
            q.angle_deviation_mean_deg,
            q.irregular_vertices,
            q.flipped_quads,
            seconds
        ));
        println!("{}", table.last().unwrap());
        // Welded pure quads with the input's boundary loops.
        assert!(quads.quads.iter().all(|f| f.iter().all(|&v| (v as usize) < quads.positions.len())), "{name}");
        assert_eq!(common::quad_boundary_loops(&quads), topology(&mesh).boundary_loops.len(), "{name}: boundary loops");
        // About the quads asked for (the issue's ±15 %): never too few, the counts can always
        // go finer; too many only where faces average fewer than 5 × 5 quads, where each piece
        // between T-vertices taking one segment at least decides the count.
        let (got, asked) = (q.faces as f64, area / (h * h));
        let coarse = s.faces.len() as f64 > asked / 25.0;
        if got < 0.85 * asked || (got > 1.15 * asked && !coarse) {
            failures.push(format!("{name}: {got} quads where {asked:.0} were asked"));
        }
        // Near the surface: within the verdict's bar for a miss (fandisk's first proposal
        // missed by 8.2 %; the refinement by a short solve splits its distorted faces). Eight,
        // whose 315 vertices are few for vertex paths, missed by 5.3 % with streamlines of the
        // field; its iso-lines' layout misses by 1.3 %.
        if q.hausdorff > MISSED_DIAGONAL {
            failures.push(format!("{name}: the quads miss the surface by {:.1} % of the diagonal", 100.0 * q.hausdorff));
        }
    }
    println!("| mesh | quads | Hausdorff | mean angle deviation | irregular vertices | folded | flipped triangles | layout time | layout |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for row in table {
        println!("{row}");
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The sheared cube's proposal is its 12 edges, tagged: its 8 corners are feature corners and
/// its 12 sharp edges feature lines, and nothing inside a side needs a trace (the field is
/// constant on each flat side, with no singularity).
#[test]
fn the_sheared_cube_gets_its_twelve_edges_tagged() {
    let (mesh, reference) = common::sheared_cube(8);
    let p = propose_layout(&mesh, &LayoutOptions::default()).unwrap();
    assert_eq!(p.surface.faces.len(), 6);
    assert_eq!(p.layout.edges.len(), 12, "{:?}", p.layout.edges);
    assert!(p.layout.edges.iter().all(|e| e.align));
    let mut nodes = p.surface.node_vertex.clone();
    let mut corners = reference.node_vertex.clone();
    nodes.sort_unstable();
    corners.sort_unstable();
    assert_eq!(nodes, corners);
    assert_eq!(p.surface.t_vertex_count(), 0);
}

/// Every sharp edge of fandisk lies on a tagged layout curve: its feature lines are edge loops.
#[test]
fn fandisk_sharp_edges_are_tagged_curves() {
    use quadlay::layout::curve::CurvePoint;
    let mesh = load_mesh("fandisk.obj");
    let p = propose_layout(&mesh, &LayoutOptions::default()).unwrap();
    let mut on_tagged = vec![false; mesh.n_edges()];
    for c in p.surface.curves.iter().filter(|c| c.align) {
        for w in c.curve.points.windows(2) {
            if let [CurvePoint::Vertex(a), CurvePoint::Vertex(b)] = w {
                if let Some(h) = mesh.find_halfedge(*a, *b) {
                    on_tagged[mesh.edge(h) as usize] = true;
                }
            }
        }
    }
    let sharp: Vec<usize> = (0..mesh.n_edges()).filter(|&e| p.field.features.sharp[e]).collect();
    assert!(sharp.len() > 100, "fandisk has {} sharp edges", sharp.len());
    let missed: Vec<usize> = sharp.iter().copied().filter(|&e| !on_tagged[e]).collect();
    println!("fandisk: {} sharp edges, {} not on a tagged curve", sharp.len(), missed.len());
    for &e in &missed {
        let (a, b) = (mesh.from_vertex(2 * e as u32), mesh.to_vertex(2 * e as u32));
        let in_line = p.field.features.lines.iter().any(|l| l.windows(2).any(|w| (w[0] == a && w[1] == b) || (w[0] == b && w[1] == a)));
        let node = |v: u32| p.surface.node_vertex.contains(&v);
        println!("  edge {e}: {a}-{b} in a line {in_line}, nodes {} {}, on any curve {}", node(a), node(b),
            p.surface.curves.iter().any(|c| c.curve.points.windows(2).any(|w| matches!(w, [CurvePoint::Vertex(x), CurvePoint::Vertex(y)] if (*x == a && *y == b) || (*x == b && *y == a)))));
    }
    assert!(missed.is_empty(), "sharp edges not on tagged curves: {missed:?}");
    // Grid lines go on across the sharp edges: at a node inside a feature line (two tagged
    // curves) traces from both sides meet it in a crossing rather than each in a T-junction
    // of its own (stop 56: 1 crossing, 43 T-junctions; now 64 and 13).
    let mut tagged = vec![0; p.layout.nodes.len()];
    let mut untagged = vec![0; p.layout.nodes.len()];
    for e in &p.layout.edges {
        for &n in &e.nodes {
            if e.align { tagged[n as usize] += 1 } else { untagged[n as usize] += 1 }
        }
    }
    let on_line = |k: usize| (0..tagged.len()).filter(|&n| tagged[n] == 2 && untagged[n] == k).count();
    let (crossings, t_junctions) = (on_line(2), on_line(1));
    println!("fandisk: {crossings} crossings of feature lines, {t_junctions} T-junctions on them");
    assert!(crossings > 2 * t_junctions, "{crossings} crossings, {t_junctions} T-junctions");
}

/// Coarse tessellations of smooth surfaces have edges bent beyond the feature angle (the
/// 315-vertex eight, the low-resolution bunny, nefertiti), but the surface turns as much
/// beside them: none is a feature line, so no layout curve is forced along their zigzags.
#[test]
fn coarse_smooth_meshes_have_no_feature_lines() {
    use quadlay::field::{find_features, DEFAULT_FEATURE_ANGLE};
    use quadlay::geom::dot;
    use quadlay::mesh::geometry::face_normals;
    for name in ["eight.obj", "bunny_1k8.obj", "nefertiti.obj"] {
        let mesh = load_mesh(name);
        let normals = face_normals(&mesh);
        let bent = (0..mesh.n_edges() as u32)
            .filter(|&e| !mesh.is_boundary_edge(e))
            .filter(|&e| {
                let (f, g) = (normals[mesh.face(2 * e) as usize], normals[mesh.face(2 * e + 1) as usize]);
                dot(f, g).clamp(-1.0, 1.0).acos() > DEFAULT_FEATURE_ANGLE.to_radians()
            })
            .count();
        let features = find_features(&mesh, DEFAULT_FEATURE_ANGLE);
        println!("{name}: {bent} edges bent beyond {DEFAULT_FEATURE_ANGLE}°, {} feature lines", features.lines.len());
        assert!(bent >= 30, "{name}: only {bent} bent edges, the test shows nothing");
        assert!(features.lines.is_empty(), "{name}: feature lines {:?}", features.lines);
    }
}

/// A washer (a rectangle revolved: two flat rings and two cylinders) has four circular sharp
/// rims without corners: nothing in the field starts a trace from them, and every face between
/// them is a ring. Each rim gets four nodes and traces across both its sides, so the faces
/// are quarters of the rings and cylinders, and the quads of these developable pieces are
/// near square.
#[test]
fn a_washer_is_cut_across_its_rims() {
    use quadlay::layout::curve::CurvePoint;
    let mesh = common::washer(96, 4);
    let p = propose_layout(&mesh, &LayoutOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let s = &p.surface;
    let radius = |v: u32| mesh.position(v)[0].hypot(mesh.position(v)[1]);
    let rims = [[2.0, 0.0], [2.0, 0.5], [1.0, 0.5], [1.0, 0.0]];
    for [r, z] in rims {
        let on_rim = |v: &&u32| (radius(**v) - r).abs() < 1e-9 && (mesh.position(**v)[2] - z).abs() < 1e-9;
        let nodes = s.node_vertex.iter().filter(on_rim).count();
        assert!(nodes >= 4, "the rim at r = {r}, z = {z} has {nodes} nodes");
    }
    // Every rim edge is on a tagged curve.
    let tagged: std::collections::HashSet<(u32, u32)> = s
        .curves
        .iter()
        .filter(|c| c.align)
        .flat_map(|c| c.curve.points.windows(2).filter_map(|w| if let [CurvePoint::Vertex(a), CurvePoint::Vertex(b)] = w { Some((*a.min(b), *a.max(b))) } else { None }).collect::<Vec<_>>())
        .collect();
    let sharp = (0..mesh.n_edges()).filter(|&e| p.field.features.sharp[e]).count();
    assert_eq!(sharp, 4 * 96);
    assert_eq!(tagged.len(), sharp, "rim edges on tagged curves");
    let area: f64 = triangle_areas(&mesh).iter().sum();
    let h = (area / 2000.0).sqrt();
    let mut param = ParamSession::new(&mesh, s, &ParamOptions::default()).unwrap();
    for _ in 0..ParamOptions::default().iterations {
        param.step().unwrap();
    }
    param.finish().unwrap();
    let (quads, _) = extract(s, &param, &QuadOptions::with_edge_length(h)).unwrap();
    let q = measure(&mesh, &quads);
    println!(
        "washer: {} faces, {} quads, Hausdorff {:.3} %, mean angle deviation {:.2}°, {} irregular, {} folded",
        s.faces.len(),
        q.faces,
        100.0 * q.hausdorff,
        q.angle_deviation_mean_deg,
        q.irregular_vertices,
        q.flipped_quads
    );
    assert_eq!(q.flipped_quads, 0);
    assert!(q.angle_deviation_mean_deg < 3.0, "{:.2}°", q.angle_deviation_mean_deg);
}

/// A torus has a field without singularities, and its proposal has none either: every node
/// is where four curves meet or a T-junction (three, one of them straight through).
#[test]
fn a_torus_gets_a_layout_without_singularities() {
    let mesh = common::torus(48, 16);
    let p = propose_layout(&mesh, &LayoutOptions::default()).unwrap();
    assert!(p.field.singularities.is_empty(), "{:?}", p.field.singularities);
    let mut degree = vec![0; p.surface.node_vertex.len()];
    for e in &p.layout.edges {
        degree[e.nodes[0] as usize] += 1;
        degree[e.nodes[1] as usize] += 1;
    }
    // A valence-3 or -5 layout node would be a singularity of the layout's quads: T-junctions
    // (degree 3) are allowed only as T-vertices, which the faces list.
    let t_nodes: std::collections::HashSet<u32> = p.surface.faces.iter().flat_map(|f| f.t_vertices()).collect();
    for (n, &d) in degree.iter().enumerate() {
        assert!(d == 4 || (d == 3 && t_nodes.contains(&(n as u32))), "node {n} has {d} curves");
    }
}

/// `--patches` below what the singularities make cancels pairs farther apart: bunny_1k8's
/// faces become fewer, at most half again the 30 asked for (each tracing keeps its layout
/// nearest the count asked, and the judge keeps the tracing whose quads are best: 42 faces,
/// where the one of 31 misses the surface by 22 % of the diagonal), and the layout stays
/// valid.
#[test]
fn fewer_patches_asked_give_fewer_faces() {
    let mesh = load_mesh("bunny_1k8.obj");
    let default = propose_layout(&mesh, &LayoutOptions::default()).unwrap().surface.faces.len();
    let mut options = LayoutOptions::default();
    options.patches = Some(30);
    let p = propose_layout(&mesh, &options).unwrap();
    let faces = p.surface.faces.len();
    assert!(default > 45 && faces < default && (20..=45).contains(&faces), "{default} faces by default, {faces} for --patches 30");
    assert_eq!(parse_layout(&write_layout(&p.layout)).unwrap(), p.layout);
    assert!(ParamSession::new(&mesh, &p.surface, &ParamOptions::default()).is_ok());
}

/// Two cubes touching along a side, each with vertices of its own there (as CAD exports have
/// seams): the mesh is coarse and refined, and the written layout reads back on it. The
/// midpoints of the seam's twin edges once shared points, which name vertices the refinement
/// adds in a layout file: `remesh` snapped a tagged curve's waypoint onto the other cube.
#[test]
fn a_layout_on_cubes_touching_along_a_seam_reads_back() {
    let (one, _) = common::cube(2);
    let mut positions = one.positions().to_vec();
    positions.extend(one.positions().iter().map(|p| [p[0] + 1.0, p[1], p[2]]));
    let n = one.n_vertices() as u32;
    let triangles = one.triangles().iter().copied().chain(one.triangles().iter().map(|t| t.map(|v| v + n))).collect();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("auto_layout_seam");
    std::fs::create_dir_all(&dir).unwrap();
    let path = |f: &str| dir.join(f).to_string_lossy().into_owned();
    std::fs::write(path("cubes.obj"), common::obj_text(&common::mesh_of(positions, triangles))).unwrap();
    let (code, _, err) = common::run_cli(&["layout", &path("cubes.obj"), "-o", &path("cubes.json")]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = common::run_cli(&["remesh", &path("cubes.obj"), "--layout", &path("cubes.json"), "--quads", "500", "-o", &path("quads.obj")]);
    assert_eq!(code, 0, "{err}");
}
