// The message protocol between the page (client.js) and the worker that owns the wasm
// session (worker.js). This module is the one place that states it; both sides import it.
//
// Every request is   { id, type, ...args }          page → worker
// and every reply is { id, result }                  worker → page, on success
//                 or { id, error, kind, culprits, fatal? }   worker → page, on failure
//
// `id` is a number the client picks to match a reply to its request; replies come in the
// order the requests were sent (the worker handles one message at a time). `error` is a
// readable sentence meant for the user, e.g. "x.obj: OBJ line 2: 'x' is not a number"; it
// may be reworded any time, so programs read `kind` and `culprits` instead:
//   kind      a stable snake_case name: the core's (wasm.rs: e.g. 'same_face_both_sides',
//             'patch_not_a_face', 'not_positive_definite', 'read_syntax'), or 'no_mesh' (the
//             worker has no mesh yet), 'internal' (fatal), 'stopped' (the client threw the
//             worker away), 'other'
//   culprits  what the error names, or null: { nodes, edges, patches (indices into the
//             layout file's lists), vertices (mesh vertices), point ([x, y, z] or null) }
// `fatal: true` means the wasm instance trapped (a Rust panic, out of memory) and cannot be
// trusted any more: the client throws the worker away and starts a fresh one.
//
// Large arrays travel as transferred ArrayBuffers in both directions (no copies); the sender
// must not use them afterwards.

/** Message types (`type` of a request). */
export const MSG = Object.freeze({
  /**
   * Read a mesh file and make it the worker's current mesh.
   * args:   { bytes: ArrayBuffer (transferred), name: string — its extension picks the format:
   *           .obj .ply .stl .gltf .glb }
   * result: { summary: MeshSummary, positions: Float32Array (xyz interleaved),
   *           triangles: Uint32Array (vertex index triples) }  — buffers transferred
   * On error the worker keeps its previous mesh.
   *
   * MeshSummary (the object `quadlay check` prints): { format, vertices, triangles, edges,
   *   boundary_loops, genus, components: [{ vertices, edges, faces, boundary_loops,
   *   euler_characteristic, genus }], bounding_box: [[x,y,z],[x,y,z]],
   *   repairs: { welded_vertices, removed_zero_area_faces, unreferenced_vertices } }
   */
  LOAD: 'load',
  /**
   * Place a layout (format v1, see shared/spec/layout-format.md) on the current mesh.
   * args:   { text: string — the layout file's JSON }
   * result: LayoutView { summary: { nodes, edges, aligned_edges, boundary_pieces, faces,
   *           t_vertices, charts: [quad, rect, unit], face_list: [{ corners, t_vertices,
   *           chart }] },
   *           curves: [{ source: { edge: 3 } | { boundary: 0 } (a file edge, or a piece of
   *                      a boundary loop), align, nodes: [a, b],
   *                      points: number[] (xyz interleaved) }],
   *           vertex_face: number[] (face of every mesh vertex, -1 for nodes) }
   * On error (the layout's rule that fails, naming the entry) the worker has no layout.
   */
  SET_LAYOUT: 'set-layout',
  /**
   * Start a parameterization of the placed layout (paper 3.1: every edge aligned, unit
   * charts, the initial solve = iteration 0). Replaces the active run.
   * args:   { options: { align?: boolean (default true),
   *                      chart?: 'quad' | 'rect' | 'unit' | null — chart type of faces whose
   *                              patches entry names none; null: the layout's default } }
   * result: IterationStats { iteration: 0, distortion: Distortion, seconds }
   *   Distortion { mean (area-weighted ‖JᵀJ−I‖²), max, flipped (triangles) }
   */
  PARAM_START: 'param-start',
  /** One chart-optimization iteration of the active run. args: {}; result: IterationStats. */
  PARAM_STEP: 'param-step',
  /**
   * The final solve with the user's alignment tags, and everything the page draws.
   * args:   {}
   * result: ParamResult { distortion: Distortion, history: IterationStats[],
   *           charts: [{ kind: 'quad'|'rect'|'unit', corners: [[u,v] × 4] }] (per face),
   *           seconds: { load, layout } (reading the mesh, placing the layout, in the worker),
   *           triangles: number (of the refined mesh),
   *           position: Float32Array (9 per refined triangle: its corners' xyz),
   *           uv: Float32Array (6 per triangle: its corners' uv in its face's chart),
   *           face: Uint32Array (per triangle: its layout face),
   *           triangleDistortion: Float32Array (per triangle: ‖JᵀJ−I‖²),
   *           cornerDistortion: Float32Array (3 per triangle, the same per corner; negated
   *             for a flipped triangle),
   *           cornerFace: Float32Array (3 per triangle: its face, per corner) }
   *         — arrays transferred
   */
  PARAM_FINISH: 'param-finish',
  /** Put the active run aside as `name`. args: { name }; result: null. */
  PARAM_KEEP: 'param-keep',
  /**
   * Make the run kept as `name` the active one (the active one is kept as `previous`).
   * args: { name, previous?: string }; result: boolean (false: no such run).
   */
  PARAM_USE: 'param-use',
  /**
   * Extract the quad mesh of the active run (paper Section 4) and measure it.
   * args:   { options: { edge_length?: number — target quad edge length, mesh units;
   *                      default 1/40 of the bounding-box diagonal } }
   * result: QuadResult { report (the --report JSON of cli.md), vertices, faces,
   *           positions: Float32Array (xyz per quad vertex),
   *           index: Uint32Array (two triangles per quad, for drawing it shaded),
   *           normal: Float32Array (per vertex),
   *           segments: Float32Array (xyz of both ends of every quad edge, once) }
   *         — arrays transferred
   */
  REMESH: 'remesh',
  /**
   * A file of the active run, to download.
   * args:   { what: 'param-obj' (the input triangle mesh, one vt per triangle corner: the
   *                              command line's --param-out)
   *                 | 'cut-obj' (the same for the mesh refined along the layout curves)
   *                 | 'quad-obj' | 'quad-ply' | 'quad-glb' (the quad mesh of the last REMESH) }
   * result: { bytes: ArrayBuffer (transferred), mime: string }
   */
  EXPORT: 'export',
  /**
   * The smooth cross field of the current mesh and its singularities, for drawing (issue 22).
   * args:   { options: { featureAngle?: number — degrees; mesh edges with a larger dihedral
   *                      angle are sharp features the field follows (default 35) } }
   * result: CrossField { directions: Float32Array (per vertex, one unit arm of the cross,
   *           xyz; the others are it turned by 90° about the normal; zero at isolated
   *           vertices) — transferred,
   *           singularities: [{ point: [x, y, z] (its triangle's centroid), valence: 3 | 5 | … }] }
   */
  FIELD: 'field',
  /**
   * Propose a coarse quad layout for the current mesh (the command line's `quadlay layout`).
   * The worker's placed layout is not changed: the page places the proposal as an edit.
   * args:   { options: { patches?: number — about this many faces (absent: as the mesh gives
   *                      them), featureAngle?: number (degrees, default 35),
   *                      quads?: number — the quads it will be remeshed with, where the
   *                      user asked for a count (the proposals are judged by their quads
   *                      there, as `quadlay remesh --layout auto --quads N` judges them),
   *                      tracing?: number — only the proposal along this tracing (the core
   *                      makes one per tracing, 6, and keeps the best), for
   *                      PICK_SUGGESTION: workers make them at once } }
   * result: { text: string — the layout file (format v1), field: CrossField (the field it was
   *           made from, as FIELD gives it), seconds: number (in the worker),
   *           note: string | null — when the faces are far from the patches asked, why }
   *         with `tracing` also { tracings: number (how many there are; text and field are
   *           null when `tracing` is not below it), judged: { hausdorff, score, folded } | null,
   *           curves: number,
   *           error: string | null (why this tracing made no layout; text and field are then
   *           null) }
   * On error: why no valid layout could be made, in words.
   */
  SUGGEST: 'suggest-layout',
  /**
   * Which of the proposals SUGGEST made with `tracing` (one per tracing, in order) to keep,
   * as SUGGEST without it keeps them. Needs no mesh.
   * args:   { candidates: [{ judged, curves } (as SUGGEST answered) | null (it failed)] }
   * result: the index of the one to keep, or null if none was made
   */
  PICK_SUGGESTION: 'pick-suggestion',
  /**
   * The last step of proposals made apart, as SUGGEST without `tracing` ends: the one
   * PICK_SUGGESTION kept, or the Voronoi cells' layout where that one is far from the surface,
   * its judged quads fold (judged.folded > 0), or none was made, and the cells' is better; either, or a version of it with the corners of
   * all faces chosen together where its quads judge no worse.
   * args:   { text: string | null (none was made), judged: { hausdorff, score, folded } | null (as
   *           SUGGEST answered them), options (as SUGGEST got them) }
   * result: { layout: string — the layout file (format v1), judged: { hausdorff, score, folded } | null }
   * On error: the layout's or the field's, or why no layout could be made, in words.
   */
  FINISH_SUGGESTION: 'finish-suggestion',
});
