//! The browser's door to the core: the only file that knows about wasm-bindgen. A
//! [`Session`] lives in the page's worker and keeps state between messages; data crosses as
//! typed arrays, summaries as plain JS objects, errors as JS `Error`s with readable text.

use crate::io::{read_mesh, LoadedMesh};
use crate::layout::{build_layout, curve, parse_layout, SurfaceLayout};
use crate::param::{ParamOptions, ParamSession};
use crate::summary::{LayoutSummary, MeshSummary};
use serde::Serialize;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
pub struct Session {
    loaded: LoadedMesh,
    layout: Option<SurfaceLayout>,
    param: Option<ParamSession>,
}

/// A layout curve as the page draws it.
#[derive(Serialize)]
struct CurveView {
    source: String,
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
}

fn to_js<T: Serialize>(value: &T) -> Result<JsValue, JsError> {
    value
        .serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .map_err(|e| JsError::new(&e.to_string()))
}

#[wasm_bindgen]
impl Session {
    /// Reads a mesh from the bytes of a file; `name` decides the format by its extension.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8], name: &str) -> Result<Session, JsError> {
        let loaded = read_mesh(bytes, name).map_err(|e| JsError::new(&format!("{name}: {e}")))?;
        Ok(Session { loaded, layout: None, param: None })
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
    pub fn summary(&self) -> Result<JsValue, JsError> {
        to_js(&MeshSummary::of(&self.loaded))
    }

    /// Places a layout file (format v1, as text) on the mesh. Returns its summary, the
    /// curves as polylines and the face of every vertex; throws the layout's error.
    #[wasm_bindgen(js_name = setLayout)]
    pub fn set_layout(&mut self, text: &str) -> Result<JsValue, JsError> {
        self.layout = None;
        self.param = None;
        let mesh = &self.loaded.mesh;
        let layout = parse_layout(text).map_err(|e| JsError::new(&e.to_string()))?;
        let surface = build_layout(mesh, &layout).map_err(|e| JsError::new(&e.to_string()))?;
        let curves = surface
            .curves
            .iter()
            .map(|c| CurveView {
                source: c.source.to_string(),
                align: c.align,
                nodes: c.nodes,
                points: c.curve.points.iter().flat_map(|p| curve::position(mesh, p).map(|x| x as f32)).collect(),
            })
            .collect();
        let view = LayoutView {
            summary: LayoutSummary::of(&surface),
            curves,
            vertex_face: surface.vertex_face.iter().map(|&f| if f == u32::MAX { -1 } else { f as i32 }).collect(),
        };
        self.layout = Some(surface);
        to_js(&view)
    }

    /// Starts the parameterization of the placed layout: unit charts, every edge aligned,
    /// the initial solve (iteration 0). Returns its statistics.
    #[wasm_bindgen(js_name = startParam)]
    pub fn start_param(&mut self, align: bool) -> Result<JsValue, JsError> {
        let layout = self.layout.as_ref().ok_or_else(|| JsError::new("place a layout first"))?;
        let options = ParamOptions { align, ..ParamOptions::default() };
        let session = ParamSession::new(&self.loaded.mesh, layout, &options).map_err(|e| JsError::new(&e.to_string()))?;
        let first = session.history()[0];
        self.param = Some(session);
        to_js(&first)
    }

    /// One chart-optimization iteration (paper 3.1); returns its statistics.
    #[wasm_bindgen(js_name = stepParam)]
    pub fn step_param(&mut self) -> Result<JsValue, JsError> {
        let p = self.param.as_mut().ok_or_else(|| JsError::new("start the parameterization first"))?;
        to_js(&p.step().map_err(|e| JsError::new(&e.to_string()))?)
    }

    /// The final solve with the user's alignment tags; returns its distortion.
    #[wasm_bindgen(js_name = finishParam)]
    pub fn finish_param(&mut self) -> Result<JsValue, JsError> {
        let p = self.param.as_mut().ok_or_else(|| JsError::new("start the parameterization first"))?;
        to_js(&p.finish().map_err(|e| JsError::new(&e.to_string()))?)
    }
}
