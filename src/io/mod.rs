//! Mesh files in and out, from and to bytes (so the browser needs no file system).
//!
//! Readers: OBJ, PLY (ASCII and binary), STL (ASCII and binary), glTF 2.0 / GLB.
//! Writers: OBJ (triangles or quads, optional per-corner `vt`), PLY, GLB.
//! Every reader returns a [`ReadError`] that names the place in the file; none panics.

pub mod gltf;
pub mod obj;
pub mod ply;
pub mod stl;
mod text;
mod weld;

use crate::mesh::{build_mesh, refine_coarse, Mesh, MeshError, Repairs, TriangleSoup};
use crate::quote::quoted;
use std::fmt;

/// File formats quadlay reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    Obj,
    Ply,
    Stl,
    Gltf,
}

impl Format {
    /// The format named by a file name's extension.
    pub fn from_name(name: &str) -> Option<Format> {
        let ext = name.rsplit('.').next()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "stl" => Some(Format::Stl),
            "gltf" | "glb" => Some(Format::Gltf),
            _ => None,
        }
    }

    /// What a face of the soup is called in this format's files, for error messages.
    fn face_unit(self) -> &'static str {
        match self {
            Format::Obj => "line",
            Format::Ply => "face",
            Format::Stl => "facet",
            Format::Gltf => "triangle",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Gltf => "glTF",
        })
    }
}

/// Why a file could not be read as a mesh.
#[derive(Debug, Clone, PartialEq)]
pub enum ReadError {
    /// The name has no extension quadlay knows.
    UnknownFormat { name: String },
    /// A text file is wrong at `line` (1-based).
    Syntax { format: Format, line: usize, message: String },
    /// A binary file or a declared count ends early, or the structure is wrong.
    Invalid { format: Format, message: String },
    /// The data parsed but is not a valid mesh; `location` is where the face came from.
    Mesh { error: MeshError, location: Option<String> },
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::UnknownFormat { name } => write!(
                f,
                "cannot tell the format of {}: expected .obj, .ply, .stl, .gltf or .glb",
                quoted(name)
            ),
            ReadError::Syntax { format, line, message } => write!(f, "{format} line {line}: {message}"),
            ReadError::Invalid { format, message } => write!(f, "{format}: {message}"),
            ReadError::Mesh { error, location: Some(loc) } => write!(f, "{error} ({loc})"),
            ReadError::Mesh { error, location: None } => write!(f, "{error}"),
        }
    }
}

impl std::error::Error for ReadError {}

impl ReadError {
    /// A stable snake_case name of the error, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self {
            ReadError::UnknownFormat { .. } => "unknown_format",
            ReadError::Syntax { .. } => "read_syntax",
            ReadError::Invalid { .. } => "read_invalid",
            ReadError::Mesh { .. } => "bad_mesh",
        }
    }
}

/// A soup as a reader produced it, with where each triangle came from in the file.
pub(crate) struct ReadSoup {
    pub soup: TriangleSoup,
    /// Per triangle: the file's own number for its face (OBJ line, PLY face, ...).
    pub origin: Vec<u32>,
}

/// A validated mesh read from a file.
#[derive(Debug, Clone)]
pub struct LoadedMesh {
    pub mesh: Mesh,
    pub repairs: Repairs,
    pub format: Format,
}

impl LoadedMesh {
    /// This mesh refined where it is coarse ([`refine_coarse`]), the refinement listed with
    /// the repairs: every command and the page work on the refined mesh, and layouts drawn on
    /// the mesh as read stay valid on it.
    pub fn refined(self) -> LoadedMesh {
        match refine_coarse(&self.mesh) {
            Some((mesh, refinements)) => {
                let repairs = Repairs {
                    refinements,
                    vertices_before_refinement: self.mesh.n_vertices(),
                    triangles_before_refinement: self.mesh.n_faces(),
                    ..self.repairs
                };
                LoadedMesh { mesh, repairs, format: self.format }
            }
            None => self,
        }
    }
}

/// Reads a mesh from `bytes`; `name` (a file name) decides the format by its extension.
///
/// # Errors
/// [`ReadError`] naming the line, face or element at fault.
pub fn read_mesh(bytes: &[u8], name: &str) -> Result<LoadedMesh, ReadError> {
    read_mesh_with_resources(bytes, name, &|_| None)
}

/// Like [`read_mesh`], with a way to fetch files a glTF refers to by relative URI.
pub fn read_mesh_with_resources(
    bytes: &[u8],
    name: &str,
    resource: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<LoadedMesh, ReadError> {
    let format =
        Format::from_name(name).ok_or_else(|| ReadError::UnknownFormat { name: name.to_string() })?;
    let read = match format {
        Format::Obj => obj::read(bytes)?,
        Format::Ply => ply::read(bytes)?,
        Format::Stl => stl::read(bytes)?,
        Format::Gltf => gltf::read(bytes, resource)?,
    };
    let origin = read.origin;
    let built = build_mesh(read.soup).map_err(|error| {
        let location = error
            .face()
            .and_then(|f| origin.get(f as usize))
            .map(|o| format!("{} {}", format.face_unit(), o));
        ReadError::Mesh { error, location }
    })?;
    Ok(LoadedMesh { mesh: built.mesh, repairs: built.repairs, format })
}

pub use write::{write_glb, write_gltf, write_obj, write_ply, Polygons};
mod write;
