//! Bad input gets the right error and never a panic or a hang.
//!
//! Every file in `tests/broken/` makes `quadlay check` exit with status 2, print nothing on
//! standard output and exactly one `error:` line on standard error that names the file and
//! says what is wrong (the line, face, vertex or element where there is one); the table
//! below pins the message of each file, and every file there must be in the table. Then
//! every reader is run over every truncation and a few hundred deterministic mutations of
//! small valid files of each format: each returns Ok or Err, none panics.

mod common;

use common::run_cli;
use quadlay::io::{read_mesh, write_glb, write_ply, Polygons};
use std::path::{Path, PathBuf};

/// File in `tests/broken/` → a piece of the error message it must give.
const EXPECTED: &[(&str, &str)] = &[
    ("garbage_binary.obj", "OBJ line 1: not a text line"),
    ("glb_length_below_header.glb", "GLB declares 5 bytes but the file has 528"),
    ("glb_truncated.glb", "GLB declares 560 bytes but the file has 280"),
    ("gltf_accessor_outside_buffer.gltf", "mesh 0 primitive 0: accessor 0 reaches outside its buffer"),
    ("gltf_empty_accessor.gltf", "mesh 0 primitive 0: accessor 0 has no elements"),
    ("gltf_float_indices.gltf", "index accessor 1 is not SCALAR of unsigned integers"),
    ("gltf_inf_position.gltf", "mesh 0 primitive 0: vertex 2 is not finite"),
    ("gltf_invalid_json.gltf", "EOF while parsing a value at line 69"),
    ("gltf_missing_external_buffer.gltf", "buffer 0 is the external file 'missing.bin'"),
    ("gltf_position_accessor_missing.gltf", "mesh 0 primitive 0: POSITION accessor 5 does not exist"),
    ("gltf_position_not_float.gltf", "POSITION accessor 0 is not VEC3 of FLOAT"),
    ("gltf_stride_too_small.gltf", "accessor 0 has a stride of 4 bytes, less than its 12-byte elements"),
    ("obj_bowtie_vertex.obj", "non-manifold vertex 0: its faces form more than one fan"),
    ("obj_empty.obj", "the mesh has no vertices"),
    ("obj_face_two_vertices.obj", "OBJ line 6: a face needs 3 or more vertices, found 2"),
    ("obj_garbled_number.obj", "OBJ line 3: '1.0.0' is not a number"),
    (
        "obj_inconsistent_orientation.obj",
        "inconsistent orientation: triangles 0 and 1 both run from vertex 0 to vertex 1 (line 6)",
    ),
    ("obj_index_out_of_range.obj", "refers to vertex 8, but there are only 4 vertices (line 6)"),
    ("obj_index_zero.obj", "OBJ line 6: vertex index 0 (OBJ counts from 1)"),
    ("obj_inf_coordinate.obj", "OBJ line 4: coordinate 'inf' is not a finite number"),
    ("obj_nan_coordinate.obj", "OBJ line 3: coordinate 'nan' is not a finite number"),
    ("obj_negative_index_out_of_range.obj", "OBJ line 6: vertex index -9 is out of range"),
    ("obj_no_faces.obj", "the mesh has no faces"),
    (
        "obj_non_manifold_edge.obj",
        "non-manifold edge between vertices 0 and 1: shared by triangles 0, 1, 2 (line 6)",
    ),
    ("obj_repeated_vertex.obj", "triangle 2 uses vertex 1 more than once (line 7)"),
    ("ply_ascii_ends_early.ply", "PLY: the file ends inside face 0"),
    ("ply_binary_truncated.ply", "PLY: the file ends inside face 2"),
    ("ply_face_index_out_of_range.ply", "refers to vertex 7, but there are only 4 vertices (face 1)"),
    ("ply_header_without_end.ply", "the header has no 'end_header' line"),
    ("ply_huge_vertex_count.ply", "declares 4000000000 vertex elements, more than the file can hold"),
    ("ply_inf_coordinate.ply", "vertex 2 has a coordinate that is not a finite number"),
    ("ply_missing_end_header.ply", "PLY line 9: unknown header keyword '0'"),
    ("ply_no_face_list.ply", "the face element has no 'vertex_indices' list"),
    ("points.xyz", "cannot tell the format"),
    ("stl_ascii_ends_inside_facet.stl", "STL: the file ends inside the facet of line 9"),
    ("stl_ascii_facet_two_vertices.stl", "STL line 14: facet has 2 vertices; 3 needed"),
    ("stl_ascii_inf_coordinate.stl", "STL line 6: coordinate '-inf' is not a finite number"),
    ("stl_binary_nan.stl", "STL: facet 1 has a coordinate that is not a finite number"),
    ("stl_binary_truncated.stl", "declares 2 triangles (184 bytes) but the file has 154 bytes"),
    ("text_not_obj.obj", "OBJ: not an OBJ file: no line begins with an OBJ statement (v, f, ...); line 1 begins 'x,y,z'"),
];

fn broken_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/broken")
}

#[test]
fn every_broken_file_gives_its_one_line_error() {
    for (name, expected) in EXPECTED {
        let path = broken_dir().join(name);
        let (code, out, err) = run_cli(&["check", path.to_str().unwrap()]);
        assert_eq!(code, 2, "{name}: exit status; stderr: {err}");
        assert_eq!(out, "", "{name}: standard output");
        let line = err.strip_suffix('\n').unwrap_or_else(|| panic!("{name}: stderr {err:?}"));
        assert!(!line.contains('\n'), "{name}: more than one line:\n{err}");
        assert!(line.starts_with("error: "), "{name}: {line}");
        assert!(line.contains(name), "{name}: the file is not named: {line}");
        assert!(line.contains(expected), "{name}: expected '{expected}' in\n{line}");
    }
}

#[test]
fn every_file_in_the_broken_directory_is_in_the_table() {
    let mut on_disk: Vec<String> = std::fs::read_dir(broken_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let listed: Vec<String> = EXPECTED.iter().map(|e| e.0.to_string()).collect();
    assert_eq!(on_disk, listed, "tests/broken/ and the table must list the same files, sorted");
}

// ---- readers over truncations and mutations ----

/// Deterministic pseudo-random numbers (xorshift64).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

/// One to four random edits: overwrite, flip a bit, change a digit, delete, insert, repeat.
fn mutate(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    const SPECIAL: &[u8] = b"\0\xff\n -.09e/";
    let mut b = bytes.to_vec();
    for _ in 0..1 + rng.below(4) {
        if b.is_empty() {
            b.push(b'0');
        }
        let i = rng.below(b.len());
        match rng.below(6) {
            0 => b[i] = rng.below(256) as u8,
            1 => b[i] ^= 1 << rng.below(8),
            2 => b[i] = SPECIAL[rng.below(SPECIAL.len())],
            3 => {
                // Numbers in headers, indices, JSON: a digit becomes another digit.
                if let Some(d) = (i..b.len()).find(|&k| b[k].is_ascii_digit()) {
                    b[d] = b'0' + rng.below(10) as u8;
                }
            }
            4 => {
                b.remove(i);
            }
            _ => {
                let len = rng.below(16).min(b.len() - i);
                let chunk = b[i..i + len].to_vec();
                b.splice(i..i, chunk);
            }
        }
    }
    b
}

fn tetrahedron() -> (Vec<[f64; 3]>, Vec<u32>) {
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    (p, vec![0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3])
}

fn binary_stl(positions: &[[f64; 3]], faces: &[u32]) -> Vec<u8> {
    let mut b = vec![b'x'; 80];
    b.extend_from_slice(&(faces.len() as u32 / 3).to_le_bytes());
    for t in faces.chunks(3) {
        b.extend_from_slice(&[0; 12]);
        for &v in t {
            for c in positions[v as usize] {
                b.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
    }
    b
}

/// Small valid files of every format, with a name that selects the reader.
fn samples() -> Vec<(&'static str, Vec<u8>)> {
    let (p, f) = tetrahedron();
    let tet = Polygons { positions: &p, faces: &f, arity: 3 };
    let obj = "# cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvt 0 0\n\
               f 1/1 4/1 3/1 2/1\nf 5 6 7 8\nf 1//1 2//1 6//1 5//1\nf 2 3 7 6\nf -5 -1 -2 -6\nf 4 1 5 8\n";
    let ply = "ply\nformat ascii 1.0\ncomment tetrahedron\nelement vertex 4\nproperty float x\n\
               property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
    let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
               endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\n\
               vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    vec![
        ("a.obj", obj.as_bytes().to_vec()),
        ("a.ply", ply.as_bytes().to_vec()),
        ("b.ply", write_ply(tet)),
        ("a.stl", stl.as_bytes().to_vec()),
        ("b.stl", binary_stl(&p, &f)),
        ("a.glb", write_glb(tet)),
    ]
}

/// Reads `bytes`; a panic becomes a failure that names the input.
fn read_without_panic(bytes: &[u8], name: &str, case: &str) {
    let r = std::panic::catch_unwind(|| read_mesh(bytes, name).map(|_| ()));
    assert!(r.is_ok(), "{name}, {case}: the reader panicked on {bytes:?}");
}

#[test]
fn readers_survive_truncation_and_mutation() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for (name, bytes) in samples() {
        if let Err(e) = read_mesh(&bytes, name) {
            panic!("{name}: the valid sample does not read: {e}");
        }
        for len in 0..bytes.len() {
            read_without_panic(&bytes[..len], name, &format!("truncated to {len} bytes"));
        }
        for k in 0..250 {
            read_without_panic(&mutate(&bytes, &mut rng), name, &format!("mutation {k}"));
        }
    }
}

#[test]
fn ply_element_without_properties_is_not_looped_over() {
    // Such an element holds no bytes, so nothing bounds its count by the file's size.
    let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
        property float y\nproperty float z\nelement junk 18446744073709551615\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n"
        .to_vec();
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        b.extend_from_slice(&c.to_le_bytes());
    }
    b.push(3);
    for i in [0i32, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let m = read_mesh(&b, "junk.ply").unwrap().mesh;
    assert_eq!((m.n_vertices(), m.n_faces()), (3, 1));
}
