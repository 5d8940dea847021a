//! The repairs a user asks for (cli.md, "Repairs the user asks for"): keep only the largest
//! connected component, close small holes. Raw scans come with specks of loose triangles and
//! holes where the scanner saw nothing; every component and every boundary loop would need
//! layout nodes of its own.
//!
//! Vertex numbering is kept: a dropped component's vertices stay in the numbering, unused, and
//! the vertices a filled hole adds come after the file's, so layouts that name vertices by
//! index keep their meaning.

use super::topology::topology;
use super::{build_mesh, Mesh, MeshError, Repairs, TriangleSoup};

/// What to repair. The default repairs nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RepairOptions {
    /// Keep only the connected component with the most triangles (default: off).
    #[serde(default)]
    pub keep_largest: bool,
    /// Close every boundary loop of at most this many edges (default: none).
    #[serde(default)]
    pub fill_holes: Option<usize>,
}

impl RepairOptions {
    pub fn is_none(&self) -> bool {
        *self == RepairOptions::default()
    }
}

/// Applies `options` to `mesh` and adds what was done to `repairs`.
///
/// Holes are closed after the other components are dropped, so only the kept component's
/// loops count. A loop is closed by rings of new vertices shrinking towards its centroid,
/// then relaxed to a membrane spanning the loop (each new vertex at the mean of its
/// neighbours): smooth inside, no folds for a loop that is roughly planar as seen from its
/// centroid.
///
/// # Errors
/// [`MeshError`] when the repaired triangles no longer make a valid mesh (a loop so twisted
/// that its filling crosses itself into a zero-area or non-manifold face).
pub fn repair_mesh(mesh: &Mesh, repairs: &Repairs, options: &RepairOptions) -> Result<(Mesh, Repairs), MeshError> {
    let mut repairs = repairs.clone();
    let mut positions = mesh.positions().to_vec();
    let mut triangles = mesh.triangles().to_vec();
    let topo = topology(mesh);
    if options.keep_largest && topo.components.len() > 1 {
        let largest = (0..topo.components.len()).max_by_key(|&c| (topo.components[c].faces, usize::MAX - c));
        let largest = largest.unwrap_or(0) as u32;
        let before = triangles.len();
        triangles.retain(|t| topo.vertex_component[t[0] as usize] == largest);
        repairs.removed_components = topo.components.len() - 1;
        repairs.removed_component_faces = before - triangles.len();
    }
    if let Some(max_edges) = options.fill_holes {
        let kept = if repairs.removed_components > 0 { Some(rebuild(&positions, &triangles)?) } else { None };
        let current = kept.as_ref().unwrap_or(mesh);
        let loops = topology(current).boundary_loops;
        for lp in loops.iter().filter(|lp| lp.len() <= max_edges) {
            let ring: Vec<u32> = lp.iter().map(|&h| current.from_vertex(h)).collect();
            let added = fill_loop(&ring, &mut positions, &mut triangles);
            repairs.filled_holes += 1;
            repairs.fill_vertices += added;
        }
    }
    let built = rebuild(&positions, &triangles)?;
    Ok((built, repairs))
}

fn rebuild(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Mesh, MeshError> {
    let soup = TriangleSoup { positions: positions.to_vec(), triangles: triangles.to_vec(), ..Default::default() };
    Ok(build_mesh(soup)?.mesh)
}

/// Closes the loop `ring` (its vertices in the order of its boundary halfedges, so a new
/// triangle holding `ring[i] → ring[i+1]` takes the mesh's orientation). Returns the number
/// of vertices added.
fn fill_loop(ring: &[u32], positions: &mut Vec<[f64; 3]>, triangles: &mut Vec<[u32; 3]>) -> usize {
    let k = ring.len();
    if k == 3 {
        triangles.push([ring[0], ring[1], ring[2]]);
        return 0;
    }
    let first_new = positions.len();
    let rim: Vec<[f64; 3]> = ring.iter().map(|&v| positions[v as usize]).collect();
    let centroid = rim.iter().fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]]).map(|c| c / k as f64);
    // As many rings as make the new triangles about as long radially as the rim's edges are.
    let rings = ((k as f64 / std::f64::consts::TAU).round() as usize).clamp(1, 64);
    let mut previous: Vec<u32> = ring.to_vec();
    for j in 1..rings {
        let s = j as f64 / rings as f64;
        let current: Vec<u32> = rim
            .iter()
            .map(|p| {
                positions.push([0, 1, 2].map(|c| p[c] + s * (centroid[c] - p[c])));
                (positions.len() - 1) as u32
            })
            .collect();
        for i in 0..k {
            let n = (i + 1) % k;
            triangles.push([previous[i], previous[n], current[n]]);
            triangles.push([previous[i], current[n], current[i]]);
        }
        previous = current;
    }
    positions.push(centroid);
    let centre = (positions.len() - 1) as u32;
    for i in 0..k {
        triangles.push([previous[i], previous[(i + 1) % k], centre]);
    }
    relax(ring, rings, first_new, positions);
    positions.len() - first_new
}

/// Moves the filling's new vertices (rings 1.. of `k` vertices each, then the centre) to the
/// mean of their neighbours until they settle: a discrete membrane over the fixed rim.
fn relax(ring: &[u32], rings: usize, first_new: usize, positions: &mut [[f64; 3]]) {
    let k = ring.len();
    // Vertex i of ring j (ring 0 is the rim; ring `rings` is the centre).
    let at = |j: usize, i: usize| -> usize {
        if j == 0 {
            ring[i % k] as usize
        } else if j == rings {
            first_new + (rings - 1) * k
        } else {
            first_new + (j - 1) * k + i % k
        }
    };
    // Jacobi sweeps; a membrane of `rings` rings settles in about rings² of them.
    let sweeps = (4 * rings * rings).clamp(10, 2000);
    for _ in 0..sweeps {
        let old = positions.to_vec();
        for j in 1..rings {
            for i in 0..k {
                // The strip triangulation's neighbours: along the ring, and across to both
                // neighbouring rings (two on the outer one, two on the inner one).
                let nbrs = [at(j, i + k - 1), at(j, i + 1), at(j - 1, i), at(j - 1, i + k - 1), at(j + 1, i), at(j + 1, i + 1)];
                positions[at(j, i)] = mean(&old, &nbrs);
            }
        }
        let last: Vec<usize> = (0..k).map(|i| at(rings - 1, i)).collect();
        positions[at(rings, 0)] = mean(&old, &last);
    }
}

fn mean(positions: &[[f64; 3]], of: &[usize]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for &v in of {
        for c in 0..3 {
            s[c] += positions[v][c];
        }
    }
    s.map(|c| c / of.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::geometry;
    use crate::mesh::primitives;

    /// A unit grid with its middle cells removed, and a loose triangle far away.
    fn holed_grid_and_speck() -> Mesh {
        let n = 8;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push([i as f64, j as f64, 0.0]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if (3..5).contains(&i) && (3..5).contains(&j) {
                    continue;
                }
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let s = positions.len() as u32;
        positions.extend([[20.0, 0.0, 0.0], [21.0, 0.0, 0.0], [20.0, 1.0, 0.0]]);
        triangles.push([s, s + 1, s + 2]);
        build_mesh(TriangleSoup { positions, triangles, ..Default::default() }).unwrap().mesh
    }

    fn area(mesh: &Mesh) -> f64 {
        geometry::triangle_areas(mesh).iter().sum()
    }

    #[test]
    fn keeps_the_largest_component_and_its_numbering() {
        let m = holed_grid_and_speck();
        let options = RepairOptions { keep_largest: true, fill_holes: None };
        let (r, repairs) = repair_mesh(&m, &Repairs::default(), &options).unwrap();
        assert_eq!(r.n_vertices(), m.n_vertices());
        assert_eq!(r.n_faces(), m.n_faces() - 1);
        assert_eq!((repairs.removed_components, repairs.removed_component_faces), (1, 1));
        assert_eq!(topology(&r).components.len(), 1);
    }

    #[test]
    fn fills_the_small_hole_flat_and_leaves_the_rim_open() {
        let m = holed_grid_and_speck();
        let options = RepairOptions { keep_largest: true, fill_holes: Some(8) };
        let (r, repairs) = repair_mesh(&m, &Repairs::default(), &options).unwrap();
        let topo = topology(&r);
        // The 2×2 hole (8 edges) is closed; the grid's rim (32 edges) stays open.
        assert_eq!(topo.boundary_loops.len(), 1);
        assert_eq!(topo.boundary_loops[0].len(), 32);
        assert_eq!(repairs.filled_holes, 1);
        // A flat loop gives a flat filling of exactly the hole's area: the grid is 8×8 again.
        assert!((area(&r) - 64.0).abs() < 1e-9, "area {}", area(&r));
        assert!(r.positions()[m.n_vertices()..].iter().all(|p| p[2].abs() < 1e-12));
        // New vertices come after the file's.
        assert_eq!(r.n_vertices(), m.n_vertices() + repairs.fill_vertices);
    }

    #[test]
    fn a_closed_box_with_a_hole_is_closed_again() {
        let (cube, _) = primitives::parallelepiped([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], 4);
        // Remove the star of the vertex in the middle of one face.
        let positions = cube.positions().to_vec();
        let middle = |p: &[f64; 3]| (p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2) + (p[2] - 1.0).powi(2);
        let top = (0..positions.len()).min_by(|&a, &b| middle(&positions[a]).total_cmp(&middle(&positions[b]))).unwrap();
        let normal_z = |m: &Mesh, t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| m.position(v));
            crate::geom::cross(crate::geom::sub(b, a), crate::geom::sub(c, a))[2]
        };
        let (removed, kept): (Vec<[u32; 3]>, Vec<[u32; 3]>) =
            cube.triangles().iter().partition(|t| t.contains(&(top as u32)));
        let outward = normal_z(&cube, &removed[0]).signum();
        let holed = build_mesh(TriangleSoup { positions, triangles: kept, ..Default::default() }).unwrap().mesh;
        assert_eq!(topology(&holed).boundary_loops.len(), 1);
        let options = RepairOptions { keep_largest: false, fill_holes: Some(100) };
        let (r, repairs) = repair_mesh(&holed, &Repairs::default(), &options).unwrap();
        let topo = topology(&r);
        assert!(topo.boundary_loops.is_empty());
        assert_eq!(topo.components[0].genus, 0);
        assert_eq!(repairs.filled_holes, 1);
        // The filling is flat like the face it closes, and keeps the mesh's orientation.
        assert!((area(&r) - 6.0).abs() < 1e-9, "area {}", area(&r));
        for t in &r.triangles()[holed.n_faces()..] {
            assert_eq!(normal_z(&r, t).signum(), outward, "a filling triangle is turned over");
        }
    }
}
