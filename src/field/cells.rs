//! The last start of an automatic layout, when the cross field's traces give none: the surface
//! cut into geodesic Voronoi cells of seeds spread by farthest-point sampling, each cell a
//! disk, their borders the layout's first curves (the repairs then give every face four nodes
//! or more, its corners where it turns most, the rest T-vertices).
//!
//! Why: the traces follow the field, and on a mesh whose field is noisy and whose parts are
//! thin (CGAL's man: 483 singularities, fingers a few triangles across) the repairs can end
//! with faces that are still not disks, or with a handful of faces round one hand and one face
//! for the rest of the body. Voronoi cells are disks once there are enough of them: a cell
//! that wraps round a limb or a handle gets a second seed at its point farthest from the
//! first, and the two halves no longer close round it.

use super::faces::analyze;
use super::graph::CurveGraph;
use crate::geom::{add, norm, scale, sub, Vec3};
use crate::layout::curve::Entry;
use crate::mesh::{Mesh, NONE};
use std::collections::BinaryHeap;

/// Rounds of seeds added to the cells that are not disks.
const SPLIT_ROUNDS: usize = 30;
/// The fewest triangles per cell asked for: six make the fan round one inside vertex.
const MIN_TRIANGLES: usize = 12;

/// Geodesic Voronoi cells over the triangles (distances between centroids across edges).
struct Cells {
    cell: Vec<u32>,
    dist: Vec<f64>,
    seeds: usize,
}

impl Cells {
    fn new(mesh: &Mesh) -> Cells {
        let nt = mesh.n_faces();
        Cells { cell: vec![NONE; nt], dist: vec![f64::INFINITY; nt], seeds: 0 }
    }

    /// Makes triangle `t` the seed of a new cell and takes over the triangles nearer to it,
    /// never across an edge that `walls` holds (a curve already there).
    fn add_seed(&mut self, mesh: &Mesh, centroids: &[Vec3], walls: &[u32], t: u32) {
        let id = self.seeds as u32;
        self.seeds += 1;
        self.dist[t as usize] = 0.0;
        self.cell[t as usize] = id;
        let mut heap = BinaryHeap::from([Entry(0.0, t)]);
        while let Some(Entry(d, t)) = heap.pop() {
            if d > self.dist[t as usize] {
                continue;
            }
            for k in 0..3 {
                let h = mesh.face_halfedge(t, k);
                let u = mesh.face(mesh.twin(h));
                if u == NONE || walls[mesh.edge(h) as usize] != NONE {
                    continue;
                }
                let du = d + norm(sub(centroids[u as usize], centroids[t as usize]));
                if du < self.dist[u as usize] {
                    self.dist[u as usize] = du;
                    self.cell[u as usize] = id;
                    heap.push(Entry(du, u));
                }
            }
        }
    }

    /// The triangle farthest from every seed (an unreached one first), among those `among`.
    fn farthest(&self, among: impl Fn(u32) -> bool) -> Option<u32> {
        (0..self.cell.len() as u32).filter(|&t| among(t)).max_by(|&a, &b| self.dist[a as usize].total_cmp(&self.dist[b as usize]))
    }
}

/// The distinct cells of the triangles on either side of halfedge `h`.
fn cells_beside(mesh: &Mesh, cell: &[u32], h: u32) -> impl Iterator<Item = u32> {
    let (a, b) = (mesh.face(h), mesh.face(mesh.twin(h)));
    let ca = (a != NONE).then(|| cell[a as usize]);
    let cb = (b != NONE).then(|| cell[b as usize]).filter(|&c| Some(c) != ca);
    ca.into_iter().chain(cb)
}

/// The triangles of each of `n` cells.
fn members(cell: &[u32], n: usize) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); n];
    for (t, &c) in cell.iter().enumerate() {
        out[c as usize].push(t as u32);
    }
    out
}

/// V − E + F of the triangles `tris` (1 for a disk; a cell round a limb or pinched at a
/// vertex has 0 or less).
fn euler(mesh: &Mesh, tris: &[u32]) -> i64 {
    let mut edges: Vec<u32> = Vec::with_capacity(3 * tris.len());
    let mut vertices: Vec<u32> = Vec::with_capacity(3 * tris.len());
    for &t in tris {
        for k in 0..3 {
            let h = mesh.face_halfedge(t, k);
            edges.push(mesh.edge(h));
            vertices.push(mesh.from_vertex(h));
        }
    }
    for list in [&mut edges, &mut vertices] {
        list.sort_unstable();
        list.dedup();
    }
    vertices.len() as i64 - edges.len() as i64 + tris.len() as i64
}

/// Merges every cell without a vertex inside (its borders would leave a face without one,
/// which the layout reader refuses) into the neighbour it shares the most edges with that it
/// makes a disk with. Merged here, not by the repairs' removal of a side: the shortest side
/// often joined two cells that also meet elsewhere, rings too thin to cut (CGAL's femur).
fn merge_empty(mesh: &Mesh, g: &CurveGraph, walls: &[u32], cell: &mut [u32], n: usize) {
    loop {
        let mut inside = vec![0usize; n];
        for v in (0..mesh.n_vertices() as u32).filter(|&v| !g.taken(v)) {
            let mut around = mesh.outgoing(v).map(|h| mesh.face(h)).filter(|&t| t != NONE).map(|t| cell[t as usize]);
            if let Some(c) = around.next() {
                if around.all(|d| d == c) {
                    inside[c as usize] += 1;
                }
            }
        }
        let mut tris = members(cell, n);
        let mut merged = false;
        for c in 0..n {
            if tris[c].is_empty() || inside[c] > 0 {
                continue;
            }
            let mut shared: Vec<(u32, usize)> = Vec::new();
            for &t in &tris[c] {
                for k in 0..3 {
                    let h = mesh.face_halfedge(t, k);
                    let u = mesh.face(mesh.twin(h));
                    if u == NONE || walls[mesh.edge(h) as usize] != NONE || cell[u as usize] == c as u32 {
                        continue;
                    }
                    match shared.iter_mut().find(|s| s.0 == cell[u as usize]) {
                        Some(s) => s.1 += 1,
                        None => shared.push((cell[u as usize], 1)),
                    }
                }
            }
            shared.sort_by_key(|s| std::cmp::Reverse(s.1));
            let mine = std::mem::take(&mut tris[c]);
            let into = shared.iter().map(|s| s.0 as usize).find(|&d| {
                let together: Vec<u32> = tris[d].iter().chain(&mine).copied().collect();
                euler(mesh, &together) == 1
            });
            match into {
                Some(d) => {
                    for &t in &mine {
                        cell[t as usize] = d as u32;
                    }
                    tris[d].extend(mine);
                    merged = true;
                }
                None => tris[c] = mine,
            }
        }
        if !merged {
            return;
        }
    }
}

/// The cell of every triangle: `count` seeds by farthest-point sampling (at least one in every
/// region that the curves of `g` and the components part; `walls`: per mesh edge, the curve
/// along it), then more in every cell that is not a disk until all are, then the cells
/// without a vertex inside merged away.
fn voronoi(mesh: &Mesh, g: &CurveGraph, walls: &[u32], count: usize) -> Vec<u32> {
    let centroids: Vec<Vec3> = mesh
        .triangles()
        .iter()
        .map(|t| scale(1.0 / 3.0, add(add(mesh.position(t[0]), mesh.position(t[1])), mesh.position(t[2]))))
        .collect();
    let mut cells = Cells::new(mesh);
    // A face needs triangles round a vertex inside: more cells than this would only be merged
    // again (and `--patches` may ask for 100000, each seed a scan of the triangles).
    let count = count.min(mesh.n_faces() / MIN_TRIANGLES);
    while cells.seeds < count || cells.dist.iter().any(|d| d.is_infinite()) {
        match cells.farthest(|_| true) {
            Some(t) => cells.add_seed(mesh, &centroids, walls, t),
            None => break,
        }
    }
    for _ in 0..SPLIT_ROUNDS {
        let split: Vec<u32> = members(&cells.cell, cells.seeds).iter().enumerate().filter(|(_, tris)| euler(mesh, tris) != 1).map(|(c, _)| c as u32).collect();
        if split.is_empty() {
            break;
        }
        let seeds: Vec<u32> = split.iter().filter_map(|&c| cells.farthest(|t| cells.cell[t as usize] == c)).collect();
        for t in seeds {
            cells.add_seed(mesh, &centroids, walls, t);
        }
    }
    let n = cells.seeds;
    merge_empty(mesh, g, walls, &mut cells.cell, n);
    cells.cell
}

/// Adds to `g` the borders of about `count` geodesic Voronoi cells that are disks, each inside
/// one of the faces `g`'s curves make, as paths of mesh vertices cut at every vertex where
/// three cells meet or that `g` already holds.
pub fn add_cell_borders(mesh: &Mesh, g: &mut CurveGraph, count: usize) {
    let walls = analyze(mesh, g).cut_by;
    let cell = voronoi(mesh, g, &walls, count);
    let border = |h: u32| walls[mesh.edge(h) as usize] == NONE && cells_beside(mesh, &cell, h).count() == 2;
    let degree: Vec<usize> = (0..mesh.n_vertices() as u32).map(|v| mesh.outgoing(v).filter(|&h| border(h)).count()).collect();
    let stop = |v: u32| degree[v as usize] != 2 || g.taken(v);
    let mut walked = vec![false; mesh.n_edges()];
    let mut paths: Vec<Vec<u32>> = Vec::new();
    // From every stop first, then round the closed loops left (a cell inside another's ring).
    let starts = (0..mesh.n_vertices() as u32).filter(|&v| stop(v)).chain((0..mesh.n_vertices() as u32).filter(|&v| !stop(v)));
    for start in starts.collect::<Vec<_>>() {
        for h in mesh.outgoing(start).collect::<Vec<_>>() {
            if !border(h) || walked[mesh.edge(h) as usize] {
                continue;
            }
            let mut path = vec![start];
            let mut h = h;
            loop {
                walked[mesh.edge(h) as usize] = true;
                let v = mesh.to_vertex(h);
                path.push(v);
                if stop(v) || v == start {
                    break;
                }
                match mesh.outgoing(v).find(|&n| border(n) && !walked[mesh.edge(n) as usize]) {
                    Some(n) => h = n,
                    None => break,
                }
            }
            // An edge between two vertices the graph holds already (along a feature line, or
            // a chord between two of its vertices) stays out.
            if !(path.len() == 2 && g.taken(path[0]) && g.taken(path[1])) {
                paths.push(path);
            }
        }
    }
    for p in &paths {
        g.add_path(p, false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::tests::torus;

    /// A torus has no disk among few cells round its tube; the cells split until each is one,
    /// and the borders cut it into disks.
    #[test]
    fn cells_of_a_torus_are_disks() {
        let mesh = torus(48, 16, 1.0, 0.35);
        let mut g = CurveGraph::new(&mesh);
        add_cell_borders(&mesh, &mut g, 3);
        let fa = analyze(&mesh, &g);
        assert!(fa.faces.len() >= 4, "{} faces", fa.faces.len());
        assert!(fa.faces.iter().all(|f| f.euler == 1), "{:?}", fa.faces.iter().map(|f| f.euler).collect::<Vec<_>>());
        assert!(fa.slits.is_empty());
    }
}
