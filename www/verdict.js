// The verdict on a finished run, beside "Done" in the solve card: a plain "no warnings" only
// when the core found nothing to warn about (report.warnings, cli.md), else each warning in
// words with a button that flies the camera to the place it names and marks it. Also the
// readable scale of the distortion numbers the card shows.

/** Relative length error in percent: 0.052 → "5.2 %". */
export function percent(x, digits = 1) {
  if (!Number.isFinite(x)) return String(x);
  return `${(100 * x).toFixed(x < 0.001 && x > 0 ? 2 : digits)} %`;
}

/**
 * The typical relative length error of a parameterization whose area-weighted mean of
 * ‖JᵀJ − I‖²_F is `mean`: near an isometry ‖JᵀJ − I‖²_F ≈ 8 e² for a length error e (J's
 * singular values 1 + e₁, 1 + e₂: (2e₁)² + (2e₂)² = 8 × their mean square), so the root mean
 * square error is √(mean / 8). Used where the core has not measured the error itself (the
 * progress of a run, the chart comparison).
 */
export function lengthErrorOf(mean) {
  return Math.sqrt(Math.max(0, mean) / 8);
}

/** What a warning's kind is called in the list. */
const TITLES = {
  surface_missed: 'The quads miss the surface',
  face_distorted: 'A face is far more distorted than the others',
  flipped_triangles: 'Flipped triangles',
  folded_quads: 'Folded quads',
  counts_raised: 'Curves too short for one edge',
  counts_stretched: 'Quads stretched along some curves',
  quad_count_off: 'Not the quad count asked for',
};

export class Verdict {
  /**
   * @param {object} o
   * @param {import('./viewer.js').Viewer} o.viewer flies to the warnings' places
   * @param {HTMLElement} o.container where the verdict goes (after the progress line)
   */
  constructor({ viewer, container }) {
    this.viewer = viewer;
    this.box = document.createElement('div');
    this.box.className = 'verdict';
    this.box.id = 'solve-verdict';
    this.box.setAttribute('aria-live', 'polite');
    this.box.hidden = true;
    container.append(this.box);
  }

  /**
   * Shows the verdict of `report` (null: none, e.g. while running; a report without
   * `warnings` gets none either, not a false "no warnings").
   */
  show(report) {
    this.viewer.setMarker(null);
    delete this.box.dataset.marked;
    if (!Array.isArray(report?.warnings)) {
      this.box.hidden = true;
      this.box.replaceChildren();
      return;
    }
    const warnings = report.warnings;
    this.box.hidden = false;
    this.box.dataset.state = warnings.length ? 'warn' : 'ok';
    const head = document.createElement('p');
    head.className = 'verdict-head';
    const miss = report.quads?.hausdorff;
    const distance = Number.isFinite(miss) ? `the quads stay within ${percent(miss, 2)} of the bounding-box diagonal from the surface` : null;
    head.textContent = warnings.length
      ? `${warnings.length} warning${warnings.length === 1 ? '' : 's'}: look before trusting the result`
      : `No warnings${distance ? `: ${distance}` : ''}`;
    const list = document.createElement('ul');
    list.className = 'verdict-list';
    warnings.forEach((w, i) => list.append(this.item(w, i)));
    this.box.replaceChildren(head, list);
  }

  item(w, i) {
    const li = document.createElement('li');
    li.dataset.kind = w.kind;
    const text = document.createElement('p');
    const title = document.createElement('strong');
    title.textContent = TITLES[w.kind] ?? w.kind;
    const message = w.message ? w.message[0].toUpperCase() + w.message.slice(1) : '';
    text.append(title, document.createElement('br'), `${message}${/[.!?]$/.test(message) ? '' : '.'}`);
    li.append(text);
    if (Array.isArray(w.at) && w.at.length === 3 && w.at.every(Number.isFinite)) {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'tool';
      b.dataset.warning = String(i);
      b.textContent = 'Show';
      b.title = 'fly the camera there and mark the place';
      b.addEventListener('click', () => {
        this.box.dataset.marked = String(i);
        return this.viewer.flyTo(w.at);
      });
      li.append(b);
    }
    return li;
  }
}
