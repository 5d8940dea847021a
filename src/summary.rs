//! The one-screen summary of a mesh that `quadlay check` prints and the page shows.

use crate::io::{Format, LoadedMesh};
use crate::mesh::geometry::bounding_box;
use crate::mesh::topology::{topology, Component};
use crate::mesh::Repairs;
use serde::Serialize;
use std::fmt;

#[derive(Debug, Clone, Serialize)]
pub struct MeshSummary {
    pub format: Format,
    pub vertices: usize,
    pub triangles: usize,
    pub edges: usize,
    pub boundary_loops: usize,
    /// Sum over the components.
    pub genus: i64,
    pub components: Vec<Component>,
    pub bounding_box: [[f64; 3]; 2],
    pub repairs: Repairs,
}

impl MeshSummary {
    pub fn of(loaded: &LoadedMesh) -> MeshSummary {
        let m = &loaded.mesh;
        let topo = topology(m);
        let (lo, hi) = bounding_box(m);
        MeshSummary {
            format: loaded.format,
            vertices: m.n_vertices(),
            triangles: m.n_faces(),
            edges: m.n_edges(),
            boundary_loops: topo.boundary_loops.len(),
            genus: topo.components.iter().map(|c| c.genus).sum(),
            components: topo.components,
            bounding_box: [lo, hi],
            repairs: loaded.repairs.clone(),
        }
    }
}

impl fmt::Display for MeshSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "format:         {}", self.format)?;
        writeln!(f, "vertices:       {}", self.vertices)?;
        writeln!(f, "triangles:      {}", self.triangles)?;
        writeln!(f, "edges:          {}", self.edges)?;
        writeln!(f, "boundary loops: {}", self.boundary_loops)?;
        writeln!(f, "genus:          {}", self.genus)?;
        writeln!(f, "components:     {}", self.components.len())?;
        if self.components.len() > 1 {
            for (i, c) in self.components.iter().enumerate() {
                writeln!(
                    f,
                    "  component {i}: {} vertices, {} triangles, {} boundary loops, genus {}",
                    c.vertices, c.faces, c.boundary_loops, c.genus
                )?;
            }
        }
        let [lo, hi] = self.bounding_box;
        let size: Vec<String> = (0..3).map(|k| format!("{:.6}", hi[k] - lo[k])).collect();
        writeln!(f, "bounding box:   {}", size.join(" x "))?;
        let r = &self.repairs;
        if r.is_empty() {
            writeln!(f, "repairs:        none")?;
        } else {
            writeln!(
                f,
                "repairs:        {} vertices welded, {} zero-area faces removed, {} unreferenced vertices ignored",
                r.welded_vertices, r.removed_zero_area_faces, r.unreferenced_vertices
            )?;
        }
        Ok(())
    }
}
