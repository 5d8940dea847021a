//! The layout file, format version 1 (shared/spec/layout-format.md): reading with every
//! rule of the spec checked, writing, and resolving nodes and waypoints to mesh vertices.
//!
//! The JSON is walked by hand rather than through derived deserializers so that every
//! error names its entry (`edges[3].via[0]: ...`) and says what was expected.

use crate::culprits::Culprits;
use crate::mesh::Mesh;
use crate::quote::quoted;
use serde_json::{json, Map, Value};
use std::fmt;

/// Where a node or waypoint sits: a mesh vertex, or a point snapped to the nearest vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Location {
    /// A vertex index as the file gives it (u64: an index past the mesh's is refused when
    /// the layout is placed, with the mesh's real vertex count).
    Vertex(u64),
    Point([f64; 3]),
}

/// Chart type of a layout face (paper, Section 3 and 3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ChartType {
    /// General quadrilateral, 5 degrees of freedom.
    #[default]
    Quad,
    /// Rectangle, 2 degrees of freedom (width, height).
    Rect,
    /// Unit square, no degrees of freedom.
    Unit,
}

impl ChartType {
    pub fn parse(s: &str) -> Option<ChartType> {
        match s {
            "quad" => Some(ChartType::Quad),
            "rect" => Some(ChartType::Rect),
            "unit" => Some(ChartType::Unit),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            ChartType::Quad => "quad",
            ChartType::Rect => "rect",
            ChartType::Unit => "unit",
        }
    }
}

/// From its name, as in a layout file (`"quad"`, `"rect"`, `"unit"`), with the file's message
/// for any other.
impl<'de> serde::Deserialize<'de> for ChartType {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        ChartType::parse(&name).ok_or_else(|| serde::de::Error::custom(err("", Problem::UnknownChart(name))))
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct EdgeSpec {
    pub nodes: [u32; 2],
    pub align: bool,
    pub via: Vec<Location>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PatchSpec {
    /// Four node indices, counter-clockwise around the face.
    pub corners: [u32; 4],
    pub chart: Option<ChartType>,
}

/// The most waypoints (`via` entries) a layout may have in all. Each is the end of a
/// geodesic leg traced over the mesh (a few milliseconds on a mesh of 30,000 vertices), so
/// this bounds the time a layout takes to place to seconds; the sample layouts have up to
/// 574, a hand-drawn one rarely more than a few per edge.
pub const MAX_WAYPOINTS: usize = 4096;
/// The size of a mesh, as a layout's `mesh` entry records it: the identity of the mesh the
/// layout was drawn on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct MeshCounts {
    pub vertices: usize,
    pub triangles: usize,
}

impl MeshCounts {
    /// The counts of `mesh` (every vertex of the numbering, used or not).
    pub fn of(mesh: &Mesh) -> MeshCounts {
        MeshCounts { vertices: mesh.n_vertices(), triangles: mesh.n_faces() }
    }
}

/// The meshes whose vertex numbering a layout file may use on the mesh at hand: the file as
/// read, and the mesh as numbered after the repairs the user asked for (which number new
/// vertices after the file's). The mesh worked on may have more vertices past those
/// ([`crate::mesh::refine_coarse`]): a file names them by their points
/// ([`Layout::in_numbering`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Numbering {
    pub as_read: MeshCounts,
    pub numbered: MeshCounts,
}

impl Numbering {
    /// The numbering of `mesh` itself: every vertex by its index.
    pub fn of(mesh: &Mesh) -> Numbering {
        Numbering { as_read: MeshCounts::of(mesh), numbered: MeshCounts::of(mesh) }
    }
}

impl fmt::Display for MeshCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} vertices and {} triangles", self.vertices, self.triangles)
    }
}

/// A layout as the file states it (nodes not yet snapped to the mesh).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Layout {
    pub nodes: Vec<Location>,
    pub edges: Vec<EdgeSpec>,
    pub patches: Vec<PatchSpec>,
    pub default_chart: ChartType,
    /// The counts of the mesh the layout was drawn on, if the file says.
    pub mesh: Option<MeshCounts>,
}

impl Layout {
    /// Whether any node or waypoint is given by a vertex index (which means something only
    /// on the mesh the layout was drawn on).
    pub fn uses_vertex_indices(&self) -> bool {
        let vertex = |l: &Location| matches!(l, Location::Vertex(_));
        self.nodes.iter().any(vertex) || self.edges.iter().flat_map(|e| &e.via).any(vertex)
    }

    /// This layout, made on `mesh`, as a file gives it in `numbering`: nodes and waypoints on
    /// vertices past the numbering by their points (snapped back to the same vertices), and
    /// the numbered mesh as its `mesh` entry.
    pub fn in_numbering(&self, mesh: &Mesh, numbering: Numbering) -> Layout {
        let named = |l: &Location| match *l {
            Location::Vertex(v) if v >= numbering.numbered.vertices as u64 && (v as usize) < mesh.n_vertices() => {
                Location::Point(mesh.position(v as u32))
            }
            _ => *l,
        };
        let mut out = self.clone();
        out.nodes = self.nodes.iter().map(named).collect();
        for e in &mut out.edges {
            e.via = e.via.iter().map(named).collect();
        }
        out.mesh = Some(numbering.numbered);
        out
    }

    /// Checks the `mesh` entry against the mesh at hand (layout-format.md, "mesh"): when the
    /// layout names vertices by index, its mesh must have the counts of one of `accepted`
    /// (the mesh, and the file it was read from before the repairs the user asked for,
    /// which keep the vertex numbering).
    ///
    /// # Errors
    /// [`Problem::OtherMesh`] on the entry `mesh`, with both counts.
    pub fn check_mesh(&self, accepted: &[MeshCounts]) -> Result<(), LayoutFileError> {
        match self.mesh {
            Some(made_for) if self.uses_vertex_indices() && !accepted.contains(&made_for) => {
                let mesh = accepted.first().copied().unwrap_or(MeshCounts { vertices: 0, triangles: 0 });
                Err(err("mesh", Problem::OtherMesh { layout: made_for, mesh }))
            }
            _ => Ok(()),
        }
    }
}

/// What is wrong with an entry of a layout file.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    Json(String),
    UnknownKey(String),
    Missing(&'static str),
    Expected(&'static str),
    WrongFormat(String),
    UnsupportedVersion(Value),
    NotFinite,
    NoSuchNode { node: u64, nodes: usize },
    NoSuchVertex { vertex: u64, vertices: usize },
    /// The vertex belongs to no face of the mesh.
    IsolatedVertex { vertex: u32 },
    SameVertex { vertex: u32, other: usize },
    SelfLoop,
    UnknownChart(String),
    RepeatedCorner(u32),
    /// The layout's waypoints, counted up to this entry, are more than [`MAX_WAYPOINTS`].
    TooManyWaypoints,
    /// The layout names vertices by index and was drawn on a mesh of other counts.
    OtherMesh { layout: MeshCounts, mesh: MeshCounts },
}

/// A layout error: the entry it is about and the problem.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutFileError {
    pub entry: Entry,
    pub problem: Problem,
}

/// Where in a layout file an error is: the path its message names (`nodes[2]`,
/// `edges[3].via[0]`, empty for the whole document), and as data the node, edge or patch
/// that path is in (`None` for the document's own keys).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Entry {
    path: String,
    element: Option<Element>,
}

impl Entry {
    pub fn as_str(&self) -> &str {
        &self.path
    }

    pub fn is_empty(&self) -> bool {
        self.path.is_empty()
    }

    /// The node, edge or patch the entry is in.
    pub fn element(&self) -> Option<Element> {
        self.element
    }
}

impl fmt::Display for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.path)
    }
}

impl PartialEq<str> for Entry {
    fn eq(&self, path: &str) -> bool {
        self.path == path
    }
}

impl PartialEq<&str> for Entry {
    fn eq(&self, path: &&str) -> bool {
        self.path == *path
    }
}

/// A node, edge or patch of a layout file, by its index in its list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    Node(u32),
    Edge(u32),
    Patch(u32),
}

impl LayoutFileError {
    /// The error as found inside `element` (kept if it already names one).
    pub(crate) fn within(mut self, element: Element) -> Self {
        self.entry.element.get_or_insert(element);
        self
    }

    /// A stable snake_case name of the problem, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self.problem {
            Problem::Json(_) => "not_json",
            Problem::UnknownKey(_) => "unknown_key",
            Problem::Missing(_) => "missing_key",
            Problem::Expected(_) => "wrong_type",
            Problem::WrongFormat(_) => "wrong_format",
            Problem::UnsupportedVersion(_) => "unsupported_version",
            Problem::NotFinite => "not_finite",
            Problem::NoSuchNode { .. } => "no_such_node",
            Problem::NoSuchVertex { .. } => "no_such_vertex",
            Problem::IsolatedVertex { .. } => "isolated_vertex",
            Problem::SameVertex { .. } => "same_vertex",
            Problem::SelfLoop => "self_loop",
            Problem::UnknownChart(_) => "unknown_chart",
            Problem::RepeatedCorner(_) => "repeated_corner",
            Problem::TooManyWaypoints => "too_many_waypoints",
            Problem::OtherMesh { .. } => "other_mesh",
        }
    }

    /// The element the error is in, and the node and mesh vertex a node shares.
    pub fn culprits(&self) -> Culprits {
        let mut c = Culprits::none();
        match self.entry.element {
            Some(Element::Node(i)) => c.nodes.push(i),
            Some(Element::Edge(i)) => c.edges.push(i),
            Some(Element::Patch(i)) => c.patches.push(i),
            None => {}
        }
        match self.problem {
            Problem::SameVertex { vertex, other } => {
                c.nodes.push(other as u32);
                c.vertices.push(vertex);
            }
            Problem::IsolatedVertex { vertex } => c.vertices.push(vertex),
            _ => {}
        }
        c
    }
}

impl fmt::Display for LayoutFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.entry.is_empty() {
            write!(f, "{}: ", self.entry)?;
        }
        match &self.problem {
            Problem::Json(e) => write!(f, "not valid JSON: {e}"),
            Problem::UnknownKey(k) => write!(f, "unknown key {}", quoted(k)),
            Problem::Missing(k) => write!(f, "missing '{k}'"),
            Problem::Expected(what) => write!(f, "expected {what}"),
            Problem::WrongFormat(s) => write!(f, "format is {}, expected 'quad-layout'", quoted(s)),
            Problem::UnsupportedVersion(v) => {
                // A number as it is; anything else (a string of megabytes) quoted.
                let v = if v.is_number() { v.to_string() } else { quoted(&v.to_string()) };
                write!(f, "version {v} is not supported (this reader knows version 1)")
            },
            Problem::NotFinite => write!(f, "coordinates must be finite numbers"),
            Problem::NoSuchNode { node, nodes } => write!(f, "node {node} does not exist ({nodes} nodes)"),
            Problem::NoSuchVertex { vertex, vertices } => {
                write!(f, "vertex {vertex} does not exist (the mesh has {vertices} vertices)")
            }
            Problem::IsolatedVertex { vertex } => write!(f, "vertex {vertex} belongs to no triangle"),
            Problem::SameVertex { vertex, other } => {
                write!(f, "on mesh vertex {vertex}, like nodes[{other}]")
            }
            Problem::SelfLoop => write!(f, "an edge must join two different nodes"),
            Problem::UnknownChart(c) => write!(f, "unknown chart type {} (quad, rect or unit)", quoted(c)),
            Problem::RepeatedCorner(n) => write!(f, "node {n} is named twice as a corner"),
            Problem::TooManyWaypoints => write!(
                f,
                "the layout has more than {MAX_WAYPOINTS} waypoints up to here; a curve needs a waypoint only where \
                 it must not take the shortest way, so remove some"
            ),
            Problem::OtherMesh { layout, mesh } => write!(
                f,
                "the layout was made for another mesh: it was drawn on a mesh of {layout}, this mesh has {mesh}"
            ),
        }
    }
}

impl std::error::Error for LayoutFileError {}

fn err(entry: impl Into<String>, problem: Problem) -> LayoutFileError {
    LayoutFileError { entry: Entry { path: entry.into(), element: None }, problem }
}

/// An object's fields, refusing keys outside `allowed`.
fn object<'a>(
    v: &'a Value,
    entry: &str,
    allowed: &[&str],
    what: &'static str,
) -> Result<&'a Map<String, Value>, LayoutFileError> {
    let obj = v.as_object().ok_or_else(|| err(entry, Problem::Expected(what)))?;
    if let Some(k) = obj.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(err(entry, Problem::UnknownKey(k.clone())));
    }
    Ok(obj)
}

fn array<'a>(v: &'a Value, entry: &str, what: &'static str) -> Result<&'a Vec<Value>, LayoutFileError> {
    v.as_array().ok_or_else(|| err(entry, Problem::Expected(what)))
}

fn index(v: &Value, entry: &str) -> Result<u64, LayoutFileError> {
    v.as_u64().ok_or_else(|| err(entry, Problem::Expected("a non-negative whole number")))
}

fn node_index(v: &Value, entry: &str, nodes: usize) -> Result<u32, LayoutFileError> {
    let n = index(v, entry)?;
    if n >= nodes as u64 {
        return Err(err(entry, Problem::NoSuchNode { node: n, nodes }));
    }
    Ok(n as u32)
}

fn location(v: &Value, entry: &str) -> Result<Location, LayoutFileError> {
    const WHAT: &str = "{\"vertex\": i} or {\"point\": [x, y, z]}";
    let obj = object(v, entry, &["vertex", "point"], WHAT)?;
    match (obj.get("vertex"), obj.get("point")) {
        (Some(i), None) => {
            // Checked against the mesh's vertex count when the layout is placed.
            Ok(Location::Vertex(index(i, &format!("{entry}.vertex"))?))
        }
        (None, Some(p)) => {
            let e = format!("{entry}.point");
            let a = array(p, &e, "[x, y, z]")?;
            if a.len() != 3 {
                return Err(err(e, Problem::Expected("[x, y, z]")));
            }
            let mut xyz = [0.0; 3];
            for (k, c) in a.iter().enumerate() {
                // JSON has no NaN or infinity: JavaScript writes them as null, and serde_json
                // refuses literals that overflow.
                if c.is_null() {
                    return Err(err(&e, Problem::NotFinite));
                }
                xyz[k] = c.as_f64().ok_or_else(|| err(&e, Problem::Expected("[x, y, z] numbers")))?;
                if !xyz[k].is_finite() {
                    return Err(err(&e, Problem::NotFinite));
                }
            }
            Ok(Location::Point(xyz))
        }
        _ => Err(err(entry, Problem::Expected(WHAT))),
    }
}

/// `edges[i]`: two different nodes, an optional alignment tag and waypoints (`waypoints`
/// counts those of the layout so far).
fn edge(v: &Value, entry: &str, n: usize, waypoints: &mut usize) -> Result<EdgeSpec, LayoutFileError> {
    let empty = Vec::new();
    let obj = object(v, entry, &["nodes", "align", "via"], "an object")?;
    let pair = obj.get("nodes").ok_or_else(|| err(entry, Problem::Missing("nodes")))?;
    let pair = array(pair, &format!("{entry}.nodes"), "[a, b]")?;
    if pair.len() != 2 {
        return Err(err(format!("{entry}.nodes"), Problem::Expected("two node indices [a, b]")));
    }
    let a = node_index(&pair[0], entry, n)?;
    let b = node_index(&pair[1], entry, n)?;
    if a == b {
        return Err(err(entry, Problem::SelfLoop));
    }
    let align = match obj.get("align") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(_) => return Err(err(format!("{entry}.align"), Problem::Expected("true or false"))),
    };
    let via_values = match obj.get("via") {
        None => &empty[..],
        Some(v) => array(v, &format!("{entry}.via"), "an array of waypoints")?,
    };
    *waypoints += via_values.len();
    if *waypoints > MAX_WAYPOINTS {
        return Err(err(format!("{entry}.via"), Problem::TooManyWaypoints));
    }
    let via = via_values
        .iter()
        .enumerate()
        .map(|(k, w)| location(w, &format!("{entry}.via[{k}]")))
        .collect::<Result<_, _>>()?;
    Ok(EdgeSpec { nodes: [a, b], align, via })
}

/// `patches[i]`: four different corners and an optional chart type.
fn patch(p: &Value, entry: &str, n: usize) -> Result<PatchSpec, LayoutFileError> {
    let obj = object(p, entry, &["corners", "chart"], "an object")?;
    let c = obj.get("corners").ok_or_else(|| err(entry, Problem::Missing("corners")))?;
    let c = array(c, &format!("{entry}.corners"), "four node indices")?;
    if c.len() != 4 {
        return Err(err(format!("{entry}.corners"), Problem::Expected("four node indices")));
    }
    let mut corners = [0u32; 4];
    for k in 0..4 {
        corners[k] = node_index(&c[k], entry, n)?;
        if corners[..k].contains(&corners[k]) {
            return Err(err(entry, Problem::RepeatedCorner(corners[k])));
        }
    }
    let chart = obj.get("chart").map(|c| chart(c, &format!("{entry}.chart"))).transpose()?;
    Ok(PatchSpec { corners, chart })
}

fn chart(v: &Value, entry: &str) -> Result<ChartType, LayoutFileError> {
    let s = v.as_str().ok_or_else(|| err(entry, Problem::Expected("\"quad\", \"rect\" or \"unit\"")))?;
    ChartType::parse(s).ok_or_else(|| err(entry, Problem::UnknownChart(s.to_string())))
}

/// Parses a layout file and checks every rule that does not need the mesh.
///
/// # Errors
/// [`LayoutFileError`] naming the entry.
pub fn parse_layout(text: &str) -> Result<Layout, LayoutFileError> {
    let doc: Value = serde_json::from_str(text).map_err(|e| err("", Problem::Json(e.to_string())))?;
    let root =
        object(&doc, "", &["format", "version", "nodes", "edges", "patches", "defaults", "mesh"], "a JSON object")?;
    match root.get("format") {
        Some(Value::String(s)) if s == "quad-layout" => {}
        Some(Value::String(s)) => return Err(err("format", Problem::WrongFormat(s.clone()))),
        Some(_) => return Err(err("format", Problem::Expected("the string \"quad-layout\""))),
        None => return Err(err("", Problem::Missing("format"))),
    }
    match root.get("version") {
        Some(v) if v.as_u64() == Some(1) => {}
        Some(v) => return Err(err("version", Problem::UnsupportedVersion(v.clone()))),
        None => return Err(err("", Problem::Missing("version"))),
    }
    let nodes_v = root.get("nodes").ok_or_else(|| err("", Problem::Missing("nodes")))?;
    let nodes = array(nodes_v, "nodes", "an array of nodes")?
        .iter()
        .enumerate()
        .map(|(i, v)| location(v, &format!("nodes[{i}]")).map_err(|e| e.within(Element::Node(i as u32))))
        .collect::<Result<Vec<_>, _>>()?;
    let n = nodes.len();

    let mut edges = Vec::new();
    let mut waypoints = 0;
    let empty = Vec::new();
    let edge_values = match root.get("edges") {
        Some(v) => array(v, "edges", "an array of edges")?,
        None => &empty,
    };
    for (i, v) in edge_values.iter().enumerate() {
        let edge = edge(v, &format!("edges[{i}]"), n, &mut waypoints);
        edges.push(edge.map_err(|e| e.within(Element::Edge(i as u32)))?);
    }

    let mut patches = Vec::new();
    if let Some(v) = root.get("patches") {
        for (i, p) in array(v, "patches", "an array of patches")?.iter().enumerate() {
            patches.push(patch(p, &format!("patches[{i}]"), n).map_err(|e| e.within(Element::Patch(i as u32)))?);
        }
    }
    let mut default_chart = ChartType::Quad;
    if let Some(d) = root.get("defaults") {
        let obj = object(d, "defaults", &["chart"], "an object")?;
        if let Some(c) = obj.get("chart") {
            default_chart = chart(c, "defaults.chart")?;
        }
    }
    let mesh = match root.get("mesh") {
        None => None,
        Some(m) => {
            const WHAT: &str = "{\"vertices\": n, \"triangles\": m}";
            let obj = object(m, "mesh", &["vertices", "triangles"], WHAT)?;
            let count = |key: &'static str| -> Result<usize, LayoutFileError> {
                let v = obj.get(key).ok_or_else(|| err("mesh", Problem::Missing(key)))?;
                let n = index(v, &format!("mesh.{key}"))?;
                usize::try_from(n).map_err(|_| err(format!("mesh.{key}"), Problem::Expected("a smaller count")))
            };
            Some(MeshCounts { vertices: count("vertices")?, triangles: count("triangles")? })
        }
    };
    Ok(Layout { nodes, edges, patches, default_chart, mesh })
}

fn location_json(l: &Location) -> Value {
    match l {
        Location::Vertex(v) => json!({ "vertex": v }),
        Location::Point(p) => json!({ "point": p }),
    }
}

/// The layout as a version 1 file (pretty JSON). `parse_layout` reads it back unchanged.
pub fn write_layout(layout: &Layout) -> String {
    let edges: Vec<Value> = layout
        .edges
        .iter()
        .map(|e| {
            let mut o = json!({ "nodes": e.nodes });
            if e.align {
                o["align"] = json!(true);
            }
            if !e.via.is_empty() {
                o["via"] = Value::Array(e.via.iter().map(location_json).collect());
            }
            o
        })
        .collect();
    let mut doc = json!({
        "format": "quad-layout",
        "version": 1,
        "nodes": layout.nodes.iter().map(location_json).collect::<Vec<_>>(),
        "edges": edges,
    });
    if !layout.patches.is_empty() {
        doc["patches"] = Value::Array(
            layout
                .patches
                .iter()
                .map(|p| {
                    let mut o = json!({ "corners": p.corners });
                    if let Some(c) = p.chart {
                        o["chart"] = json!(c.name());
                    }
                    o
                })
                .collect(),
        );
    }
    if layout.default_chart != ChartType::Quad {
        doc["defaults"] = json!({ "chart": layout.default_chart.name() });
    }
    if let Some(m) = layout.mesh {
        doc["mesh"] = json!({ "vertices": m.vertices, "triangles": m.triangles });
    }
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}

/// The mesh vertex of a location: the vertex itself (checked: below `vertices`, the count
/// of the numbering the file uses), or the nearest vertex that belongs to a triangle.
pub fn resolve_location(mesh: &Mesh, l: &Location, entry: &str, vertices: usize) -> Result<u32, LayoutFileError> {
    match *l {
        Location::Vertex(v) => {
            let vertices = vertices.min(mesh.n_vertices());
            let Some(v) = u32::try_from(v).ok().filter(|&v| (v as usize) < vertices) else {
                return Err(err(entry, Problem::NoSuchVertex { vertex: v, vertices }));
            };
            if mesh.is_isolated(v) {
                return Err(err(entry, Problem::IsolatedVertex { vertex: v }));
            }
            Ok(v)
        }
        Location::Point(p) => {
            let d2 = |q: &[f64; 3]| (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>();
            let mut best = (f64::INFINITY, 0u32);
            for (v, q) in mesh.positions().iter().enumerate() {
                if !mesh.is_isolated(v as u32) && d2(q) < best.0 {
                    best = (d2(q), v as u32);
                }
            }
            Ok(best.1)
        }
    }
}

/// The mesh vertex of every node ([`resolve_location`]); two nodes on one vertex are an
/// error.
pub fn resolve_nodes(mesh: &Mesh, layout: &Layout, vertices: usize) -> Result<Vec<u32>, LayoutFileError> {
    let mut owner = std::collections::HashMap::new();
    let mut out = Vec::with_capacity(layout.nodes.len());
    for (i, l) in layout.nodes.iter().enumerate() {
        let entry = format!("nodes[{i}]");
        let node = Element::Node(i as u32);
        let v = resolve_location(mesh, l, &entry, vertices).map_err(|e| e.within(node))?;
        if let Some(&other) = owner.get(&v) {
            return Err(err(entry, Problem::SameVertex { vertex: v, other }).within(node));
        }
        owner.insert(v, i);
        out.push(v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"{
      "format": "quad-layout", "version": 1,
      "nodes": [ { "vertex": 120 }, { "point": [0.12, 0.5, -0.3] }, { "vertex": 3 } ],
      "edges": [
        { "nodes": [0, 1] },
        { "nodes": [1, 2], "align": true, "via": [ { "vertex": 77 }, { "point": [0.2, 0.4, 0.0] } ] }
      ],
      "patches": [ { "corners": [0, 1, 2, 0], "chart": "quad" } ],
      "defaults": { "chart": "rect" },
      "mesh": { "vertices": 6475, "triangles": 12946 }
    }"#;

    #[test]
    fn round_trip() {
        let text = EXAMPLE.replace("[0, 1, 2, 0]", "[0, 1, 2, 1]");
        assert_eq!(parse_layout(&text).unwrap_err().to_string(), "patches[0]: node 1 is named twice as a corner");
        let text = EXAMPLE.replace(r#""corners": [0, 1, 2, 0], "#, r#""corners": [0, 1, 2, 3], "#);
        let text = text.replace(r#"{ "vertex": 3 } ]"#, r#"{ "vertex": 3 }, { "vertex": 4 } ]"#);
        let l = parse_layout(&text).unwrap();
        assert_eq!(l.default_chart, ChartType::Rect);
        assert_eq!(l.edges[1].via[1], Location::Point([0.2, 0.4, 0.0]));
        assert_eq!(l.mesh, Some(MeshCounts { vertices: 6475, triangles: 12946 }));
        assert_eq!(parse_layout(&write_layout(&l)).unwrap(), l);
    }

    #[test]
    fn a_layout_for_another_mesh_is_refused_when_it_names_vertices() {
        let mut l = parse_layout(&EXAMPLE.replace("[0, 1, 2, 0]", "[0, 1, 2, 3]").replace(r#"{ "vertex": 3 } ]"#, r#"{ "vertex": 3 }, { "vertex": 4 } ]"#)).unwrap();
        let made_for = MeshCounts { vertices: 6475, triangles: 12946 };
        let other = MeshCounts { vertices: 2337, triangles: 4608 };
        assert_eq!(l.check_mesh(&[made_for]), Ok(()));
        // The repaired mesh's counts or the file's: either is this mesh.
        assert_eq!(l.check_mesh(&[other, made_for]), Ok(()));
        let e = l.check_mesh(&[other]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "mesh: the layout was made for another mesh: it was drawn on a mesh of 6475 vertices and 12946 \
             triangles, this mesh has 2337 vertices and 4608 triangles"
        );
        // Points only: the counts are informative.
        l.nodes = vec![Location::Point([0.0; 3]); 4];
        l.edges.iter_mut().for_each(|e| e.via.clear());
        assert_eq!(l.check_mesh(&[other]), Ok(()));
        l.mesh = None;
        l.nodes[0] = Location::Vertex(1);
        assert_eq!(l.check_mesh(&[other]), Ok(()));
    }

    #[test]
    fn each_rule_names_its_entry() {
        let base = r#"{"format":"quad-layout","version":1,"nodes":[{"vertex":0},{"vertex":1}],"edges":[EDGES]}"#;
        let cases = [
            (base.replace("EDGES", r#"{"nodes":[0,5]}"#), "edges[0]: node 5 does not exist (2 nodes)"),
            (base.replace("EDGES", r#"{"nodes":[1,1]}"#), "edges[0]: an edge must join two different nodes"),
            (base.replace("EDGES", r#"{"nodes":[0,1],"color":3}"#), "edges[0]: unknown key 'color'"),
            (base.replace("EDGES", r#"{"nodes":[0,1],"align":"yes"}"#), "edges[0].align: expected true or false"),
            (base.replace("EDGES", r#"{"nodes":[0,1],"via":[{"point":[0,null,0]}]}"#), "edges[0].via[0].point: coordinates must be finite numbers"),
            (base.replace("EDGES", "").replace("\"version\":1", "\"version\":2"), "version: version 2 is not supported (this reader knows version 1)"),
            (base.replace("EDGES", "").replace("quad-layout", "quad"), "format: format is 'quad', expected 'quad-layout'"),
            (base.replace("EDGES", "").replace("{\"vertex\":1}", "{\"vertex\":-1}"), "nodes[1].vertex: expected a non-negative whole number"),
            (base.replace("EDGES", "").replace("{\"vertex\":1}", "{\"vertex\":1,\"point\":[0,0,0]}"), "nodes[1]: expected {\"vertex\": i} or {\"point\": [x, y, z]}"),
            (base.replace("EDGES", "").replace("\"edges\":[]", "\"edges\":[],\"defaults\":{\"chart\":\"hex\"}"), "defaults.chart: unknown chart type 'hex' (quad, rect or unit)"),
            (base.replace("EDGES", "").replace("\"edges\":[]", "\"edges\":[],\"mesh\":{\"vertices\":3}"), "mesh: missing 'triangles'"),
            (base.replace("EDGES", "").replace("\"edges\":[]", "\"edges\":[],\"mesh\":{\"vertices\":3,\"triangles\":1.5}"), "mesh.triangles: expected a non-negative whole number"),
            (base.replace("EDGES", "").replace("\"edges\":[]", "\"edges\":[],\"mesh\":{\"vertices\":3,\"triangles\":1,\"name\":\"x\"}"), "mesh: unknown key 'name'"),
        ];
        for (text, want) in cases {
            let got = parse_layout(&text).map(|_| ()).unwrap_err().to_string();
            assert_eq!(got, want, "{text}");
        }
        assert!(parse_layout("{").unwrap_err().to_string().starts_with("not valid JSON"));
    }
}
