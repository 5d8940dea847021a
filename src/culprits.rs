//! What an error is about, as data: the layout entries and mesh vertices it names. The
//! messages say the same in words for people (the CLI's `error:` line); programs read this
//! instead (the page draws the culprits in red), so rewording a message breaks nothing.
//!
//! Every error type of the core has a `kind()`, a stable snake_case name, and a
//! `culprits()`; the layout's errors take the layout file too (a face is named by its nodes,
//! and its sides are the file's edges between them).

use serde::Serialize;

/// The elements an error names. Indices into the layout file's lists (`nodes`, `edges`,
/// `patches`) and the mesh's vertices; `point` where the error happens between vertices
/// (two curves crossing).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Culprits {
    pub nodes: Vec<u32>,
    pub edges: Vec<u32>,
    pub patches: Vec<u32>,
    pub vertices: Vec<u32>,
    pub point: Option<[f64; 3]>,
}

impl Culprits {
    /// Names nothing.
    pub fn none() -> Culprits {
        Culprits::default()
    }

    /// Names the given nodes.
    pub fn nodes(nodes: impl IntoIterator<Item = u32>) -> Culprits {
        Culprits { nodes: nodes.into_iter().collect(), ..Culprits::default() }
    }

    /// Names the given layout edges.
    pub fn edges(edges: impl IntoIterator<Item = u32>) -> Culprits {
        Culprits { edges: edges.into_iter().collect(), ..Culprits::default() }
    }

    /// Names the given mesh vertices.
    pub fn vertices(vertices: impl IntoIterator<Item = u32>) -> Culprits {
        Culprits { vertices: vertices.into_iter().collect(), ..Culprits::default() }
    }

    /// True when nothing is named.
    pub fn is_empty(&self) -> bool {
        *self == Culprits::default()
    }
}
