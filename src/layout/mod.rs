//! The layout on the surface (paper Section 3, Fig. 3; shared/spec/layout-format.md).
//!
//! [`build_layout`] turns a layout file and a mesh into what the parameterization needs:
//! nodes on vertices, every layout edge and boundary piece as a curve on the surface,
//! the faces those curves bound (each a disk with four corners and maybe T-vertices, and a
//! chart type), and the face of every mesh vertex and triangle.

pub mod curve;
pub mod embedding;
pub mod file;
pub mod patches;

use crate::mesh::topology::topology;
use crate::mesh::{Mesh, NONE};
use curve::{meeting_point_of, trace_curve, Curve, CurvePoint, Prepared};
use embedding::{rotation, trace_faces, CurveNodes, Directed};
pub use file::{parse_layout, write_layout, ChartType, Element, Entry, Layout, LayoutFileError, Location, MeshCounts, Numbering, MAX_WAYPOINTS};
use crate::culprits::Culprits;
use std::fmt;

/// Where a curve comes from: a layout edge of the file, or a piece of a mesh boundary loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveSource {
    Edge(usize),
    Boundary { boundary_loop: usize },
}

impl fmt::Display for CurveSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveSource::Edge(i) => write!(f, "edges[{i}]"),
            CurveSource::Boundary { boundary_loop } => write!(f, "boundary loop {boundary_loop}"),
        }
    }
}

/// A layout edge or boundary piece on the surface.
#[derive(Debug, Clone)]
pub struct LayoutCurve {
    /// First and last node (indices into the layout's nodes).
    pub nodes: CurveNodes,
    pub curve: Curve,
    /// Tagged for alignment; boundary pieces always are (paper Section 3.2).
    pub align: bool,
    pub source: CurveSource,
}

/// A face of the layout, the domain of one chart.
#[derive(Debug, Clone)]
pub struct Face {
    /// The curves around the face, counter-clockwise (face on their left), starting at the
    /// first corner.
    pub pieces: Vec<Directed>,
    /// The node each piece starts from.
    pub nodes: Vec<u32>,
    /// Interior angle on the surface at each of `nodes`.
    pub angles: Vec<f64>,
    /// Positions in `nodes` of the four chart corners, increasing; `corners[0] == 0`.
    pub corners: [usize; 4],
    /// The chart type: its `patches` entry's, else the layout's `defaults.chart`.
    pub chart: ChartType,
    /// Whether `chart` comes from the face's `patches` entry (a run's default chart type,
    /// [`crate::param::ParamOptions::default_chart`], does not replace it).
    pub chart_from_patch: bool,
}

impl Face {
    /// Nodes on the face's boundary that are not corners (paper Section 3.3).
    pub fn t_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.nodes.len()).filter(|k| !self.corners.contains(k)).map(|k| self.nodes[k])
    }
    /// The pieces of side `s` (0..4), from corner `s` to corner `s + 1`.
    pub fn side(&self, s: usize) -> &[Directed] {
        let end = if s == 3 { self.pieces.len() } else { self.corners[s + 1] };
        &self.pieces[self.corners[s]..end]
    }
    pub fn corner_nodes(&self) -> [u32; 4] {
        self.corners.map(|k| self.nodes[k])
    }
    /// The chart type of a run whose default chart type is `default` (`None`: the layout's).
    pub fn chart_with_default(&self, default: Option<ChartType>) -> ChartType {
        match default {
            Some(chart) if !self.chart_from_patch => chart,
            _ => self.chart,
        }
    }
}

/// The layout on the surface: everything later stages need.
#[derive(Debug, Clone)]
pub struct SurfaceLayout {
    /// Mesh vertex of every node.
    pub node_vertex: Vec<u32>,
    /// The file's edges first (curve `i` is `edges[i]`), then the boundary pieces.
    pub curves: Vec<LayoutCurve>,
    pub faces: Vec<Face>,
    /// Face of every mesh vertex; [`NONE`] for nodes (they belong to all faces around them)
    /// and for vertices no triangle uses.
    pub vertex_face: Vec<u32>,
    /// The face in whose chart each triangle is parameterized: the face of its first
    /// vertex that is not a node, else the face its first corner's sector lies in.
    pub triangle_face: Vec<u32>,
}

impl SurfaceLayout {
    pub fn t_vertex_count(&self) -> usize {
        self.faces.iter().map(|f| f.nodes.len() - 4).sum()
    }
}

/// Why a layout does not make quads on this mesh; each names what is at fault.
#[derive(Debug, Clone, PartialEq)]
pub enum LayoutError {
    File(LayoutFileError),
    /// No path on the surface for an edge (other component, or walled in by nodes).
    NoPath { edge: usize, reason: String },
    CurvesMeet { a: CurveSource, b: CurveSource, at: [f64; 3] },
    ComponentWithoutNodes { component: usize, first_vertex: u32 },
    BoundaryLoopNodes { boundary_loop: usize, nodes: usize, first_vertex: u32 },
    NodeOnNoEdge { node: usize },
    /// The curve has the same face on both sides (a dangling edge or a slit).
    SameFaceBothSides { curve: CurveSource },
    FaceTooFewNodes { nodes: Vec<u32> },
    FaceNotDisk { nodes: Vec<u32>, reason: String },
    PatchNotAFace { patch: usize, reason: String },
    /// The layout is fine but the mesh cannot carry it (a face with no vertex inside).
    TooCoarse { nodes: Vec<u32> },
}

fn node_list(nodes: &[u32]) -> String {
    nodes.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LayoutError::File(e) => write!(f, "{e}"),
            LayoutError::NoPath { edge, reason } => write!(f, "edges[{edge}]: no path on the surface ({reason})"),
            LayoutError::CurvesMeet { a, b, at } => write!(
                f,
                "{a} and {b}: the curves meet away from the nodes, at ({:.6}, {:.6}, {:.6})",
                at[0], at[1], at[2]
            ),
            LayoutError::ComponentWithoutNodes { component, first_vertex } => write!(
                f,
                "mesh component {component} (with vertex {first_vertex}) has no nodes; every part of the surface needs some"
            ),
            LayoutError::BoundaryLoopNodes { boundary_loop, nodes, first_vertex } => write!(
                f,
                "boundary loop {boundary_loop} (through vertex {first_vertex}) carries {nodes} node(s); it needs at least 2"
            ),
            LayoutError::NodeOnNoEdge { node } => write!(f, "nodes[{node}]: no edge or boundary reaches this node"),
            LayoutError::SameFaceBothSides { curve } => write!(
                f,
                "{curve}: the same face lies on both sides of this curve (it dangles or cuts a slit); faces must be disks"
            ),
            LayoutError::FaceTooFewNodes { nodes } => write!(
                f,
                "the face with nodes {} has {} node(s); a face needs at least 4",
                node_list(nodes),
                nodes.len()
            ),
            LayoutError::FaceNotDisk { nodes, reason } => {
                write!(f, "the face with nodes {} is not a disk: {reason}", node_list(nodes))
            }
            LayoutError::PatchNotAFace { patch, reason } => write!(f, "patches[{patch}]: {reason}"),
            LayoutError::TooCoarse { nodes } => write!(
                f,
                "the face with nodes {} has no mesh vertex inside; the mesh is too coarse for it",
                node_list(nodes)
            ),
        }
    }
}

impl std::error::Error for LayoutError {}

impl CurveSource {
    /// The index of the file's edge this curve is, or `None` for a boundary piece.
    pub fn edge(self) -> Option<u32> {
        match self {
            CurveSource::Edge(i) => Some(i as u32),
            CurveSource::Boundary { .. } => None,
        }
    }
}

impl LayoutError {
    /// A stable snake_case name of the rule that failed, for programs (the page).
    pub fn kind(&self) -> &'static str {
        match self {
            LayoutError::File(e) => e.kind(),
            LayoutError::NoPath { .. } => "no_path",
            LayoutError::CurvesMeet { .. } => "curves_meet",
            LayoutError::ComponentWithoutNodes { .. } => "component_without_nodes",
            LayoutError::BoundaryLoopNodes { .. } => "boundary_loop_nodes",
            LayoutError::NodeOnNoEdge { .. } => "node_on_no_edge",
            LayoutError::SameFaceBothSides { .. } => "same_face_both_sides",
            LayoutError::FaceTooFewNodes { .. } => "face_too_few_nodes",
            LayoutError::FaceNotDisk { .. } => "face_not_disk",
            LayoutError::PatchNotAFace { .. } => "patch_not_a_face",
            LayoutError::TooCoarse { .. } => "face_too_coarse",
        }
    }

    /// What the error names in `layout`, the file it is about: a face brings its nodes and
    /// its sides (the file's edges between two of them), a patch its corners, a mesh
    /// component or boundary loop one of its vertices.
    pub fn culprits(&self, layout: &Layout) -> Culprits {
        let face = |nodes: &[u32]| Culprits {
            nodes: nodes.to_vec(),
            edges: (0..layout.edges.len() as u32)
                .filter(|&i| layout.edges[i as usize].nodes.iter().all(|n| nodes.contains(n)))
                .collect(),
            ..Culprits::none()
        };
        match self {
            LayoutError::File(e) => e.culprits(),
            LayoutError::NoPath { edge, .. } => Culprits::edges([*edge as u32]),
            LayoutError::CurvesMeet { a, b, at } => {
                Culprits { edges: [a, b].into_iter().filter_map(|s| s.edge()).collect(), point: Some(*at), ..Culprits::none() }
            }
            LayoutError::ComponentWithoutNodes { first_vertex, .. } | LayoutError::BoundaryLoopNodes { first_vertex, .. } => {
                Culprits::vertices([*first_vertex])
            }
            LayoutError::NodeOnNoEdge { node } => Culprits::nodes([*node as u32]),
            LayoutError::SameFaceBothSides { curve } => Culprits::edges(curve.edge()),
            LayoutError::FaceTooFewNodes { nodes } | LayoutError::FaceNotDisk { nodes, .. } | LayoutError::TooCoarse { nodes } => {
                face(nodes)
            }
            LayoutError::PatchNotAFace { patch, .. } => Culprits {
                nodes: layout.patches.get(*patch).map_or_else(Vec::new, |p| p.corners.to_vec()),
                patches: vec![*patch as u32],
                ..Culprits::none()
            },
        }
    }
}

impl From<LayoutFileError> for LayoutError {
    fn from(e: LayoutFileError) -> Self {
        LayoutError::File(e)
    }
}

/// Places `layout` on `mesh`: traces curves, finds faces, corners, T-vertices and patches.
///
/// # Errors
/// Every rule of the layout format; see [`LayoutError`].
pub fn build_layout(mesh: &Mesh, layout: &Layout) -> Result<SurfaceLayout, LayoutError> {
    build_layout_on(mesh, layout, Numbering::of(mesh))
}

/// [`build_layout`] on a mesh made from the file's by the repairs the user asked for
/// (`--keep-largest`, `--fill-holes`) and by refinement ([`crate::mesh::refine_coarse`]):
/// the vertex numbering is `numbering`'s, so a layout drawn on the file's mesh or on the
/// repaired one is accepted (its `mesh` entry may name either).
///
/// # Errors
/// Every rule of the layout format; see [`LayoutError`].
pub fn build_layout_on(mesh: &Mesh, layout: &Layout, numbering: Numbering) -> Result<SurfaceLayout, LayoutError> {
    place(mesh, layout, numbering)?.with_patches(mesh, layout)
}

/// A layout placed on the surface up to its faces' corners: all that its `patches` and
/// default chart do not change. Tracing the curves is most of a placement's time, so a
/// producer of layouts that picks the corners from the placed faces ([`crate::field`])
/// places once and sets the corners with [`Placement::with_patches`].
pub struct Placement {
    node_vertex: Vec<u32>,
    curves: Vec<LayoutCurve>,
    traced: Vec<embedding::TracedFace>,
    rot: embedding::Rotation,
    /// Per vertex: the curve running through it, or [`NONE`].
    on_curve: Vec<u32>,
    /// Per vertex: the face of its region, or [`NONE`] (nodes and curves).
    region_face: Vec<u32>,
}

/// The first stage of [`build_layout_on`]: curves, faces and their regions, all but the
/// corners.
///
/// # Errors
/// Every rule of the layout format but those of `patches`; see [`LayoutError`].
pub fn place(mesh: &Mesh, layout: &Layout, numbering: Numbering) -> Result<Placement, LayoutError> {
    layout.check_mesh(&[numbering.as_read, numbering.numbered])?;
    let indexed = numbering.numbered.vertices;
    let node_vertex = file::resolve_nodes(mesh, layout, indexed)?;
    let mut is_node = vec![false; mesh.n_vertices()];
    for &v in &node_vertex {
        is_node[v as usize] = true;
    }
    let node_of = |v: u32| node_vertex.iter().position(|&x| x == v).map(|n| n as u32);

    let topo = topology(mesh);
    let mut component_has_node = vec![false; topo.components.len()];
    for &v in &node_vertex {
        component_has_node[topo.vertex_component[v as usize] as usize] = true;
    }
    if let Some(c) = component_has_node.iter().position(|&has| !has) {
        let first_vertex = topo.vertex_component.iter().position(|&x| x == c as u32).unwrap_or(0) as u32;
        return Err(LayoutError::ComponentWithoutNodes { component: c, first_vertex });
    }

    let mut curves = Vec::new();
    for (i, e) in layout.edges.iter().enumerate() {
        let mut stops = vec![node_vertex[e.nodes[0] as usize]];
        for (k, w) in e.via.iter().enumerate() {
            let entry = format!("edges[{i}].via[{k}]");
            let v = file::resolve_location(mesh, w, &entry, indexed).map_err(|e| e.within(Element::Edge(i as u32)))?;
            if let Some(n) = node_of(v) {
                let reason = format!("waypoint {k} lies on node {n}; curves may meet only at their own ends");
                return Err(LayoutError::NoPath { edge: i, reason });
            }
            stops.push(v);
        }
        stops.push(node_vertex[e.nodes[1] as usize]);
        let curve = trace_curve(mesh, &stops, &is_node)
            .map_err(|err| LayoutError::NoPath { edge: i, reason: err.to_string() })?;
        curves.push(LayoutCurve { nodes: e.nodes, curve, align: e.align, source: CurveSource::Edge(i) });
    }
    for (l, lp) in topo.boundary_loops.iter().enumerate() {
        // Boundary halfedges have the hole on their left: walk their twins backwards so
        // the mesh is on the left of every boundary piece.
        let verts: Vec<u32> = lp.iter().rev().map(|&h| mesh.to_vertex(h)).collect();
        let on_loop: Vec<usize> = (0..verts.len()).filter(|&k| is_node[verts[k] as usize]).collect();
        if on_loop.len() < 2 {
            let (boundary_loop, nodes, first_vertex) = (l, on_loop.len(), verts[0]);
            return Err(LayoutError::BoundaryLoopNodes { boundary_loop, nodes, first_vertex });
        }
        for (k, &start) in on_loop.iter().enumerate() {
            let end = on_loop[(k + 1) % on_loop.len()];
            let len = (end + verts.len() - start) % verts.len();
            let pts: Vec<u32> = (0..=len).map(|s| verts[(start + s) % verts.len()]).collect();
            let length = pts
                .windows(2)
                .map(|w| crate::geom::norm(crate::geom::sub(mesh.position(w[1]), mesh.position(w[0]))))
                .sum();
            let nodes = [node_of(pts[0]).unwrap_or(0), node_of(pts[len]).unwrap_or(0)];
            let curve = Curve { points: pts.into_iter().map(CurvePoint::Vertex).collect(), length };
            curves.push(LayoutCurve { nodes, curve, align: true, source: CurveSource::Boundary { boundary_loop: l } });
        }
    }
    check_meetings(mesh, &curves, &node_vertex)?;

    let mut reached = vec![false; node_vertex.len()];
    for c in &curves {
        reached[c.nodes[0] as usize] = true;
        reached[c.nodes[1] as usize] = true;
    }
    if let Some(node) = reached.iter().position(|&r| !r) {
        return Err(LayoutError::NodeOnNoEdge { node });
    }

    let pairs: Vec<(CurveNodes, &Curve)> = curves.iter().map(|c| (c.nodes, &c.curve)).collect();
    let rot = rotation(mesh, &node_vertex, &pairs).map_err(|c| LayoutError::NoPath {
        edge: c as usize,
        reason: "the traced curve does not leave its node through a neighbouring triangle".into(),
    })?;
    let is_hole = |d: &Directed| !d.forward && matches!(curves[d.curve as usize].source, CurveSource::Boundary { .. });
    let traced: Vec<_> = trace_faces(&rot, &pairs).into_iter().filter(|f| !f.pieces.iter().any(is_hole)).collect();

    for f in &traced {
        for (k, d) in f.pieces.iter().enumerate() {
            if f.pieces[k + 1..].iter().any(|o| o.curve == d.curve) {
                return Err(LayoutError::SameFaceBothSides { curve: curves[d.curve as usize].source });
            }
        }
        let mut sorted = f.nodes.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            let reason = format!("its boundary passes node {} twice", w[0]);
            return Err(LayoutError::FaceNotDisk { nodes: f.nodes.clone(), reason });
        }
        if f.nodes.len() < 4 {
            return Err(LayoutError::FaceTooFewNodes { nodes: f.nodes.clone() });
        }
    }

    // Patches: flood regions inside faces; each face must own its regions alone, each a disk.
    let cuts = patches::cuts(mesh, &node_vertex, &pairs);
    let (region, n_regions) = patches::regions(mesh, &cuts);
    let piece_lists: Vec<Vec<Directed>> = traced.iter().map(|f| f.pieces.clone()).collect();
    let face_regions = patches::face_regions(mesh, &pairs, &piece_lists, &region);
    let chi = patches::region_euler(mesh, &cuts, &region, n_regions);
    let mut region_face = vec![NONE; n_regions];
    for (fi, rs) in face_regions.iter().enumerate() {
        if rs.is_empty() {
            return Err(LayoutError::TooCoarse { nodes: traced[fi].nodes.clone() });
        }
        for &r in rs {
            if region_face[r as usize] != NONE {
                let reason = "its inside is also inside another face (an edge loop without nodes inside?)".to_string();
                return Err(LayoutError::FaceNotDisk { nodes: traced[fi].nodes.clone(), reason });
            }
            region_face[r as usize] = fi as u32;
            if chi[r as usize] != 1 {
                let reason = format!(
                    "its inside has Euler characteristic {} (a disk has 1): a hole, a handle or a boundary without nodes",
                    chi[r as usize]
                );
                return Err(LayoutError::FaceNotDisk { nodes: traced[fi].nodes.clone(), reason });
            }
        }
    }
    if let Some(r) = region_face.iter().position(|&f| f == NONE) {
        let v = region.iter().position(|&x| x == r as u32).unwrap_or(0);
        let reason = format!("the part of the surface around vertex {v} is enclosed by no face");
        return Err(LayoutError::FaceNotDisk { nodes: Vec::new(), reason });
    }

    let region_face = region.iter().map(|&r| if r == NONE { NONE } else { region_face[r as usize] }).collect();
    Ok(Placement { node_vertex, curves, traced, rot, on_curve: cuts.on_curve, region_face })
}

impl Placement {
    /// The placed layout with the corners and charts of `layout`'s `patches` (and its
    /// default chart): the second stage of [`build_layout_on`]. `layout` differs from the
    /// one placed at most in those.
    ///
    /// # Errors
    /// [`LayoutError::PatchNotAFace`] for a `patches` entry that names no face.
    pub fn with_patches(&self, mesh: &Mesh, layout: &Layout) -> Result<SurfaceLayout, LayoutError> {
        let faces = choose_corners(layout, self.traced.clone())?;
        let face_left_of = |d: Directed| faces.iter().position(|f| f.pieces.contains(&d)).map_or(NONE, |i| i as u32);
        let mut vertex_face = self.region_face.clone();
        for (v, &c) in self.on_curve.iter().enumerate() {
            if c != NONE {
                vertex_face[v] = face_left_of(Directed { curve: c, forward: true });
            }
        }
        let triangle_face = mesh
            .triangles()
            .iter()
            .map(|t| match t.iter().find(|&&v| vertex_face[v as usize] != NONE) {
                Some(&v) => vertex_face[v as usize],
                None => sector_face(mesh, &self.rot, &self.node_vertex, t, &face_left_of),
            })
            .collect();
        let (node_vertex, curves) = (self.node_vertex.clone(), self.curves.clone());
        Ok(SurfaceLayout { node_vertex, curves, faces, vertex_face, triangle_face })
    }
}

/// The face of a triangle whose corners are all nodes: the face whose sector at its first
/// corner contains the triangle's middle direction.
fn sector_face(
    mesh: &Mesh,
    rot: &embedding::Rotation,
    node_vertex: &[u32],
    t: &[u32; 3],
    face_left_of: &dyn Fn(Directed) -> u32,
) -> u32 {
    let Some(node) = node_vertex.iter().position(|&v| v == t[0]) else { return NONE };
    let Some(j) = mesh.outgoing(t[0]).position(|h| mesh.to_vertex(h) == t[1]) else { return NONE };
    let key = j as f64 - 0.5; // t is face(h_j), which lies between h_{j-1} and h_j
    let ring = &rot.ends[node];
    let next = ring.iter().find(|e| e.key > key).or(ring.first());
    next.map_or(NONE, |e| face_left_of(Directed { curve: e.end.curve, forward: e.end.at_start }))
}

fn check_meetings(mesh: &Mesh, curves: &[LayoutCurve], node_vertex: &[u32]) -> Result<(), LayoutError> {
    let bbox = |c: &Curve| {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &c.points {
            let q = curve::position(mesh, p);
            for k in 0..3 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        (lo, hi)
    };
    let boxes: Vec<_> = curves.iter().map(|c| bbox(&c.curve)).collect();
    let prepared: Vec<Prepared> = curves.iter().map(|c| Prepared::new(mesh, &c.curve)).collect();
    for i in 0..curves.len() {
        for j in i + 1..curves.len() {
            let ((lo_a, hi_a), (lo_b, hi_b)) = (boxes[i], boxes[j]);
            if (0..3).any(|k| lo_a[k] > hi_b[k] || lo_b[k] > hi_a[k]) {
                continue;
            }
            let ends = |c: &LayoutCurve| c.nodes.map(|n| node_vertex[n as usize]);
            let shared: Vec<u32> = ends(&curves[i]).into_iter().filter(|v| ends(&curves[j]).contains(v)).collect();
            if let Some(at) = meeting_point_of(mesh, &curves[i].curve, &prepared[i], &prepared[j], &shared) {
                return Err(LayoutError::CurvesMeet { a: curves[i].source, b: curves[j].source, at });
            }
        }
    }
    Ok(())
}

/// The first face (of faces given by their nodes in order round them) with the four
/// `corners` among its nodes counter-clockwise: the face a `patches` entry names; and whether
/// some face has them all, in whatever order.
pub fn face_named_by<'a>(faces: impl Iterator<Item = &'a [u32]>, corners: &[u32; 4]) -> (Option<usize>, bool) {
    let mut on_boundary = false;
    for (fi, nodes) in faces.enumerate() {
        let pos: Option<Vec<usize>> = corners.iter().map(|c| nodes.iter().position(|n| n == c)).collect();
        let Some(pos) = pos else { continue };
        on_boundary = true;
        // Counter-clockwise: positions increase cyclically from the first corner.
        let rel: Vec<usize> = pos.iter().map(|&k| (k + nodes.len() - pos[0]) % nodes.len()).collect();
        if rel.windows(2).all(|w| w[0] < w[1]) {
            return (Some(fi), true);
        }
    }
    (None, on_boundary)
}

/// Corners per face: from the file's `patches` entry, else the four nodes with the
/// smallest interior angle; and the chart type.
fn choose_corners(layout: &Layout, traced: Vec<embedding::TracedFace>) -> Result<Vec<Face>, LayoutError> {
    let mut entry_of = vec![None; traced.len()];
    for (p, spec) in layout.patches.iter().enumerate() {
        let (counter_clockwise, on_boundary) = face_named_by(traced.iter().map(|f| &f.nodes[..]), &spec.corners);
        let reason = match (counter_clockwise, on_boundary) {
            (Some(fi), _) if entry_of[fi].is_none() => {
                entry_of[fi] = Some(p);
                continue;
            }
            (Some(_), _) => "another patches entry names the same face",
            (None, true) => "the corners are nodes of a face, but not listed counter-clockwise",
            (None, false) => "no face has these four nodes on its boundary",
        };
        return Err(LayoutError::PatchNotAFace { patch: p, reason: reason.to_string() });
    }
    Ok(traced
        .into_iter()
        .zip(entry_of)
        .map(|(f, entry)| {
            let mut corner_pos: Vec<usize> = match entry {
                Some(p) => layout.patches[p]
                    .corners
                    .iter()
                    .filter_map(|c| f.nodes.iter().position(|n| n == c))
                    .collect(),
                None => {
                    let mut order: Vec<usize> = (0..f.nodes.len()).collect();
                    order.sort_by(|&a, &b| f.angles[a].total_cmp(&f.angles[b]));
                    order.truncate(4);
                    order
                }
            };
            corner_pos.sort_unstable();
            let from_patch = entry.and_then(|p| layout.patches[p].chart);
            let chart = from_patch.unwrap_or(layout.default_chart);
            // Start the cycle at the first corner.
            let shift = corner_pos[0];
            let (mut pieces, mut nodes, mut angles) = (f.pieces, f.nodes, f.angles);
            pieces.rotate_left(shift);
            nodes.rotate_left(shift);
            angles.rotate_left(shift);
            let corners = [0, corner_pos[1] - shift, corner_pos[2] - shift, corner_pos[3] - shift];
            Face { pieces, nodes, angles, corners, chart, chart_from_patch: from_patch.is_some() }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `patches` entry names the first face that has its corners counter-clockwise (in
    /// any rotation), not one that has them in another order.
    #[test]
    fn a_patches_entry_names_the_first_face_with_its_corners_in_order() {
        let faces: [&[u32]; 2] = [&[5, 0, 1, 2, 3], &[2, 3, 7, 0, 1]];
        assert_eq!(face_named_by(faces.into_iter(), &[0, 1, 2, 3]), (Some(0), true));
        assert_eq!(face_named_by(faces.into_iter(), &[2, 3, 0, 1]), (Some(0), true));
        assert_eq!(face_named_by(faces.into_iter(), &[7, 0, 1, 2]), (Some(1), true));
        assert_eq!(face_named_by(faces.into_iter(), &[3, 2, 1, 0]), (None, true));
        assert_eq!(face_named_by(faces.into_iter(), &[0, 1, 2, 9]), (None, false));
    }

    /// A run's default chart type replaces the layout's default, never a `patches` entry's.
    #[test]
    fn a_default_chart_type_keeps_the_patches_charts() {
        let face = |chart, chart_from_patch| Face {
            pieces: Vec::new(),
            nodes: vec![0, 1, 2, 3],
            angles: vec![1.0; 4],
            corners: [0, 1, 2, 3],
            chart,
            chart_from_patch,
        };
        let (given, defaulted) = (face(ChartType::Unit, true), face(ChartType::Quad, false));
        assert_eq!(given.chart_with_default(Some(ChartType::Rect)), ChartType::Unit);
        assert_eq!(defaulted.chart_with_default(Some(ChartType::Rect)), ChartType::Rect);
        assert_eq!(defaulted.chart_with_default(None), ChartType::Quad);
        assert_eq!(given.chart_with_default(None), ChartType::Unit);
    }
}
