// The page's entry point: wires the panel, the view and the worker client together, and
// exposes `window.quadlay` for tests and scripting:
//   state    'loading' | 'ready' | 'error'  ('ready' once a frame with the mesh is drawn)
//   summary  the shown mesh's summary (protocol.js), null before the first mesh
//   name     the shown mesh's file name
//   error    the last error's message, null after a successful load
//   load(url | File) → Promise<summary>; rejects with the error (also shown on the page);
//            null if a newer load overtook it
//   repair({ keep_largest?: true, fill_holes?: N }) → Promise<summary>: loads the shown mesh
//            again with these repairs (cli.md; also one click each in the summary when the
//            mesh has several components or boundary loops); the layout being drawn stays
//   layout   the shown layout's summary (protocol.js, SET_LAYOUT), null without one
//   loadLayout(url | File) → Promise<layout summary>; rejects with the layout's error
//   editor   the layout editor (editor.js), null without WebGL:
//     doc            a copy of the layout document being edited (format v1)
//     mode, setMode('view'|'node'|'edge'|'bend'|'align'|'chart'|'delete')
//     error          the core's verdict on the document (e.g. 'edges[3]: ...'), null if valid
//     fault          the same as data: { message, kind, culprits } (protocol.js), null if valid
//     problem        what the error names: { nodes, edges, patches, vertices, points }
//     summary        the layout summary while the document is valid, else null
//     checking       true while the core checks the last edit; settled() → Promise when done
//     undo(), redo(), canUndo, canRedo; setDoc(doc) records a document as an edit
//     text() the layout file's text; save() downloads it as NAME.layout.json
//     offer          the autosaved layout offered for restoring ({ time, doc }) or null
//     edgePoints(i)  edge i as drawn, [[x,y,z], ...]
//     screenOf(vertex | [x,y,z]) → { x, y } page pixels (null behind the camera)
//     pick(x, y)     what a click there hits: { kind: 'node'|'edge'|'via'|'surface', index, vertex }
//     vertexAt(x, y) the mesh vertex a node placed there snaps to (-1 off the mesh)
//     faceAt(x, y)   the layout face there (index into summary.face_list), -1 if none
//     stopCore()     stops the worker as a crash would; the next edit reloads the mesh into a
//                    fresh one and places the layout again (for tests)
//     restartCore()  restarts the worker as after a crash; an edit in flight is checked again
// `?mesh=URL` loads that mesh instead of the first sample, `&layout=URL` a layout on it,
// `&view=x,y,z` looks from that direction.
// Shareable links: `?mesh=URL&layout=URL&run=1` loads both and, with `run=1`, solves (and
// remeshes) at once; `&edge=L` sets the target quad edge length (mesh units; default 1/40 of
// the bounding-box diagonal), `&quads=N` the target quad count instead,
// `&chart=quad|rect|unit` the chart type of the faces whose
// patches entry names none, `&iterations=K` the chart-optimization iterations (default 3).
// The solve card (solve.js) adds to `window.quadlay`: solve, param, result (the report of
// cli.md, set once per run when it is complete: null until the quad mesh is extracted and
// measured), paramReport (the partial report of the parameterization alone, `quads: null`,
// kept apart so a script waiting for `result` never gets it), runs, run(), cancel(),
// compareCharts(), setView(), showRun(), showCharts(), exportFile(), setOptions(); see
// solve.js's header.
// The automatic layout card (suggest.js) adds suggestion, suggest(), cancelSuggest(), field,
// showField(); see its header.
import { CoreClient } from './client.js';
import { initDropZone } from './dropzone.js';
import { boundaryLoopSizes, surfaceArea } from './mesh-measure.js';
import { Editor } from './editor.js';
import * as panel from './panel.js';
import { Solver } from './solve.js';
import { Suggester } from './suggest.js';
import { SAMPLES } from './samples.js';
import { Viewer } from './viewer.js';

const $ = (id) => document.getElementById(id);
const fmt = new Intl.NumberFormat('en-US');

const quadlay = { state: 'loading', summary: null, name: null, error: null, layout: null, load, loadLayout, repair };
window.quadlay = quadlay;

const client = new CoreClient();
const viewer = createViewer();
const solver = viewer ? new Solver({ client, viewer, quadlay, panel }) : null;
const editor = viewer
  ? new Editor({
    viewer,
    client,
    viewport: $('viewport'),
    onChange: (summary) => { quadlay.layout = summary; },
    // The worker lost the mesh (it crashed and was restarted): load it again; the editor
    // keeps its layout and places it again.
    onCoreLost: () => { if (shownSource) load(shownSource).catch(() => {}); },
  })
  : null;
/** Where the shown mesh came from (a URL or a File), to load it again after a crash. */
let shownSource = null;
quadlay.editor = editor?.api ?? null;
// A finished run's faces (curvature, distortion, where a node would help) guide the editing.
if (solver && editor) solver.onResult = (report) => editor.setGuidance(report?.faces ?? null);
// The automatic layout card (suggest.js) goes under the Solve card (hidden until a layout is
// placed), so the Solve button keeps its place in the window.
if (editor) new Suggester({ client, editor, viewer, quadlay, after: $('solve-card'), askedQuads: () => solver?.askedQuads() ?? null });
/** Counts loads, so a load overtaken by a newer one does not overwrite it. */
let latest = 0;

/** The repairs the shown mesh was loaded with ({ keep_largest?, fill_holes? }), or null. */
let shownRepairs = null;

/**
 * Loads a mesh from a URL (relative to the page) or a File, and shows it.
 * @param {string|URL|File} source
 * @param {{repairs?: object, keepLayout?: boolean}} [options] repairs for the core to make
 *   (cli.md); keepLayout: the same mesh again, the layout being drawn stays on it
 */
async function load(source, { repairs = null, keepLayout = false } = {}) {
  const seq = ++latest;
  const name = nameOf(source);
  quadlay.state = 'loading';
  panel.setStatus('loading', `Loading ${name}…`);
  panel.setBusy(`Loading ${name}…`);
  const t0 = performance.now();
  try {
    const bytes = await readBytes(source);
    if (seq !== latest) return null;
    const mesh = await client.load(bytes, name, { repairs });
    if (seq !== latest) return null;
    if (!viewer) throw new Error('this browser cannot show 3D graphics (WebGL 2 is not available)');
    const drawn = viewer.setMesh(mesh);
    solver.setMeshArea(surfaceArea(mesh.positions, mesh.triangles));
    viewer.setOverlay(null);
    editor.setMesh(mesh, name, { keep: keepLayout });
    if (!keepLayout) {
      quadlay.layout = null;
      panel.renderLayoutSummary(null);
    }
    panel.hideError();
    panel.renderSummary(mesh.summary, name, repairsOffered(mesh, repairs));
    panel.markSample(sampleFileOf(source));
    await drawn;
    if (seq !== latest) return null;
    Object.assign(quadlay, { summary: mesh.summary, name, error: null, state: 'ready' });
    shownSource = source;
    shownRepairs = repairs;
    const ms = Math.round(performance.now() - t0);
    panel.setStatus('ready', `Loaded ${name} in ${fmt.format(ms)} ms`);
    return mesh.summary;
  } catch (err) {
    if (seq === latest) {
      const message = err?.message || String(err);
      Object.assign(quadlay, { error: message, state: 'error' });
      panel.showError(`Could not load ${name}`, message);
      // The summary's heading still names the mesh that stays shown.
      panel.setStatus('error', `${name} failed to load`);
    }
    throw err;
  } finally {
    if (seq === latest) panel.setBusy(null);
  }
}

/**
 * Places a layout (URL relative to the page, or a File) on the shown mesh and draws it.
 * @param {string|URL|File} source
 */
async function loadLayout(source) {
  const name = nameOf(source);
  const seq = latest;
  quadlay.state = 'loading';
  panel.setStatus('loading', `Placing ${name}…`);
  const t0 = performance.now();
  try {
    const text = new TextDecoder().decode(await readBytes(source));
    // The editor places it and draws it; a layout the core rejects stays in the editor,
    // its problem drawn on the mesh, to be fixed there.
    const view = await editor.open(text, name, { user: source instanceof Blob });
    if (seq !== latest) return null;
    await viewer.nextFrame();
    panel.hideError();
    panel.renderLayoutSummary(view.summary, name);
    // The editor's rows of the same card add the faces' curvature (editor-guide.js).
    editor.updateUi();
    Object.assign(quadlay, { layout: view.summary, error: null, state: 'ready' });
    const ms = Math.round(performance.now() - t0);
    panel.setStatus('ready', `Placed ${name}: ${view.summary.faces} faces in ${fmt.format(ms)} ms`);
    return view.summary;
  } catch (err) {
    const message = err?.message || String(err);
    Object.assign(quadlay, { error: message, state: 'error' });
    panel.showError(`Layout ${name} does not fit`, message);
    panel.setStatus('error', `${name}: not placed`);
    throw err;
  }
}

/** The 3D view, or null (with the reason on screen) where WebGL is not available. */
function createViewer() {
  try {
    return new Viewer($('viewport'));
  } catch (err) {
    panel.showError('No 3D view', `WebGL could not start: ${err?.message || err}`);
    return null;
  }
}

/** The shown mesh loaded again with `repairs` added to those it has; the layout stays. */
function repair(repairs) {
  if (!shownSource) return Promise.reject(new Error('load a mesh first'));
  return load(shownSource, { repairs: { ...shownRepairs, ...repairs }, keepLayout: true });
}

/**
 * The repairs the summary offers for `mesh` (loaded with `repairs`): keeping the largest
 * component when there are several; filling holes when there are boundary loops, up to the
 * size of the second-longest loop (the longest is most likely the mesh's real rim; the
 * number is on the button, and `repair()` takes any).
 */
function repairsOffered(mesh, repairs) {
  const s = mesh.summary;
  const offered = {};
  if (s.components.length > 1 && !repairs?.keep_largest) {
    offered.keepLargest = () => repair({ keep_largest: true }).catch(() => {});
  }
  if (s.boundary_loops > 0) {
    // In the file's edges: a refinement (the summary's repairs) halved every boundary edge,
    // and the repair counts the file's.
    const halved = 2 ** (s.repairs?.refinements ?? 0);
    const sizes = boundaryLoopSizes(mesh.triangles, mesh.positions.length / 3).map((n) => n / halved);
    const edges = sizes.length > 1 ? sizes[1] : sizes[0];
    if (edges > 0) offered.fillHoles = { edges, run: () => repair({ fill_holes: edges }).catch(() => {}) };
  }
  return offered;
}

/** Loads from a control of the page: the error is already on screen, nothing to rethrow. */
function loadFromUi(source) {
  load(source).catch(() => {});
}

async function readBytes(source) {
  if (source instanceof Blob) return source.arrayBuffer();
  const url = new URL(source, location.href);
  let response;
  try {
    response = await fetch(url);
  } catch (err) {
    throw new Error(`could not fetch ${url.href}: ${err.message}`);
  }
  if (!response.ok) {
    throw new Error(`could not fetch ${url.href}: HTTP ${response.status} ${response.statusText}`);
  }
  return response.arrayBuffer();
}

function nameOf(source) {
  if (source instanceof File) return source.name;
  const path = new URL(source, location.href).pathname;
  return decodeURIComponent(path.slice(path.lastIndexOf('/') + 1)) || 'mesh';
}

/** The sample's file name if `source` is one of the samples, else null. */
function sampleFileOf(source) {
  if (source instanceof Blob) return null;
  const url = new URL(source, location.href);
  const sample = SAMPLES.find((s) => new URL(`samples/${s.file}`, location.href).href === url.href);
  return sample?.file ?? null;
}

// ---- controls ------------------------------------------------------------------------------

panel.initErrorBox();
panel.renderSamples(SAMPLES, (sample) => loadWithLayout(`samples/${sample.file}`, sample.layout));

/** Loads a mesh, then (if given) a layout on it; errors are shown on the page. */
function loadWithLayout(mesh, layout) {
  // Until the layout is placed the editor says it is coming, not "No layout yet".
  editor?.expectLayout(layout ? nameOf(layout) : null);
  return load(mesh)
    .then((summary) => (summary && layout ? loadLayout(layout) : null))
    .catch(() => {})
    .finally(() => {
      if (editor?.placing === (layout ? nameOf(layout) : null)) editor.expectLayout(null);
    });
}

const layoutInput = $('layout-input');
layoutInput.addEventListener('change', () => {
  const file = layoutInput.files?.[0];
  if (file) loadLayout(file).catch(() => {});
  layoutInput.value = '';
});

const fileInput = $('file-input');
fileInput.addEventListener('change', () => {
  const file = fileInput.files?.[0];
  if (file) loadFromUi(file);
  fileInput.value = ''; // choosing the same file again loads it again
});

// A dropped .json is a layout for the shown mesh; anything else a mesh.
initDropZone($('viewport'), $('drop-hint'), (file) => {
  if (file.name.toLowerCase().endsWith('.json')) loadLayout(file).catch(() => {});
  else loadFromUi(file);
});

const shadingButtons = document.querySelectorAll('[data-shading]');
function setShading(mode) {
  for (const b of shadingButtons) b.setAttribute('aria-checked', String(b.dataset.shading === mode));
  viewer?.setShading(mode);
}
for (const b of shadingButtons) b.addEventListener('click', () => setShading(b.dataset.shading));

const wireButton = $('wireframe-toggle');
function toggleWireframe() {
  const on = wireButton.getAttribute('aria-pressed') !== 'true';
  wireButton.setAttribute('aria-pressed', String(on));
  viewer?.setWireframe(on);
}
wireButton.addEventListener('click', toggleWireframe);
$('reset-view').addEventListener('click', () => viewer?.resetView());

window.addEventListener('keydown', (event) => {
  if (event.ctrlKey || event.metaKey || event.altKey) return;
  if (event.target.closest?.('input, textarea, select, [contenteditable]')) return;
  if (event.key === 'w' || event.key === 'W') toggleWireframe();
  else if (event.key === 'f' || event.key === 'F') viewer?.resetView();
});

// ---- first mesh ----------------------------------------------------------------------------

const params = new URLSearchParams(location.search);
const view = params.get('view')?.split(',').map(Number);
if (view?.length === 3 && view.every(Number.isFinite)) viewer?.setViewFrom(view);
const first = params.has('mesh')
  ? loadWithLayout(params.get('mesh'), params.get('layout'))
  : loadWithLayout(`samples/${SAMPLES[0].file}`, SAMPLES[0].layout);
first.then(() => {
  solver?.setOptions({
    edge: Number(params.get('edge')) || undefined,
    quads: Number(params.get('quads')) || undefined,
    chart: params.get('chart') ?? undefined,
    iterations: params.get('iterations') ?? undefined,
  });
  if (params.get('run') === '1' && quadlay.layout && quadlay.state === 'ready') solver?.run().catch(() => {});
});
