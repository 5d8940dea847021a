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
        let mut made = Vec::new();
        if r.welded_vertices + r.removed_zero_area_faces + r.unreferenced_vertices > 0 {
            made.push(format!(
                "{} vertices welded, {} zero-area faces removed, {} unreferenced vertices ignored",
                r.welded_vertices, r.removed_zero_area_faces, r.unreferenced_vertices
            ));
        }
        if r.removed_components > 0 {
            made.push(format!(
                "kept the largest component: {} other components ({} triangles) removed",
                r.removed_components, r.removed_component_faces
            ));
        }
        if r.filled_holes > 0 {
            made.push(format!("{} holes filled ({} vertices added)", r.filled_holes, r.fill_vertices));
        }
        if r.refinements > 0 {
            made.push(format!(
                "refined: every triangle split in four, {} times (from {} vertices and {} triangles), so that a layout has room between the vertices",
                r.refinements, r.vertices_before_refinement, r.triangles_before_refinement
            ));
        }
        if made.is_empty() {
            writeln!(f, "repairs:        none")?;
        }
        for line in made {
            writeln!(f, "repairs:        {line}")?;
        }
        Ok(())
    }
}

/// The layout part of `quadlay check --layout`: counts, chart types, and each face.
#[derive(Debug, Clone, Serialize)]
pub struct LayoutSummary {
    pub nodes: usize,
    pub edges: usize,
    pub aligned_edges: usize,
    pub boundary_pieces: usize,
    pub faces: usize,
    pub t_vertices: usize,
    /// Faces per chart type: quad, rect, unit.
    pub charts: [usize; 3],
    /// Per face: its corner nodes, T-vertices and chart type.
    pub face_list: Vec<FaceSummary>,
}

#[derive(Debug, Clone, Serialize)]
pub struct FaceSummary {
    pub corners: [u32; 4],
    pub t_vertices: Vec<u32>,
    pub chart: crate::layout::ChartType,
}

impl LayoutSummary {
    pub fn of(layout: &crate::layout::SurfaceLayout) -> LayoutSummary {
        use crate::layout::{ChartType, CurveSource};
        let edges = layout.curves.iter().filter(|c| matches!(c.source, CurveSource::Edge(_))).count();
        let aligned = layout.curves.iter().filter(|c| c.align && matches!(c.source, CurveSource::Edge(_))).count();
        let mut charts = [0; 3];
        for f in &layout.faces {
            charts[match f.chart {
                ChartType::Quad => 0,
                ChartType::Rect => 1,
                ChartType::Unit => 2,
            }] += 1;
        }
        LayoutSummary {
            nodes: layout.node_vertex.len(),
            edges,
            aligned_edges: aligned,
            boundary_pieces: layout.curves.len() - edges,
            faces: layout.faces.len(),
            t_vertices: layout.t_vertex_count(),
            charts,
            face_list: layout
                .faces
                .iter()
                .map(|f| FaceSummary { corners: f.corner_nodes(), t_vertices: f.t_vertices().collect(), chart: f.chart })
                .collect(),
        }
    }
}

impl fmt::Display for LayoutSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "nodes:          {}", self.nodes)?;
        writeln!(f, "edges:          {} ({} tagged for alignment)", self.edges, self.aligned_edges)?;
        writeln!(f, "boundary edges: {}", self.boundary_pieces)?;
        writeln!(f, "faces:          {}", self.faces)?;
        writeln!(f, "t-vertices:     {}", self.t_vertices)?;
        let [q, r, u] = self.charts;
        writeln!(f, "charts:         {q} quad, {r} rect, {u} unit")?;
        for (i, face) in self.face_list.iter().enumerate() {
            let c = face.corners;
            write!(f, "  face {i}: corners {} {} {} {}, {}", c[0], c[1], c[2], c[3], face.chart.name())?;
            if !face.t_vertices.is_empty() {
                let t: Vec<String> = face.t_vertices.iter().map(|n| n.to_string()).collect();
                write!(f, ", t-vertices {}", t.join(" "))?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}
