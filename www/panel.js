// The side panel's views: the sample list, the mesh summary, the error box, the status line
// and the busy indicator. Each function only writes the DOM from the data it is given;
// main.js decides when.

import { numberedCounts } from './layout-doc.js';

const $ = (id) => document.getElementById(id);
const fmt = new Intl.NumberFormat('en-US');
const num = (n) => fmt.format(n);

/**
 * Fills the sample list; `onPick(sample)` is called when one is clicked.
 * @param {{file: string, title: string, note: string}[]} samples
 */
export function renderSamples(samples, onPick) {
  const list = $('samples');
  list.replaceChildren(
    ...samples.map((sample) => {
      const button = document.createElement('button');
      button.type = 'button';
      button.className = 'sample';
      button.dataset.file = sample.file;
      button.title = `${sample.title}: ${sample.note} (${sample.file})`;
      button.append(span('sample-title', sample.title), span('sample-note', sample.note));
      button.addEventListener('click', () => onPick(sample));
      const item = document.createElement('li');
      item.append(button);
      return item;
    }),
  );
}

/** Marks the sample whose file is `file` as the one shown (none if null). */
export function markSample(file) {
  for (const button of $('samples').querySelectorAll('.sample')) {
    button.setAttribute('aria-current', String(button.dataset.file === file));
  }
}

/**
 * Shows the summary of the mesh on screen (see protocol.js for its fields), folded to one
 * line unless something in it wants a look (several components, holes, repairs made).
 * @param {object} summary
 * @param {string} name the file's name
 * @param {{keepLargest?: () => void, fillHoles?: {edges: number, run: () => void}}} [repairs]
 *   the repairs offered one click each (cli.md, "Repairs the user asks for")
 */
export function renderSummary(summary, name, repairs = {}) {
  $('file-name').textContent = name;
  $('file-name').title = name;
  $('summary-empty').hidden = true;
  const loops = summary.boundary_loops;
  // The file's counts: the core works on a coarse mesh refined (a row below says so), which
  // the repairs below need not list again.
  const file = numberedCounts(summary);
  const refinements = summary.repairs.refinements ?? 0;
  const listed = { ...summary.repairs };
  for (const key of ['refinements', 'vertices_before_refinement', 'triangles_before_refinement']) delete listed[key];
  const parts = [`${num(file.vertices)} vertices`, `${num(file.triangles)} triangles`,
    loops ? `${num(loops)} boundary loop${loops === 1 ? '' : 's'}` : 'closed', `genus ${num(summary.genus)}`];
  if (summary.components.length > 1) parts.push(`${num(summary.components.length)} components`);
  $('summary-line').textContent = parts.join(' · ');
  const made = Object.entries(listed).some(([, v]) => (typeof v === 'number' ? v > 0 : Boolean(v)));
  $('summary-details').open = summary.components.length > 1 || loops > 1 || made;
  const rows = [];
  const row = (key, label, value, cls = '') => rows.push([key, label, value, cls]);
  const group = (label) => rows.push([null, label]);

  row('format', 'Format', summary.format.toUpperCase());
  row('vertices', 'Vertices', num(file.vertices));
  row('triangles', 'Triangles', num(file.triangles));
  if (refinements > 0) {
    row('refined', 'Refined to', `${num(summary.triangles)} triangles`, 'sub');
  } else {
    row('edges', 'Edges', num(summary.edges));
  }
  row('boundary_loops', 'Boundary loops', repairs.fillHoles
    ? [num(loops), button('repair-fill-holes', `Fill holes ≤ ${num(repairs.fillHoles.edges)} edges`,
      `close every boundary loop of at most ${repairs.fillHoles.edges} edges, smoothly (the longest loop stays open)`, repairs.fillHoles.run)]
    : num(loops));
  row('genus', 'Genus', num(summary.genus));
  row('components', 'Components', repairs.keepLargest
    ? [num(summary.components.length), button('repair-keep-largest', 'Keep largest',
      'keep only the largest connected component (vertex numbers stay, so layouts keep fitting)', repairs.keepLargest)]
    : num(summary.components.length));
  if (summary.components.length > 1) {
    summary.components.slice(0, 8).forEach((c, i) => {
      row(null, `#${i + 1}`, `${num(c.faces)} tri · g ${c.genus} · b ${c.boundary_loops}`, 'sub');
    });
    if (summary.components.length > 8) row(null, '…', `${summary.components.length - 8} more`, 'sub');
  }
  const [lo, hi] = summary.bounding_box;
  row('size', 'Size', lo.map((l, i) => short(hi[i] - l)).join(' × '), 'dims');

  group('Repairs');
  const { welded_vertices: welded, removed_zero_area_faces: removed, unreferenced_vertices: unref, ...asked } = listed;
  if (!made) {
    row('repairs', 'None needed', '✓', 'ok');
  } else {
    row('welded_vertices', 'Welded vertices', num(welded), welded ? 'warn' : 'none');
    row('removed_zero_area_faces', 'Zero-area faces', num(removed), removed ? 'warn' : 'none');
    row('unreferenced_vertices', 'Unused vertices', num(unref), unref ? 'warn' : 'none');
    // The repairs the user asked for, as the core names them.
    for (const [key, value] of Object.entries(asked)) {
      if (!value) continue;
      const label = key.replace(/_/g, ' ').replace(/^./, (c) => c.toUpperCase());
      row(key, label, typeof value === 'number' ? num(value) : value === true ? 'yes' : String(value), 'warn');
    }
  }

  renderRows($('summary'), rows);
}

/** Fills a <dl> with [key, label, value, class] rows; a row without value is a heading. */
function renderRows(dl, rows) {
  dl.replaceChildren();
  for (const [key, label, value, cls] of rows) {
    if (value === undefined) {
      const div = document.createElement('div');
      div.className = 'group';
      div.textContent = label;
      dl.append(div);
      continue;
    }
    const dt = document.createElement('dt');
    const dd = document.createElement('dd');
    dt.textContent = label;
    // A value with a button: [text, button].
    if (Array.isArray(value)) {
      dd.textContent = value[0];
      dd.append(value[1]);
      dd.classList.add('with-action');
    } else {
      dd.textContent = value;
    }
    if (key) dd.dataset.key = key;
    if (cls === 'sub') dt.className = 'sub';
    if (cls) dd.className = cls;
    dl.append(dt, dd);
  }
}

/**
 * Shows the layout's summary (protocol.js, SET_LAYOUT), or hides the card with null.
 * @param {object|null} summary
 * @param {string} name the layout's file name
 */
export function renderLayoutSummary(summary, name) {
  $('layout-card').hidden = !summary;
  if (!summary) return;
  $('layout-name').textContent = name;
  $('layout-name').title = name;
  const [quad, rect, unit] = summary.charts;
  renderRows($('layout-summary'), [
    ['nodes', 'Nodes', num(summary.nodes)],
    ['edges', 'Edges', `${num(summary.edges)} (${num(summary.aligned_edges)} tagged)`],
    ['boundary_pieces', 'Boundary edges', num(summary.boundary_pieces)],
    ['faces', 'Faces', num(summary.faces)],
    ['t_vertices', 'T-vertices', num(summary.t_vertices)],
    ['charts', 'Charts', `${quad} quad · ${rect} rect · ${unit} unit`],
  ]);
}

/** Shows the error box with a readable message. */
export function showError(title, message) {
  $('alert-title').textContent = title;
  $('alert-message').textContent = message;
  $('alert').hidden = false;
}

export function hideError() {
  $('alert').hidden = true;
}

/** Wires the error box's close button. */
export function initErrorBox() {
  $('alert-close').addEventListener('click', hideError);
}

/**
 * The status line under the panel.
 * @param {'loading'|'ready'|'error'} state
 * @param {string} text
 */
export function setStatus(state, text) {
  $('status').dataset.state = state;
  $('status-text').textContent = text;
  $('status-text').title = text;
}

/** The "Loading…" pill over the view; `text` null hides it. */
export function setBusy(text) {
  $('busy').hidden = text == null;
  if (text != null) $('busy-text').textContent = text;
}

function button(id, text, title, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.className = 'tool repair';
  b.id = id;
  b.textContent = text;
  b.title = title;
  b.addEventListener('click', onClick);
  return b;
}

function span(className, text) {
  const el = document.createElement('span');
  el.className = className;
  el.textContent = text;
  return el;
}

/** A length with three significant digits, without exponent for ordinary sizes. */
function short(x) {
  if (x === 0) return '0';
  const a = Math.abs(x);
  if (a >= 1e-3 && a < 1e6) return String(Number(x.toPrecision(3)));
  return x.toExponential(2);
}
