//! Simple meshes made from parameters: planar grids and parallelepipeds. Tests and
//! benchmarks use them for known answers (a flat or developable surface must come out
//! isometric).

use super::{build_mesh, Mesh, TriangleSoup};
use std::collections::HashMap;

/// The triangles of an n×n grid of squares whose vertex (i, j) is `j (n + 1) + i`, each square
/// split along alternating diagonals, counter-clockwise in the (i, j) plane.
pub fn grid_triangles(n: u32) -> Vec<[u32; 3]> {
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut triangles = Vec::with_capacity(2 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    triangles
}

/// A planar grid over the quadrilateral `q` (counter-clockwise corners in the z = 0 plane):
/// the bilinear image of an n×n grid, vertex (i, j) at index `j (n + 1) + i`.
///
/// Precondition: `q` convex, n ≥ 1.
pub fn quad_grid(q: [[f64; 2]; 4], n: u32) -> Mesh {
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
            let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
            let x = (0..4).map(|k| w[k] * q[k][0]).sum();
            let y = (0..4).map(|k| w[k] * q[k][1]).sum();
            positions.push([x, y, 0.0]);
        }
    }
    mesh(positions, grid_triangles(n))
}

/// The surface of the parallelepiped spanned by `a, b, c` (right-handed), each face an n×n
/// grid, facing outwards; the vertex of lattice point (i, j, k) in 0..=n is `ids[&[i, j, k]]`,
/// at (i a + j b + k c) / n.
pub fn parallelepiped(a: [f64; 3], b: [f64; 3], c: [f64; 3], n: u32) -> (Mesh, HashMap<[u32; 3], u32>) {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for high in [false, true] {
            // (u, v) with u × v along +axis on the high side and −axis on the low side.
            let (u, v) = if high { ((axis + 1) % 3, (axis + 2) % 3) } else { ((axis + 2) % 3, (axis + 1) % 3) };
            let local: Vec<u32> = (0..=n)
                .flat_map(|j| (0..=n).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let mut g = [0u32; 3];
                    g[axis] = if high { n } else { 0 };
                    g[u] = i;
                    g[v] = j;
                    *ids.entry(g).or_insert_with(|| {
                        let f = g.map(|x| x as f64 / n as f64);
                        positions.push(std::array::from_fn(|k| f[0] * a[k] + f[1] * b[k] + f[2] * c[k]));
                        (positions.len() - 1) as u32
                    })
                })
                .collect();
            triangles.extend(grid_triangles(n).into_iter().map(|t| t.map(|x| local[x as usize])));
        }
    }
    (mesh(positions, triangles), ids)
}

fn mesh(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Mesh {
    // Generated meshes are valid by construction.
    match build_mesh(TriangleSoup { positions, triangles, ..Default::default() }) {
        Ok(b) => b.mesh,
        Err(e) => unreachable!("a generated mesh is invalid: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology::topology;

    #[test]
    fn parallelepiped_is_a_closed_sphere_and_grid_a_disk() {
        let (m, ids) = parallelepiped([1.0, 0.0, 0.0], [0.5, 0.8, 0.0], [0.1, 0.2, 0.9], 4);
        let t = topology(&m);
        assert_eq!((t.components.len(), t.components[0].genus, t.boundary_loops.len()), (1, 0, 0));
        assert_eq!(ids.len(), m.n_vertices());
        let g = quad_grid([[0.0, 0.0], [2.0, 0.0], [2.4, 1.3], [0.3, 1.1]], 5);
        assert_eq!(topology(&g).boundary_loops.len(), 1);
        assert_eq!(g.position(35), [2.4, 1.3, 0.0]);
    }
}
