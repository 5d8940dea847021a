// The side panel's views: the sample list, the mesh summary, the error box, the status line
// and the busy indicator. Each function only writes the DOM from the data it is given;
// main.js decides when.

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
 * Shows the summary of the mesh on screen (see protocol.js for its fields).
 * @param {object} summary
 * @param {string} name the file's name
 */
export function renderSummary(summary, name) {
  $('file-name').textContent = name;
  $('file-name').title = name;
  $('summary-empty').hidden = true;
  const rows = [];
  const row = (key, label, value, cls = '') => rows.push([key, label, value, cls]);
  const group = (label) => rows.push([null, label]);

  row('format', 'Format', summary.format.toUpperCase());
  row('vertices', 'Vertices', num(summary.vertices));
  row('triangles', 'Triangles', num(summary.triangles));
  row('edges', 'Edges', num(summary.edges));
  row('boundary_loops', 'Boundary loops', num(summary.boundary_loops));
  row('genus', 'Genus', num(summary.genus));
  row('components', 'Components', num(summary.components.length));
  if (summary.components.length > 1) {
    summary.components.slice(0, 8).forEach((c, i) => {
      row(null, `#${i + 1}`, `${num(c.faces)} tri · g ${c.genus} · b ${c.boundary_loops}`, 'sub');
    });
    if (summary.components.length > 8) row(null, '…', `${summary.components.length - 8} more`, 'sub');
  }
  const [lo, hi] = summary.bounding_box;
  row('size', 'Size', lo.map((l, i) => short(hi[i] - l)).join(' × '), 'dims');

  group('Repairs');
  const { welded_vertices: welded, removed_zero_area_faces: removed, unreferenced_vertices: unref } =
    summary.repairs;
  if (welded + removed + unref === 0) {
    row('repairs', 'None needed', '✓', 'ok');
  } else {
    row('welded_vertices', 'Welded vertices', num(welded), welded ? 'warn' : 'none');
    row('removed_zero_area_faces', 'Zero-area faces', num(removed), removed ? 'warn' : 'none');
    row('unreferenced_vertices', 'Unused vertices', num(unref), unref ? 'warn' : 'none');
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
    dd.textContent = value;
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
