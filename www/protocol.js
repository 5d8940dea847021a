// The message protocol between the page (client.js) and the worker that owns the wasm
// session (worker.js). This module is the one place that states it; both sides import it.
//
// Every request is   { id, type, ...args }          page → worker
// and every reply is { id, result }                  worker → page, on success
//                 or { id, error, fatal? }           worker → page, on failure
//
// `id` is a number the client picks to match a reply to its request; replies come in the
// order the requests were sent (the worker handles one message at a time). `error` is a
// readable sentence meant for the user, e.g. "x.obj: OBJ line 2: 'x' is not a number".
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
   *           curves: [{ source: 'edges[3]' | 'boundary loop 0', align, nodes: [a, b],
   *                      points: number[] (xyz interleaved) }],
   *           vertex_face: number[] (face of every mesh vertex, -1 for nodes) }
   * On error (the layout's rule that fails, naming the entry) the worker has no layout.
   */
  SET_LAYOUT: 'set-layout',
});
