//! The run report of `quadlay remesh --report` and of the page's `window.quadlay.result`
//! (shared/spec/cli.md, "Report"): one struct, serialized the same way by both, and the one
//! function that extracts, measures, judges ([`crate::verdict`], [`crate::guidance`]) and
//! reports for both.

use crate::clock::now;
use crate::layout::SurfaceLayout;
use crate::mesh::{Mesh, Repairs};
use crate::param::ParamSession;
use crate::guidance::{face_distortion, solved_face_guidance, FaceGuidance};
use crate::geom::{norm, sub};
use crate::mesh::geometry::bounding_box;
use crate::quad::density::face_areas;
use crate::quad::quality::{measure, Quality};
use crate::quad::{check_reads_back, extract, Extraction, QuadError, QuadMesh, QuadOptions};
use crate::verdict::{distorted_faces, warnings, Outcome, Warning};
use crate::summary::LayoutSummary;
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct InputCounts {
    pub vertices: usize,
    pub triangles: usize,
    /// The repairs made on the way in (those every load makes and those the user asked for);
    /// the caller, who loaded the mesh, fills it in.
    pub repairs: Repairs,
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
    /// The distortion on a scale people read: the typical relative length error between the
    /// surface and the charts, each chart scaled to its face's area as the quads are (the
    /// area-weighted median over the triangles of [`crate::guidance::length_error`]: 0.05
    /// means half the surface has lengths off by less than 5 %).
    pub length_error: f64,
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
    /// What to look at before trusting the result ([`verdict`]); empty for a clean one.
    pub warnings: Vec<Warning>,
    /// Per layout face: area, enclosed curvature, distortion and where a node would help
    /// ([`guidance`]).
    pub faces: Vec<FaceGuidance>,
    pub seconds: Seconds,
}

impl Report {
    /// Gathers the report of a finished run. `counts` are the extraction's sample counts.
    /// If [`ParamSession::finish`] has not run, the latest iteration stands for the final
    /// parameterization. `verdict` holds the warnings and the faces' guidance.
    pub fn new(
        mesh: &Mesh,
        layout: &SurfaceLayout,
        param: &ParamSession,
        quality: &Quality,
        counts: &[u32],
        verdict: Verdict,
        seconds: Seconds,
    ) -> Report {
        let summary = LayoutSummary::of(layout);
        let last = param.history().last().map(|h| h.distortion);
        let fin = param.final_distortion().or(last);
        Report {
            input: InputCounts { vertices: mesh.n_vertices(), triangles: mesh.n_faces(), repairs: Repairs::default() },
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
                length_error: verdict.length_error,
            },
            quads: quality.clone(),
            sample_counts: counts.to_vec(),
            warnings: verdict.warnings,
            faces: verdict.faces,
            seconds,
        }
    }
}

/// The judgement of a result: its warnings, the faces' guidance and the overall length error.
#[derive(Debug, Clone, Default)]
pub struct Verdict {
    pub warnings: Vec<Warning>,
    pub faces: Vec<FaceGuidance>,
    pub length_error: f64,
}

impl Verdict {
    /// Judges the quad mesh `quads` (measured as `quality`, extracted as `extraction` at
    /// `options`) of `param` on `mesh` with `layout`.
    pub fn of(
        mesh: &Mesh,
        layout: &SurfaceLayout,
        param: &ParamSession,
        quads: &QuadMesh,
        quality: &Quality,
        extraction: &Extraction,
        options: &QuadOptions,
    ) -> Verdict {
        let measured = face_distortion(param, layout.faces.len());
        let areas = face_areas(param.cut(), layout.faces.len());
        let distorted = distorted_faces(&areas, &measured, options.edge_length);
        let (lo, hi) = bounding_box(mesh);
        let outcome = Outcome {
            layout,
            param,
            quads,
            quality,
            diagonal: norm(sub(hi, lo)),
            edge_length: options.edge_length,
            surface_area: areas.iter().sum(),
            desired: &extraction.desired,
            counts: &extraction.counts,
            distorted: &distorted,
            measured: &measured,
        };
        Verdict {
            warnings: warnings(&outcome),
            faces: solved_face_guidance(mesh, layout, &measured, &distorted),
            length_error: measured.length_error_all,
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
    let verdict = Verdict::of(mesh, layout, param, &quads, &quality, &extraction, options);
    let seconds = Seconds {
        mesh: t_mesh - t0,
        total: earlier.load + earlier.layout + earlier.parameterize + (now() - t0),
        ..earlier
    };
    let report = Report::new(mesh, layout, param, &quality, &extraction.counts, verdict, seconds);
    Ok((quads, report))
}
