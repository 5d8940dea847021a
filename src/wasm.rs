//! The browser's door to the core: the only file that knows about wasm-bindgen. A
//! [`Session`] lives in the page's worker and keeps state between messages; data crosses as
//! typed arrays, summaries as plain JS objects, errors as JS `Error`s that carry what they
//! are about as data besides their readable text ([`Thrown`]).

use crate::clock::now;
use crate::culprits::Culprits;
use crate::io::{write_glb, write_obj, write_ply, Polygons};
use crate::io::{read_mesh, LoadedMesh, ReadError};
use crate::field::{compute_field, pick, Candidate, FieldView, Judged, LayoutOptions, Proposal, ProposeError, Tracings};
use crate::layout::{build_layout_on, curve, parse_layout, place, write_layout, CurveSource, Layout, LayoutError, LayoutFileError, MeshCounts, Numbering, SurfaceLayout};
use crate::mesh::{repair_mesh, Mesh, RepairOptions};
use crate::param::chart::ChartKind;
use crate::param::input_uv::input_corner_uv;
use crate::param::{ParamError, ParamOptions, ParamSession};
use crate::guidance::{face_distortion, face_guidance, solved_face_guidance, FaceGuidance};
use crate::quad::density::{edge_length_for_quads, face_areas};
use crate::verdict::distorted_faces;
use crate::quad::{default_edge_length, QuadError, QuadMesh, QuadOptions};
use crate::quote::{quoted, quoted_in};
use crate::report::{extract_and_report, Report, Seconds};
use crate::summary::{LayoutSummary, MeshSummary};
use serde::{Deserialize, Serialize};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

#[wasm_bindgen]
pub struct Session {
    loaded: LoadedMesh,
    /// The vertex numbering layout files use on the mesh: as read, and after the repairs the
    /// user asked for (before refinement).
    numbering: Numbering,
    layout: Option<SurfaceLayout>,
    /// The active parameterization and the layout it ran on.
    param: Option<Run>,
    /// Parameterizations put aside by [`Session::keep_param`], by name.
    kept: Vec<(String, Run)>,
    /// Seconds spent reading the mesh and placing the layout (for the report).
    load_seconds: f64,
    layout_seconds: f64,
    /// The cross field and tracings of the last suggestion, with the feature angle they were
    /// made with: a page's worker asks for its tracings one after the other, then for the
    /// corners of the one kept, and each would make them again.
    tracings: Option<(f64, Tracings)>,
}

/// The tracings of `cache` if they were made with `options`' feature angle, else made now
/// and kept there.
fn cached<'a>(cache: &'a mut Option<(f64, Tracings)>, mesh: &Mesh, options: &LayoutOptions) -> Result<&'a Tracings, ProposeError> {
    if !matches!(cache, Some((angle, _)) if *angle == options.feature_angle) {
        *cache = Some((options.feature_angle, Tracings::new(mesh, options)?));
    }
    Ok(&cache.as_ref().expect("made above").1)
}

struct Run {
    layout: SurfaceLayout,
    param: ParamSession,
    /// Seconds of the parameterization: the iterations and the final solve.
    seconds: f64,
    /// The quad mesh of the last [`Session::remesh`] of this run, with its report.
    quads: Option<(QuadMesh, Report)>,
}

/// Options of [`Session::remesh`] (all optional; unknown keys are errors, see [`options`]).
#[derive(Deserialize, Default)]
#[serde(default)]
struct RemeshOptions {
    /// Target quad edge length in the mesh's units; default 1/40 of the bounding-box
    /// diagonal.
    edge_length: Option<f64>,
    /// Target number of quads instead of `edge_length` (L = √(surface area / quads)); giving
    /// both is an error.
    quads: Option<f64>,
}

/// An error for JS, thrown as an `Error` whose `message` is for people, `kind` a stable
/// snake_case name and `culprits` what it names ([`Culprits`], plain numbers): the page reads
/// those, never the message (www/protocol.js).
pub struct Thrown {
    message: String,
    kind: &'static str,
    culprits: Culprits,
}

impl Thrown {
    /// An error that names nothing.
    fn new(kind: &'static str, message: impl Into<String>) -> Thrown {
        Thrown { message: message.into(), kind, culprits: Culprits::none() }
    }

    /// Asked for something that needs an active parameterization.
    fn no_param() -> Thrown {
        Thrown::new("no_param", "start the parameterization first")
    }
}

impl From<Thrown> for JsValue {
    fn from(t: Thrown) -> JsValue {
        let error = js_sys::Error::new(&t.message);
        let serializer = serde_wasm_bindgen::Serializer::json_compatible();
        let culprits = t.culprits.serialize(&serializer).unwrap_or(JsValue::NULL);
        // Setting a property of a fresh Error cannot fail.
        let _ = js_sys::Reflect::set(&error, &"kind".into(), &t.kind.into());
        let _ = js_sys::Reflect::set(&error, &"culprits".into(), &culprits);
        error.into()
    }
}

impl From<LayoutFileError> for Thrown {
    fn from(e: LayoutFileError) -> Thrown {
        Thrown { message: e.to_string(), kind: e.kind(), culprits: e.culprits() }
    }
}

impl From<ParamError> for Thrown {
    fn from(e: ParamError) -> Thrown {
        Thrown { message: e.to_string(), kind: e.kind(), culprits: e.culprits() }
    }
}

impl From<QuadError> for Thrown {
    fn from(e: QuadError) -> Thrown {
        Thrown { message: e.to_string(), kind: e.kind(), culprits: e.culprits() }
    }
}

/// A layout's error, with what it names in `layout`, the file it is about.
fn layout_error(e: LayoutError, layout: &Layout) -> Thrown {
    Thrown { message: e.to_string(), kind: e.kind(), culprits: e.culprits(layout) }
}

/// A mesh file's error; the message starts with the file's name.
fn read_error(e: ReadError, name: &str) -> Thrown {
    Thrown::new(e.kind(), format!("{name}: {e}"))
}

/// Options of [`Session::suggest_layout`] (all optional).
#[derive(Deserialize, Default)]
#[serde(default, rename_all = "camelCase")]
struct SuggestOptions {
    patches: Option<f64>,
    feature_angle: Option<f64>,
    tracing: Option<f64>,
    quads: Option<f64>,
}

/// An options object from JS. Its keys are checked first: serde-wasm-bindgen reads only the
/// fields it knows (`deny_unknown_fields` never sees the others), so a misspelled option
/// (`edgeLength`) would be ignored without a word.
fn options<T: serde::de::DeserializeOwned>(value: JsValue, what: &str, known: &[&str]) -> Result<T, Thrown> {
    if value.is_object() {
        for key in js_sys::Object::keys(value.unchecked_ref::<js_sys::Object>()).iter() {
            let key = key.as_string().unwrap_or_default();
            if !known.contains(&key.as_str()) {
                return Err(Thrown::new("bad_options", format!("{what}: unknown option {} (known: {})", quoted_in(&key, '`'), known.join(", "))));
            }
        }
    }
    serde_wasm_bindgen::from_value(value).map_err(|e| Thrown::new("bad_options", format!("{what}: {e}")))
}

/// A face's chart as the page draws it (paper Fig. 9).
#[derive(Serialize)]
struct ChartView {
    kind: &'static str,
    /// c0..c3, counter-clockwise.
    corners: [[f64; 2]; 4],
}

/// Where a curve comes from, tagged: `{ edge: i }` (a file edge) or `{ boundary: l }` (a
/// piece of boundary loop l).
#[derive(Serialize)]
#[serde(rename_all = "snake_case")]
enum SourceView {
    Edge(usize),
    Boundary(usize),
}

/// A layout curve as the page draws it.
#[derive(Serialize)]
struct CurveView {
    source: SourceView,
    align: bool,
    nodes: [u32; 2],
    /// xyz interleaved.
    points: Vec<f32>,
}

#[derive(Serialize)]
struct LayoutView {
    summary: LayoutSummary,
    curves: Vec<CurveView>,
    /// Face of every mesh vertex (-1 for nodes).
    vertex_face: Vec<i32>,
    /// Per face: area, the Gaussian curvature it encloses and, where it holds too much, a
    /// suggested vertex for a new node (the report's `faces`, before solving).
    faces: Vec<FaceGuidance>,
}

fn to_js<T: Serialize>(value: &T) -> Result<JsValue, Thrown> {
    value
        .serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .map_err(|e| Thrown::new("internal", e.to_string()))
}

#[wasm_bindgen]
impl Session {
    /// Reads a mesh from the bytes of a file; `name` decides the format by its extension.
    /// `repairs` (optional) asks for the repairs of cli.md: `{ keep_largest: true,
    /// fill_holes: N }`; the summary lists them.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8], name: &str, repairs: JsValue) -> Result<Session, Thrown> {
        let t0 = now();
        let asked: RepairOptions = if repairs.is_undefined() || repairs.is_null() {
            RepairOptions::default()
        } else {
            options(repairs, "repairs", &["keep_largest", "fill_holes"])?
        };
        let mut loaded = read_mesh(bytes, name).map_err(|e| read_error(e, name))?;
        let as_read = MeshCounts::of(&loaded.mesh);
        if !asked.is_none() {
            let (mesh, made) = repair_mesh(&loaded.mesh, &loaded.repairs, &asked).map_err(|e| {
                Thrown::new("bad_repair", format!("{name}: the repairs asked for do not give a valid mesh: {e}"))
            })?;
            loaded = LoadedMesh { mesh, repairs: made, format: loaded.format };
        }
        let numbering = Numbering { as_read, numbered: MeshCounts::of(&loaded.mesh) };
        let loaded = loaded.refined();
        let load_seconds = now() - t0;
        Ok(Session { loaded, numbering, layout: None, param: None, kept: Vec::new(), load_seconds, layout_seconds: 0.0, tracings: None })
    }

    /// Vertex positions, xyz interleaved, as `Float32Array`.
    pub fn positions(&self) -> Vec<f32> {
        self.loaded.mesh.positions().iter().flat_map(|p| p.map(|c| c as f32)).collect()
    }

    /// Triangles as vertex index triples, as `Uint32Array`.
    pub fn triangles(&self) -> Vec<u32> {
        self.loaded.mesh.triangles().iter().flatten().copied().collect()
    }

    /// The summary `quadlay check` prints, as an object.
    pub fn summary(&self) -> Result<JsValue, Thrown> {
        to_js(&MeshSummary::of(&self.loaded))
    }

    /// Places a layout file (format v1, as text) on the mesh. Returns its summary, the
    /// curves as polylines and the face of every vertex; throws the layout's error.
    #[wasm_bindgen(js_name = setLayout)]
    pub fn set_layout(&mut self, text: &str) -> Result<JsValue, Thrown> {
        self.layout = None;
        self.param = None;
        self.kept.clear();
        let t0 = now();
        let mesh = &self.loaded.mesh;
        let layout = parse_layout(text)?;
        let surface = build_layout_on(mesh, &layout, self.numbering).map_err(|e| layout_error(e, &layout))?;
        self.layout_seconds = now() - t0;
        let curves = surface
            .curves
            .iter()
            .map(|c| CurveView {
                source: match c.source {
                    CurveSource::Edge(i) => SourceView::Edge(i),
                    CurveSource::Boundary { boundary_loop } => SourceView::Boundary(boundary_loop),
                },
                align: c.align,
                nodes: c.nodes,
                points: c.curve.points.iter().flat_map(|p| curve::position(mesh, p).map(|x| x as f32)).collect(),
            })
            .collect();
        let view = LayoutView {
            summary: LayoutSummary::of(&surface),
            curves,
            vertex_face: surface.vertex_face.iter().map(|&f| if f == u32::MAX { -1 } else { f as i32 }).collect(),
            faces: face_guidance(mesh, &surface),
        };
        self.layout = Some(surface);
        to_js(&view)
    }

    /// Proposes a coarse quad layout from the surface's cross field (`quadlay layout`).
    /// `options`: `{ patches?: number, featureAngle?: number, tracing?: number, quads?: number }`
    /// (about how many faces; sharp edges bend more than this many degrees, default 35; the
    /// quads it will be remeshed with, where known: the proposals are judged at them). Returns
    /// `{ layout, field, note }`: `layout` the layout file's text (format v1; place it with
    /// `setLayout`), `field` the cross field for drawing: `directions` (one unit arm per
    /// vertex, xyz), and `singularityPositions` (xyz) with `singularityValences`. Throws why
    /// no valid layout could be made.
    ///
    /// With `tracing: k` only the proposal along the `k`-th tracing is made, and the answer
    /// also has `tracings` (how many there are; `layout` is null when `k` is not below it),
    /// `judged` and `curves` for [`pick_suggestion`], or `error` (and no `layout`): why the
    /// proposal along it could not be made. The page makes the proposals in workers of their
    /// own, at once.
    #[wasm_bindgen(js_name = suggestLayout)]
    pub fn suggest_layout(&mut self, options: JsValue) -> Result<JsValue, Thrown> {
        let (opts, tracing) = layout_options(options, "suggestLayout", &["patches", "featureAngle", "tracing", "quads"], &self.loaded.mesh)?;
        let mesh = &self.loaded.mesh;
        let failed = |e: ProposeError| Thrown::new("no_layout_proposed", e.to_string());
        #[derive(Serialize, Default)]
        struct Suggestion {
            layout: Option<String>,
            field: Option<FieldView>,
            note: Option<String>,
            tracings: Option<usize>,
            judged: Option<Judged>,
            curves: Option<usize>,
            error: Option<String>,
        }
        let numbering = self.numbering;
        let made = |p: Proposal| {
            let note = p.patches_note(opts.patches);
            Suggestion { layout: Some(write_layout(&p.layout.in_numbering(mesh, numbering))), field: Some(p.field.view(mesh)), note, ..Default::default() }
        };
        let tracings = cached(&mut self.tracings, mesh, &opts).map_err(failed)?;
        let Some(k) = tracing else {
            return to_js(&made(tracings.propose(mesh, &opts).map_err(failed)?));
        };
        let n = Some(tracings.count());
        if k >= tracings.count() {
            return to_js(&Suggestion { tracings: n, ..Default::default() });
        }
        // A tracing that makes no layout is an answer: another one may.
        let c = match tracings.candidate(mesh, k, &opts) {
            Ok(c) => c,
            Err(e) => return to_js(&Suggestion { tracings: n, error: Some(e.to_string()), ..Default::default() }),
        };
        let (judged, curves) = c.summary();
        let p = Proposal { layout: c.layout, field: tracings.field.clone(), surface: c.surface };
        to_js(&Suggestion { tracings: n, judged, curves: Some(curves), ..made(p) })
    }

    /// The last step of a suggestion made apart (`suggestLayout` with `tracing` in workers,
    /// then [`pick_suggestion`]), as `suggestLayout` without `tracing` ends
    /// ([`Tracings::conclude`]): `text` and `judged` are the kept proposal's layout file and
    /// judged quads as it answered, or null where no tracing made one; `options` the same as
    /// it got. Returns `{ layout, judged }`: that layout, or the Voronoi cells' where it is far
    /// from the surface or its judged quads fold, and theirs is better, either with the corners of all faces chosen
    /// together where its quads judge no worse. Throws the layout's error, or the field's, or
    /// why no layout could be made.
    #[wasm_bindgen(js_name = finishSuggestion)]
    pub fn finish_suggestion(&mut self, text: Option<String>, judged: JsValue, options: JsValue) -> Result<JsValue, Thrown> {
        let (opts, _) = layout_options(options, "finishSuggestion", &["patches", "featureAngle", "quads"], &self.loaded.mesh)?;
        let judged: Option<Judged> = serde_wasm_bindgen::from_value(judged)
            .map_err(|e| Thrown::new("bad_options", format!("finishSuggestion: judged must be {{ hausdorff, score }} or null: {e}")))?;
        let mesh = &self.loaded.mesh;
        let kept = match text {
            Some(text) => {
                let layout = parse_layout(&text)?;
                let placed = place(mesh, &layout, self.numbering).map_err(|e| layout_error(e, &layout))?;
                let surface = placed.with_patches(mesh, &layout).map_err(|e| layout_error(e, &layout))?;
                Ok(Candidate { layout, surface, judged })
            }
            None => Err(ProposeError::NoValidLayout("no tracing made a layout".into())),
        };
        let failed = |e: ProposeError| Thrown::new("no_layout_proposed", e.to_string());
        let tracings = cached(&mut self.tracings, mesh, &opts).map_err(failed)?;
        let kept = tracings.conclude(mesh, kept, &opts).map_err(failed)?;
        #[derive(Serialize)]
        struct Chosen {
            layout: String,
            judged: Option<Judged>,
        }
        to_js(&Chosen { layout: write_layout(&kept.layout.in_numbering(mesh, self.numbering)), judged: kept.judged })
    }

    /// The surface's cross field alone, for the page's field view: `options`
    /// `{ featureAngle?: number }` as for [`suggest_layout`](Self::suggest_layout), whose
    /// `field` it returns (no layout is made). Throws if the field's solve fails.
    #[wasm_bindgen(js_name = crossField)]
    pub fn cross_field(&self, options: JsValue) -> Result<JsValue, Thrown> {
        let (opts, _) = layout_options(options, "crossField", &["featureAngle"], &self.loaded.mesh)?;
        let mesh = &self.loaded.mesh;
        let field = compute_field(mesh, opts.feature_angle)
            .map_err(|e| Thrown::new(e.kind(), ProposeError::Field(e).to_string()))?;
        to_js(&field.view(mesh))
    }

    /// Starts the parameterization of the placed layout: unit charts, every edge aligned,
    /// the initial solve (iteration 0). Returns its statistics. `options` is either a boolean
    /// (align) or an object with any of [`ParamOptions`]' fields, e.g. `{ align?: bool,
    /// chart?: "quad" | "rect" | "unit" | null }` (`chart` replaces the layout's default
    /// chart type; faces with a chart in `patches` keep theirs).
    #[wasm_bindgen(js_name = startParam)]
    pub fn start_param(&mut self, options: JsValue) -> Result<JsValue, Thrown> {
        self.param = None;
        let options: ParamOptions = if let Some(align) = options.as_bool() {
            let mut o = ParamOptions::DEFAULT;
            o.align = align;
            o
        } else if options.is_undefined() || options.is_null() {
            ParamOptions::DEFAULT
        } else {
            self::options(options, "solve options", &ParamOptions::KEYS)?
        };
        let layout = self.layout.clone().ok_or_else(|| Thrown::new("no_layout", "place a layout first"))?;
        let param = ParamSession::new(&self.loaded.mesh, &layout, &options)?;
        let first = param.history()[0];
        self.param = Some(Run { layout, seconds: first.seconds, param, quads: None });
        to_js(&first)
    }

    /// One chart-optimization iteration (paper 3.1); returns its statistics.
    #[wasm_bindgen(js_name = stepParam)]
    pub fn step_param(&mut self) -> Result<JsValue, Thrown> {
        let run = self.run_mut()?;
        run.quads = None;
        let stats = run.param.step()?;
        run.seconds += stats.seconds;
        to_js(&stats)
    }


    /// The final solve with the user's alignment tags; returns its distortion.
    #[wasm_bindgen(js_name = finishParam)]
    pub fn finish_param(&mut self) -> Result<JsValue, Thrown> {
        let run = self.run_mut()?;
        run.quads = None;
        let t0 = now();
        let d = run.param.finish()?;
        run.seconds += now() - t0;
        to_js(&d)
    }


    /// The refined (cut) mesh's vertex positions, xyz interleaved, as `Float32Array`.
    #[wasm_bindgen(js_name = cutPositions)]
    pub fn cut_positions(&self) -> Result<Vec<f32>, Thrown> {
        Ok(self.param_ref()?.cut().positions.iter().flat_map(|p| p.map(|c| c as f32)).collect())
    }

    /// The refined mesh's triangles (vertex index triples), as `Uint32Array`.
    #[wasm_bindgen(js_name = cutTriangles)]
    pub fn cut_triangles(&self) -> Result<Vec<u32>, Thrown> {
        Ok(self.param_ref()?.cut().triangles.iter().flatten().copied().collect())
    }

    /// The layout face (chart) of every refined triangle, as `Uint32Array`.
    #[wasm_bindgen(js_name = triangleFace)]
    pub fn triangle_face(&self) -> Result<Vec<u32>, Thrown> {
        Ok(self.param_ref()?.cut().triangle_face.clone())
    }

    /// The latest solution: per refined triangle, its three corners' uv in its face's
    /// chart (u0 v0 u1 v1 u2 v2), as `Float32Array`.
    #[wasm_bindgen(js_name = cornerUv)]
    pub fn corner_uv(&self) -> Result<Vec<f32>, Thrown> {
        Ok(self.param_ref()?.solution().corner_uv.iter().flatten().flat_map(|u| u.map(|c| c as f32)).collect())
    }

    /// ‖JᵀJ − I‖²_F of every refined triangle in the latest solution, as `Float32Array`.
    #[wasm_bindgen(js_name = triangleDistortion)]
    pub fn triangle_distortion(&self) -> Result<Vec<f32>, Thrown> {
        Ok(self.param_ref()?.triangle_distortion().into_iter().map(|d| d as f32).collect())
    }

    /// Per layout face of the active run, with its latest solution: area, enclosed
    /// curvature, distortion, typical length error and a suggested vertex for a new node
    /// where one would help (the report's `faces`; see `guidance.rs`). Faces far more
    /// distorted than the others are judged at the default edge length.
    #[wasm_bindgen(js_name = faceGuidance)]
    pub fn face_guidance(&self) -> Result<JsValue, Thrown> {
        let run = self.param.as_ref().ok_or_else(Thrown::no_param)?;
        let mesh = &self.loaded.mesh;
        let faces = run.layout.faces.len();
        let measured = face_distortion(&run.param, faces);
        let areas = face_areas(run.param.cut(), faces);
        let distorted = distorted_faces(&areas, &measured, default_edge_length(mesh));
        to_js(&solved_face_guidance(mesh, &run.layout, &measured, &distorted))
    }

    /// Every face's chart: `[{ kind: "quad" | "rect" | "unit", corners: [[u, v] × 4] }]`.
    #[wasm_bindgen(js_name = paramCharts)]
    pub fn param_charts(&self) -> Result<JsValue, Thrown> {
        let charts: Vec<ChartView> = self
            .param_ref()?
            .charts()
            .iter()
            .map(|c| ChartView {
                kind: match c.kind {
                    ChartKind::Quad => "quad",
                    ChartKind::Rect => "rect",
                    ChartKind::Unit => "unit",
                },
                corners: c.corners(),
            })
            .collect();
        to_js(&charts)
    }

    /// The iteration history so far (0 = the initial solve), as the report's `iterations`.
    #[wasm_bindgen(js_name = paramHistory)]
    pub fn param_history(&self) -> Result<JsValue, Thrown> {
        to_js(&self.param_ref()?.history())
    }

    /// The input triangle mesh with one `vt` per triangle corner (its coordinates in the
    /// chart its triangle is parameterized in), as OBJ bytes: the file of the command
    /// line's `--param-out`.
    #[wasm_bindgen(js_name = paramObj)]
    pub fn param_obj(&self) -> Result<Vec<u8>, Thrown> {
        let run = self.param.as_ref().ok_or_else(Thrown::no_param)?;
        let mesh = &self.loaded.mesh;
        let uv: Vec<[f64; 2]> = input_corner_uv(mesh, &run.layout, &run.param).into_iter().flatten().collect();
        let tris: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        Ok(write_obj(Polygons { positions: mesh.positions(), faces: &tris, arity: 3 }, Some(&uv)))
    }

    /// The mesh refined along the layout curves (every triangle in one chart) with one `vt`
    /// per triangle corner, as OBJ bytes.
    #[wasm_bindgen(js_name = cutObj)]
    pub fn cut_obj(&self) -> Result<Vec<u8>, Thrown> {
        let p = self.param_ref()?;
        let cut = p.cut();
        let faces: Vec<u32> = cut.triangles.iter().flatten().copied().collect();
        let uv: Vec<[f64; 2]> = p.solution().corner_uv.iter().flatten().copied().collect();
        Ok(write_obj(Polygons { positions: &cut.positions, faces: &faces, arity: 3 }, Some(&uv)))
    }

    /// Extracts the quad mesh of the active run (paper Section 4) with
    /// `{ edge_length?: number, quads?: number }` (one of them; default an edge length of 1/40
    /// of the bounding-box diagonal, about surface area / edge_length² quads) and measures
    /// it. Returns the report of the command line's `--report` (cli.md); the mesh itself is
    /// read with [`quad_positions`](Self::quad_positions) and
    /// [`quad_indices`](Self::quad_indices). Uses the final solve if it ran, else the latest
    /// iteration.
    pub fn remesh(&mut self, options: JsValue) -> Result<JsValue, Thrown> {
        let opts: RemeshOptions = if options.is_undefined() || options.is_null() {
            RemeshOptions::default()
        } else {
            self::options(options, "remesh options", &["edge_length", "quads"])?
        };
        let mesh = &self.loaded.mesh;
        let (load, layout_seconds) = (self.load_seconds, self.layout_seconds);
        let run = self.param.as_mut().ok_or_else(Thrown::no_param)?;
        run.quads = None;
        let edge = match (opts.edge_length, opts.quads) {
            (Some(_), Some(_)) => return Err(Thrown::new("bad_options", "remesh options: give edge_length or quads, not both")),
            (Some(l), None) => l,
            (None, Some(n)) if n >= 1.0 && n.is_finite() => edge_length_for_quads(mesh, n),
            (None, Some(n)) => return Err(Thrown::new("bad_options", format!("remesh options: quads must be at least 1, not {n}"))),
            (None, None) => default_edge_length(mesh),
        };
        let quad_options = QuadOptions::with_edge_length(edge);
        let earlier = Seconds { load, layout: layout_seconds, parameterize: run.seconds, ..Seconds::default() };
        let (quads, mut report) = extract_and_report(mesh, &run.layout, &run.param, &quad_options, earlier)?;
        report.input.repairs = self.loaded.repairs.clone();
        let out = to_js(&report);
        run.quads = Some((quads, report));
        out
    }

    /// The last quad mesh's vertex positions, xyz interleaved, as `Float32Array`.
    #[wasm_bindgen(js_name = quadPositions)]
    pub fn quad_positions(&self) -> Result<Vec<f32>, Thrown> {
        Ok(self.quads()?.positions.iter().flat_map(|p| p.map(|c| c as f32)).collect())
    }

    /// The last quad mesh's quads, four vertex indices each (counter-clockwise seen from
    /// outside), as `Uint32Array`.
    #[wasm_bindgen(js_name = quadIndices)]
    pub fn quad_indices(&self) -> Result<Vec<u32>, Thrown> {
        Ok(self.quads()?.quads.iter().flatten().copied().collect())
    }

    /// The last report of [`remesh`](Self::remesh) of the active run.
    #[wasm_bindgen(js_name = quadReport)]
    pub fn quad_report(&self) -> Result<JsValue, Thrown> {
        let run = self.param.as_ref().ok_or_else(Thrown::no_param)?;
        to_js(&run.quads.as_ref().ok_or_else(|| Thrown::new("no_quads", "remesh first"))?.1)
    }

    /// The last quad mesh as a file: `format` is "obj" or "ply" (quads kept) or "glb" (each
    /// quad split in two triangles).
    #[wasm_bindgen(js_name = quadFile)]
    pub fn quad_file(&self, format: &str) -> Result<Vec<u8>, Thrown> {
        let q = self.quads()?;
        let faces: Vec<u32> = q.quads.iter().flatten().copied().collect();
        let polygons = Polygons { positions: &q.positions, faces: &faces, arity: 4 };
        match format {
            "obj" => Ok(write_obj(polygons, None)),
            "ply" => Ok(write_ply(polygons)),
            "glb" => Ok(write_glb(polygons)),
            _ => Err(Thrown::new("bad_options", format!("unknown quad mesh format {} (obj, ply or glb)", quoted(format)))),
        }
    }

    /// Seconds per stage of the current parameterization's solves so far, and the number of
    /// numeric factorizations: `{ assembly, symbolic, factor, solve, chart_optimization,
    /// factorizations }` (for benchmarks).
    #[wasm_bindgen(js_name = paramStages)]
    pub fn param_stages(&self) -> Result<JsValue, Thrown> {
        to_js(&self.param_ref()?.stage_times())
    }

    /// Seconds spent reading the mesh and placing the current layout: `{ load, layout }`.
    pub fn seconds(&self) -> Result<JsValue, Thrown> {
        #[derive(Serialize)]
        struct S {
            load: f64,
            layout: f64,
        }
        to_js(&S { load: self.load_seconds, layout: self.layout_seconds })
    }

    /// Puts the active parameterization aside under `name` (replacing one of that name), so
    /// several runs (e.g. unit, rect and quad charts) can be kept and switched between.
    #[wasm_bindgen(js_name = keepParam)]
    pub fn keep_param(&mut self, name: &str) -> Result<(), Thrown> {
        let run = self.param.take().ok_or_else(|| Thrown::new("no_param", "no parameterization to keep"))?;
        self.kept.retain(|(n, _)| n != name);
        self.kept.push((name.to_string(), run));
        Ok(())
    }

    /// Makes the run kept under `name` the active one (the active one is kept under
    /// `previous` if given). Returns false if there is no such run.
    #[wasm_bindgen(js_name = useParam)]
    pub fn use_param(&mut self, name: &str, previous: Option<String>) -> bool {
        let Some(at) = self.kept.iter().position(|(n, _)| n == name) else { return false };
        let (_, run) = self.kept.remove(at);
        if let (Some(prev), Some(active)) = (previous, self.param.take()) {
            self.kept.retain(|(n, _)| *n != prev);
            self.kept.push((prev, active));
        }
        self.param = Some(run);
        true
    }
}

impl Session {
    fn quads(&self) -> Result<&QuadMesh, Thrown> {
        let run = self.param.as_ref().ok_or_else(Thrown::no_param)?;
        run.quads.as_ref().map(|(q, _)| q).ok_or_else(|| Thrown::new("no_quads", "remesh first"))
    }
    fn run_mut(&mut self) -> Result<&mut Run, Thrown> {
        self.param.as_mut().ok_or_else(Thrown::no_param)
    }
    fn param_ref(&self) -> Result<&ParamSession, Thrown> {
        self.param.as_ref().map(|r| &r.param).ok_or_else(Thrown::no_param)
    }
}

/// The options of [`Session::suggest_layout`] and [`Session::cross_field`], checked: only the
/// `known` keys, `patches` a whole number from 1 to 100000, `featureAngle` in (0°, 180°),
/// `quads` 1 or more (the edge length of that many quads on `mesh`).
fn layout_options(options: JsValue, what: &str, known: &[&str], mesh: &Mesh) -> Result<(LayoutOptions, Option<usize>), Thrown> {
    let o: SuggestOptions = if options.is_undefined() || options.is_null() {
        SuggestOptions::default()
    } else {
        self::options(options, what, known)?
    };
    let mut opts = LayoutOptions::default();
    if let Some(n) = o.patches {
        if !(1.0..=100_000.0).contains(&n) || n.fract() != 0.0 {
            return Err(Thrown::new("bad_options", format!("{what}: patches must be a whole number from 1 to 100000, not {n}")));
        }
        opts.patches = Some(n as usize);
    }
    if let Some(d) = o.feature_angle {
        if !(d > 0.0 && d < 180.0) {
            return Err(Thrown::new("bad_options", format!("{what}: featureAngle must be between 0 and 180 degrees, not {d}")));
        }
        opts.feature_angle = d;
    }
    // The quads the layout will be remeshed with, where the user gave them: the proposals are
    // judged by their quads there, as `quadlay remesh --layout auto --quads N` judges them.
    if let Some(n) = o.quads {
        if !(n >= 1.0 && n.is_finite()) {
            return Err(Thrown::new("bad_options", format!("{what}: quads must be a number of quads, 1 or more, not {n}")));
        }
        opts.edge_length = Some(edge_length_for_quads(mesh, n));
    }
    let tracing = match o.tracing {
        Some(k) if !(0.0..=1000.0).contains(&k) || k.fract() != 0.0 => {
            return Err(Thrown::new("bad_options", format!("{what}: tracing must be a whole number from 0, not {k}")));
        }
        k => k.map(|k| k as usize),
    };
    Ok((opts, tracing))
}

/// Which of the proposals that `suggestLayout` made apart with `tracing` (one per tracing, in
/// order) to keep, as `suggestLayout` without it keeps them: `candidates[k]` is `{ judged,
/// curves }` as it answered, or null where it made none (its `error`, or it threw). The
/// index, or null if none was made.
#[wasm_bindgen(js_name = pickSuggestion)]
pub fn pick_suggestion(candidates: JsValue) -> Result<JsValue, Thrown> {
    #[derive(Deserialize)]
    struct Made {
        judged: Option<Judged>,
        curves: usize,
    }
    let made: Vec<Option<Made>> = serde_wasm_bindgen::from_value(candidates)
        .map_err(|e| Thrown::new("bad_options", format!("pickSuggestion: candidates must be a list of {{ judged, curves }} or null: {e}")))?;
    let summaries: Vec<_> = made.into_iter().map(|m| m.map(|m| (m.judged, m.curves))).collect();
    to_js(&pick(&summaries))
}
