//! The browser's door to the core: the only file that knows about wasm-bindgen. A
//! [`Session`] lives in the page's worker and keeps state between messages; data crosses as
//! typed arrays, summaries as plain JS objects, errors as JS `Error`s with readable text.

use crate::io::{read_mesh, LoadedMesh};
use crate::summary::MeshSummary;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
pub struct Session {
    loaded: LoadedMesh,
}

#[wasm_bindgen]
impl Session {
    /// Reads a mesh from the bytes of a file; `name` decides the format by its extension.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8], name: &str) -> Result<Session, JsError> {
        let loaded = read_mesh(bytes, name).map_err(|e| JsError::new(&format!("{name}: {e}")))?;
        Ok(Session { loaded })
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
        let s = MeshSummary::of(&self.loaded);
        s.serialize(&serde_wasm_bindgen::Serializer::json_compatible())
            .map_err(|e| JsError::new(&e.to_string()))
    }
}

use serde::Serialize;
