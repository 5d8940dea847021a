//! The real meshes in `../shared/meshes` read with exactly the topology their SOURCES.md
//! gives (vertices, triangles, genus, boundary loops, components), through the library and
//! through `quadlay check`; every writer (PLY, OBJ, GLB) reads back to the same mesh; glTF
//! node transforms are applied (mirroring ones flip the winding, so orientation stays
//! consistent) and primitives that share a seam are welded into one surface.

mod common;

use base64::Engine;
use common::{load_loaded as load, run_cli, shared_mesh};
use quadlay::io::{read_mesh, write_glb, write_obj, write_ply, Polygons};
use quadlay::summary::MeshSummary;
use serde_json::json;
use std::collections::BTreeMap;

/// Name, vertices, triangles, genus, boundary loops, components: SOURCES.md's table.
const MESHES: [(&str, usize, usize, i64, usize, usize); 7] = [
    ("nefertiti.obj", 299, 562, 0, 1, 1),
    ("eight.obj", 315, 634, 2, 0, 1),
    ("bunny_1k8.obj", 1839, 3674, 0, 0, 1),
    ("mushroom.obj", 2337, 4608, 0, 1, 1),
    ("fandisk.obj", 6475, 12946, 0, 0, 1),
    ("bunny_28k.obj", 28088, 56172, 0, 0, 1),
    ("elephant_44k.obj", 44460, 88928, 3, 0, 1),
];

/// (vertices, triangles, genus, boundary loops, components) of a summary.
fn counts(s: &MeshSummary) -> (usize, usize, i64, usize, usize) {
    (s.vertices, s.triangles, s.genus, s.boundary_loops, s.components.len())
}

#[test]
fn table_lists_every_shared_mesh() {
    let mut on_disk: Vec<String> = std::fs::read_dir(shared_mesh(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".obj"))
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = MESHES.iter().map(|m| m.0.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
}

#[test]
fn library_reads_the_topology_of_sources_md() {
    for (name, v, f, genus, loops, comps) in MESHES {
        let loaded = load(name);
        let s = MeshSummary::of(&loaded);
        assert_eq!(counts(&s), (v, f, genus, loops, comps), "{name}");
        assert!(s.repairs.is_empty(), "{name}: {:?}", s.repairs);
    }
}

#[test]
fn cli_check_prints_the_topology_of_sources_md() {
    for (name, v, f, genus, loops, comps) in MESHES {
        let path = shared_mesh(name);
        let (code, out, err) = run_cli(&["check", path.to_str().unwrap()]);
        assert_eq!((code, err.as_str()), (0, ""), "{name}");
        let fields: BTreeMap<&str, &str> = out
            .lines()
            .filter_map(|l| l.split_once(':'))
            .map(|(k, v)| (k.trim(), v.trim()))
            .collect();
        let expect = [
            ("format", "OBJ".to_string()),
            ("genus", genus.to_string()),
            ("boundary loops", loops.to_string()),
            ("components", comps.to_string()),
        ];
        for (key, value) in expect {
            assert_eq!(fields.get(key).copied(), Some(value.as_str()), "{name}: {key} in\n{out}");
        }
        // A coarse mesh is refined (mesh/refine.rs), the file's counts named with it.
        if f < quadlay::mesh::refine::MIN_TRIANGLES {
            assert!(fields["repairs"].contains(&format!("from {v} vertices and {f} triangles")), "{name}\n{out}");
            assert!(fields["triangles"].parse::<usize>().unwrap() >= quadlay::mesh::refine::MIN_TRIANGLES, "{name}\n{out}");
        } else {
            assert_eq!((fields["vertices"], fields["triangles"], fields["repairs"]), (v.to_string().as_str(), f.to_string().as_str(), "none"), "{name}");
        }
        assert!(fields["mesh"].ends_with(name), "{name}\n{out}");
    }
}

#[test]
fn writers_read_back_to_the_same_mesh() {
    for name in ["nefertiti.obj", "eight.obj", "bunny_1k8.obj", "mushroom.obj", "fandisk.obj"] {
        let original = load(name);
        let m = &original.mesh;
        let faces: Vec<u32> = m.triangles().iter().flatten().copied().collect();
        let poly = Polygons { positions: m.positions(), faces: &faces, arity: 3 };
        let expected = counts(&MeshSummary::of(&original));
        let (lo, hi) = quadlay::mesh::geometry::bounding_box(m);
        let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();

        // GLB stores f32 positions; PLY (double) and OBJ (shortest round-trip text) are exact.
        for (bytes, file, tolerance) in [
            (write_ply(poly), "round.ply", 0.0),
            (write_obj(poly, None), "round.obj", 0.0),
            (write_glb(poly), "round.glb", 1e-6 * diagonal),
        ] {
            let back = read_mesh(&bytes, file).unwrap_or_else(|e| panic!("{name} as {file}: {e}"));
            let s = MeshSummary::of(&back);
            assert_eq!(counts(&s), expected, "{name} as {file}");
            assert!(s.repairs.is_empty(), "{name} as {file}: {:?}", s.repairs);
            assert_eq!(back.mesh.triangles(), m.triangles(), "{name} as {file}");
            for (v, (a, b)) in m.positions().iter().zip(back.mesh.positions()).enumerate() {
                let d = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
                assert!(d <= tolerance, "{name} as {file}: vertex {v} moved by {d}");
            }
        }
    }
}

// ---- glTF: transforms, mirroring, seams ----

type Primitive = (Vec<[f32; 3]>, Vec<u32>);

/// A `.gltf` text with all data in one base64 `data:` buffer. `meshes[i]` lists the
/// primitives of mesh `i`; `nodes` and `scene` are the glTF arrays as given.
fn gltf_text(meshes: &[Vec<Primitive>], nodes: serde_json::Value, scene: &[usize]) -> Vec<u8> {
    let (mut bin, mut views, mut accessors, mut json_meshes) = (Vec::new(), vec![], vec![], vec![]);
    for prims in meshes {
        let mut json_prims = vec![];
        for (positions, indices) in prims {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            let start = bin.len();
            for p in positions {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                    bin.extend_from_slice(&p[k].to_le_bytes());
                }
            }
            views.push(json!({ "buffer": 0, "byteOffset": start, "byteLength": bin.len() - start }));
            accessors.push(json!({ "bufferView": views.len() - 1, "componentType": 5126,
                "count": positions.len(), "type": "VEC3", "min": lo, "max": hi }));
            let start = bin.len();
            for i in indices {
                bin.extend_from_slice(&i.to_le_bytes());
            }
            views.push(json!({ "buffer": 0, "byteOffset": start, "byteLength": bin.len() - start }));
            accessors.push(json!({ "bufferView": views.len() - 1, "componentType": 5125,
                "count": indices.len(), "type": "SCALAR" }));
            json_prims.push(json!({ "attributes": { "POSITION": accessors.len() - 2 },
                "indices": accessors.len() - 1 }));
        }
        json_meshes.push(json!({ "primitives": json_prims }));
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    );
    let doc = json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [ { "nodes": scene } ],
        "nodes": nodes,
        "meshes": json_meshes,
        "buffers": [ { "byteLength": bin.len(), "uri": uri } ],
        "bufferViews": views,
        "accessors": accessors,
    });
    serde_json::to_vec_pretty(&doc).unwrap()
}

/// The unit tetrahedron, its triangles facing outwards (positive volume).
fn tetrahedron() -> Primitive {
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    (p, vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3])
}

/// Six times the signed volume enclosed by the triangles `keep` selects.
fn signed_volume6(m: &quadlay::mesh::Mesh, keep: impl Fn([f64; 3]) -> bool) -> f64 {
    let p = m.positions();
    m.triangles()
        .iter()
        .map(|t| t.map(|v| p[v as usize]))
        .filter(|t| keep(t[0]))
        .map(|[a, b, c]| {
            let bc = [b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]];
            a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]
        })
        .sum()
}

#[test]
fn gltf_node_transforms_are_applied_and_mirrors_keep_orientation() {
    let nodes = json!([
        { "mesh": 0, "translation": [10.0, 20.0, 30.0], "scale": [2.0, 3.0, 4.0] },
        { "mesh": 0, "translation": [-5.0, 0.0, 0.0], "scale": [-1.0, 1.0, 1.0] },
        { "translation": [0.0, 0.0, 100.0], "children": [3] },
        { "mesh": 0, "scale": [5.0, 5.0, 5.0] }
    ]);
    let text = gltf_text(&[vec![tetrahedron()]], nodes, &[0, 1, 2]);
    let loaded = read_mesh(&text, "transforms.gltf").unwrap();
    let s = MeshSummary::of(&loaded);
    assert_eq!(counts(&s), (12, 12, 0, 0, 3));

    let tet = tetrahedron().0.into_iter().map(|p| p.map(f64::from));
    let mut expected: Vec<[f64; 3]> = tet
        .flat_map(|[x, y, z]| {
            [[10.0 + 2.0 * x, 20.0 + 3.0 * y, 30.0 + 4.0 * z], [-5.0 - x, y, z], [5.0 * x, 5.0 * y, 100.0 + 5.0 * z]]
        })
        .collect();
    let mut got = loaded.mesh.positions().to_vec();
    expected.sort_by(|a, b| a.partial_cmp(b).unwrap());
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(got, expected);

    // Every copy still faces outwards, the mirrored one included.
    let m = &loaded.mesh;
    assert_eq!(signed_volume6(m, |p| p[0] >= 10.0), 2.0 * 3.0 * 4.0);
    assert_eq!(signed_volume6(m, |p| p[0] <= -5.0), 1.0);
    assert_eq!(signed_volume6(m, |p| p[2] >= 100.0), 125.0);
}

#[test]
fn gltf_mirrored_half_welds_into_one_consistently_oriented_surface() {
    // A unit square on x >= 0 facing +z, and its mirror image across x = 0.
    let half = (
        vec![[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        vec![0, 2, 3, 0, 3, 1],
    );
    let nodes = json!([ { "mesh": 0 }, { "mesh": 0, "scale": [-1.0, 1.0, 1.0] } ]);
    let text = gltf_text(&[vec![half]], nodes, &[0, 1]);
    let loaded = read_mesh(&text, "mirror.gltf").unwrap();
    let s = MeshSummary::of(&loaded);
    assert_eq!(counts(&s), (6, 4, 0, 1, 1));
    assert_eq!(s.repairs.welded_vertices, 2);
    let p = loaded.mesh.positions();
    for t in loaded.mesh.triangles() {
        let [a, b, c] = t.map(|v| p[v as usize]);
        let normal_z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(normal_z > 0.0, "triangle {t:?} faces -z");
    }
}

#[test]
fn gltf_primitives_sharing_a_seam_are_welded() {
    let quad = |x: f32| {
        let p = vec![[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x + 1.0, 1.0, 0.0], [x, 1.0, 0.0]];
        (p, vec![0, 1, 2, 0, 2, 3])
    };
    let text = gltf_text(&[vec![quad(0.0), quad(1.0)]], json!([{ "mesh": 0 }]), &[0]);
    let loaded = read_mesh(&text, "seam.gltf").unwrap();
    let s = MeshSummary::of(&loaded);
    assert_eq!(counts(&s), (6, 4, 0, 1, 1));
    assert_eq!(s.repairs.welded_vertices, 2);
    assert_eq!(s.repairs.removed_zero_area_faces, 0);
}
