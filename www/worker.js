// The module Web Worker that owns the wasm core. It keeps one `Session` (the current mesh)
// between messages, so later work (layout, solve) can run on it without sending the mesh
// again. The protocol is stated in protocol.js.
import init, { Session, pickSuggestion } from './pkg/quadlay.js';
import { MSG } from './protocol.js';

/** The current mesh; replaced only by a successful load. */
let session = null;
/** The wasm instantiation, started by the first message. */
let ready = null;

/** Throws the `no_mesh` error (protocol.js) while the worker has no mesh. */
function needMesh(message = 'load a mesh first') {
  if (!session) throw Object.assign(new Error(message), { kind: 'no_mesh' });
}

/** One function per message type: args → { result, transfer }. */
const handlers = {
  [MSG.LOAD]({ bytes, name, repairs }) {
    // repairs: { keep_largest?, fill_holes? } the user asked for (cli.md, "Repairs").
    const next = repairs ? new Session(new Uint8Array(bytes), name, repairs) : new Session(new Uint8Array(bytes), name);
    session?.free();
    session = next;
    const positions = session.positions();
    const triangles = session.triangles();
    return {
      result: { summary: session.summary(), positions, triangles },
      transfer: [positions.buffer, triangles.buffer],
    };
  },
  [MSG.SET_LAYOUT]({ text }) {
    needMesh('load a mesh before a layout');
    return { result: session.setLayout(text) };
  },
  [MSG.PARAM_START]({ options = {} }) {
    needMesh();
    return { result: session.startParam(options) };
  },
  [MSG.PARAM_STEP]() {
    needMesh();
    return { result: session.stepParam() };
  },
  [MSG.PARAM_FINISH]() {
    needMesh();
    const distortion = session.finishParam();
    const view = paramView(session);
    return {
      result: { distortion, history: session.paramHistory(), charts: session.paramCharts(), seconds: session.seconds(), ...view },
      transfer: [view.position.buffer, view.uv.buffer, view.face.buffer,
        view.triangleDistortion.buffer, view.cornerDistortion.buffer, view.cornerFace.buffer],
    };
  },
  [MSG.PARAM_KEEP]({ name }) {
    needMesh();
    session.keepParam(name);
    return { result: null };
  },
  [MSG.PARAM_USE]({ name, previous }) {
    needMesh();
    return { result: session.useParam(name, previous ?? undefined) };
  },
  [MSG.REMESH]({ options = {} }) {
    needMesh();
    const report = session.remesh(options);
    const view = quadView(session.quadPositions(), session.quadIndices());
    return {
      result: { report, ...view },
      transfer: [view.positions.buffer, view.index.buffer, view.normal.buffer, view.segments.buffer],
    };
  },
  [MSG.EXPORT]({ what }) {
    needMesh();
    const [bytes, mime] = {
      'param-obj': () => [session.paramObj(), 'model/obj'],
      'cut-obj': () => [session.cutObj(), 'model/obj'],
      'quad-obj': () => [session.quadFile('obj'), 'model/obj'],
      'quad-ply': () => [session.quadFile('ply'), 'application/octet-stream'],
      'quad-glb': () => [session.quadFile('glb'), 'model/gltf-binary'],
    }[what]?.() ?? [];
    if (!bytes) throw new Error(`cannot export '${what}'`);
    return { result: { bytes: bytes.buffer, mime }, transfer: [bytes.buffer] };
  },
  [MSG.FIELD]({ options = {} }) {
    if (!session) throw new Error('load a mesh first');
    const field = fieldView(session.crossField(options));
    return { result: field, transfer: [field.directions.buffer] };
  },
  [MSG.SUGGEST]({ options = {} }) {
    if (!session) throw new Error('load a mesh first');
    const t0 = performance.now();
    const { layout, field, note, tracings, judged, curves, error } = session.suggestLayout(options);
    const seconds = (performance.now() - t0) / 1000;
    const apart = tracings == null ? {} : { tracings, judged: judged ?? null, curves: curves ?? 0, error: error ?? null };
    if (layout == null) return { result: { text: null, field: null, seconds, note: null, ...apart } };
    const view = fieldView(field);
    return { result: { text: layout, field: view, seconds, note: note ?? null, ...apart }, transfer: [view.directions.buffer] };
  },
  [MSG.PICK_SUGGESTION]({ candidates }) {
    return { result: pickSuggestion(candidates) ?? null };
  },
  [MSG.FINISH_SUGGESTION]({ text = null, judged = null, options = {} }) {
    if (!session) throw new Error('load a mesh first');
    return { result: session.finishSuggestion(text, judged, options) };
  },
};

/** The core's field view (flat arrays) as protocol.js states CrossField. */
function fieldView({ directions, singularityPositions: p, singularityValences: valence }) {
  return {
    directions: Float32Array.from(directions),
    singularities: valence.map((v, i) => ({ point: [p[3 * i], p[3 * i + 1], p[3 * i + 2]], valence: v })),
  };
}

/**
 * The quad mesh as three.js draws it: shaded (two triangles per quad, smooth normals) and
 * its edges as line segments, each edge once.
 */
function quadView(positions, quads) {
  const nv = positions.length / 3;
  const nq = quads.length / 4;
  const index = new Uint32Array(6 * nq);
  const normal = new Float32Array(3 * nv);
  const edges = new Set();
  const ends = [];
  for (let q = 0; q < nq; q++) {
    const c = quads.subarray(4 * q, 4 * q + 4);
    index.set([c[0], c[1], c[2], c[0], c[2], c[3]], 6 * q);
    // The quad's normal from its diagonals, added to its corners (area-weighted).
    const p = (k) => 3 * c[k];
    const dx = [0, 1, 2].map((i) => positions[p(2) + i] - positions[p(0) + i]);
    const ex = [0, 1, 2].map((i) => positions[p(3) + i] - positions[p(1) + i]);
    const n = [dx[1] * ex[2] - dx[2] * ex[1], dx[2] * ex[0] - dx[0] * ex[2], dx[0] * ex[1] - dx[1] * ex[0]];
    for (let k = 0; k < 4; k++) {
      for (let i = 0; i < 3; i++) normal[p(k) + i] += n[i];
      const a = c[k], b = c[(k + 1) % 4];
      const key = a < b ? a * nv + b : b * nv + a;
      if (!edges.has(key)) {
        edges.add(key);
        ends.push(a, b);
      }
    }
  }
  for (let v = 0; v < nv; v++) {
    const l = Math.hypot(normal[3 * v], normal[3 * v + 1], normal[3 * v + 2]) || 1;
    for (let i = 0; i < 3; i++) normal[3 * v + i] /= l;
  }
  const segments = new Float32Array(3 * ends.length);
  ends.forEach((v, i) => segments.set(positions.subarray(3 * v, 3 * v + 3), 3 * i));
  return { vertices: nv, faces: nq, positions, index, normal, segments };
}

/**
 * The active run's refined mesh as three.js draws it: one vertex per triangle corner, so
 * each triangle carries its own chart's uv and its own distortion (built here, not on the
 * page's thread).
 */
function paramView(s) {
  const pos = s.cutPositions();
  const tri = s.cutTriangles();
  const uv = s.cornerUv();
  const face = s.triangleFace();
  const distortion = s.triangleDistortion();
  const n = tri.length / 3;
  const position = new Float32Array(9 * n);
  const cornerDistortion = new Float32Array(3 * n);
  const cornerFace = new Float32Array(3 * n);
  for (let t = 0; t < n; t++) {
    const a = 3 * tri[3 * t], b = 3 * tri[3 * t + 1], c = 3 * tri[3 * t + 2];
    const o = 9 * t;
    for (let k = 0; k < 3; k++) {
      position[o + k] = pos[a + k];
      position[o + 3 + k] = pos[b + k];
      position[o + 6 + k] = pos[c + k];
    }
    // Flipped triangles (chart image of non-positive area, as the core counts them) carry
    // their distortion negated: the heat map paints them apart.
    const u = 6 * t;
    const signed = (uv[u + 2] - uv[u]) * (uv[u + 5] - uv[u + 1]) - (uv[u + 3] - uv[u + 1]) * (uv[u + 4] - uv[u]);
    const d = signed <= 0 ? -Math.max(distortion[t], 1e-30) : distortion[t];
    cornerDistortion[3 * t] = cornerDistortion[3 * t + 1] = cornerDistortion[3 * t + 2] = d;
    cornerFace[3 * t] = cornerFace[3 * t + 1] = cornerFace[3 * t + 2] = face[t];
  }
  return { triangles: n, position, uv, face, triangleDistortion: distortion, cornerDistortion, cornerFace };
}

// Set before anything is awaited: messages that arrive while the wasm is still being
// instantiated would otherwise be lost.
self.onmessage = async (event) => {
  const { id, type, ...args } = event.data;
  try {
    ready ??= init().catch((err) => {
      ready = null; // let the next message try again
      throw new Error(`could not start the quadlay core: ${err?.message || err}`);
    });
    await ready;
    const handler = handlers[type];
    if (!handler) throw new Error(`unknown message type '${type}'`);
    const { result, transfer = [] } = handler(args);
    self.postMessage({ id, result }, transfer);
  } catch (err) {
    // A trap leaves the instance's memory in an unknown state: ask for a fresh worker.
    const fatal = err instanceof WebAssembly.RuntimeError;
    const message = err?.message || String(err);
    self.postMessage({
      id,
      error: fatal ? `internal error in the quadlay core (${message}); it was restarted` : message,
      // The core's errors carry what they are about as data (wasm.rs); others have neither.
      kind: fatal ? 'internal' : err?.kind ?? 'other',
      culprits: err?.culprits ?? null,
      fatal,
    });
  }
};
