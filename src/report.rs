//! The run report of `quadlay remesh --report` and of the page's `window.quadlay.result`
//! (shared/spec/cli.md, "Report"): one struct, serialized the same way by both, and the one
//! function that extracts, measures and reports for both.

use crate::clock::now;
use crate::layout::SurfaceLayout;
use crate::mesh::Mesh;
use crate::param::ParamSession;
use crate::quad::quality::{measure, Quality};
use crate::quad::{check_reads_back, extract, QuadError, QuadMesh, QuadOptions};
use crate::summary::LayoutSummary;
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct InputCounts {
    pub vertices: usize,
    pub triangles: usize,
}

#[derive(Debug, Clone, Serialize)]
pub struct LayoutCounts {
    pub nodes: usize,
    pub edges: usize,
    pub faces: usize,
    pub t_vertices: usize,
}

/// One entry of the chart-optimization history; 0 is the initial parameterization.
#[derive(Debug, Clone, Serialize)]
pub struct IterationEntry {
    pub iteration: usize,
    /// Area-weighted mean of ‖JᵀJ − I‖²_F.
    pub distortion: f64,
    pub distortion_max: f64,
    pub flipped_triangles: usize,
    pub seconds: f64,
}

/// The final parameterization (with the user's alignment tags).
#[derive(Debug, Clone, Serialize)]
pub struct ParamEntry {
    pub distortion_mean: f64,
    pub distortion_max: f64,
    pub flipped_triangles: usize,
}

/// Wall-clock seconds per stage.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Seconds {
    pub load: f64,
    pub layout: f64,
    pub parameterize: f64,
    /// Quad extraction (sample counts, grids, back-mapping).
    pub mesh: f64,
    /// Everything, quality measures included.
    pub total: f64,
}

/// The report; field names are a contract (cli.md): fields may be added, never renamed.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub input: InputCounts,
    pub layout: LayoutCounts,
    pub iterations: Vec<IterationEntry>,
    pub parameterization: ParamEntry,
    /// `vertices`, `faces`, `irregular_vertices` and the other quality measures.
    pub quads: Quality,
    /// Segments per layout curve (the file's edges first, then the boundary pieces).
    pub sample_counts: Vec<u32>,
    pub seconds: Seconds,
}

impl Report {
    /// Gathers the report of a finished run. `counts` are the extraction's sample counts.
    /// If [`ParamSession::finish`] has not run, the latest iteration stands for the final
    /// parameterization.
    pub fn new(
        mesh: &Mesh,
        layout: &SurfaceLayout,
        param: &ParamSession,
        quality: &Quality,
        counts: &[u32],
        seconds: Seconds,
    ) -> Report {
        let summary = LayoutSummary::of(layout);
        let last = param.history().last().map(|h| h.distortion);
        let fin = param.final_distortion().or(last);
        Report {
            input: InputCounts { vertices: mesh.n_vertices(), triangles: mesh.n_faces() },
            layout: LayoutCounts {
                nodes: summary.nodes,
                edges: summary.edges,
                faces: summary.faces,
                t_vertices: summary.t_vertices,
            },
            iterations: param
                .history()
                .iter()
                .map(|h| IterationEntry {
                    iteration: h.iteration,
                    distortion: h.distortion.mean,
                    distortion_max: h.distortion.max,
                    flipped_triangles: h.distortion.flipped,
                    seconds: h.seconds,
                })
                .collect(),
            parameterization: ParamEntry {
                distortion_mean: fin.map_or(0.0, |d| d.mean),
                distortion_max: fin.map_or(0.0, |d| d.max),
                flipped_triangles: fin.map_or(0, |d| d.flipped),
            },
            quads: quality.clone(),
            sample_counts: counts.to_vec(),
            seconds,
        }
    }
}

/// The last stage of `quadlay remesh` and of the page's remesh, so that both time and report
/// it alike: extracts the quad mesh of `param` (paper Section 4), measures it against `mesh`
/// and gathers the report. `earlier` holds the seconds of loading, layout and
/// parameterization; `mesh` and `total` are filled in here (`total` counts the quality
/// measures too).
///
/// # Errors
/// [`QuadError`] from the extraction: a layout that does not make quads, or an edge length
/// that asks for too many.
pub fn extract_and_report(
    mesh: &Mesh,
    layout: &SurfaceLayout,
    param: &ParamSession,
    options: &QuadOptions,
    earlier: Seconds,
) -> Result<(QuadMesh, Report), QuadError> {
    let t0 = now();
    let (quads, extraction) = extract(layout, param, options)?;
    check_reads_back(&quads)?;
    let t_mesh = now();
    let quality = measure(mesh, &quads);
    let seconds = Seconds {
        mesh: t_mesh - t0,
        total: earlier.load + earlier.layout + earlier.parameterize + (now() - t0),
        ..earlier
    };
    let report = Report::new(mesh, layout, param, &quality, &extraction.counts, seconds);
    Ok((quads, report))
}
