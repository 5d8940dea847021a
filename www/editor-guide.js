// Guidance for the layout being drawn: per layout face the Gaussian curvature it encloses
// (the sum of its interior vertices' angle defects: a face holding ±90° of it cannot lie
// flat in its chart) and, once solved, how far its lengths are off in its chart; for a face
// that holds too much, a marker "add a node here" on the mesh that one click turns into a
// node (an ordinary undoable edit). The numbers come from the core: the faces of the
// layout's check (`view.faces`) when it sends them, else those of the last run's report
// (`report.faces`, cli.md), both { face, corners, area, curvature_deg, needs_node,
// length_error?, suggestion?: { vertex, at, reason } }.
import * as L from './layout-doc.js';

/**
 * The room a full "+ add a node here" label takes on screen, in pixels (editor.css
 * `.guide-marker`, with a little space round it): labels closer than this cover each other.
 */
const LABEL = { w: 150, h: 30 };

/**
 * Which markers, at screen points `at` (the most important first), show the full label: each
 * that would cover no label shown before it. The others show as a small "+" with the same
 * click and title, so labels never pile up unreadably (a proposal on a detailed mesh can flag
 * a dozen faces in one view).
 * @param {{x: number, y: number}[]} at
 * @returns {boolean[]}
 */
export function fullLabels(at, size = LABEL) {
  const shown = [];
  return at.map((p) => {
    const free = shown.every((q) => Math.abs(p.x - q.x) >= size.w || Math.abs(p.y - q.y) >= size.h);
    if (free) shown.push(p);
    return free;
  });
}

export class EditorGuide {
  /**
   * @param {import('./editor.js').Editor} ed the editor whose layout is guided
   * @param {HTMLElement} viewport where the markers go
   */
  constructor(ed, viewport) {
    this.ed = ed;
    /** Face guidance of the current layout, by face index; empty when none is known. */
    this.faces = [];
    this.markers = document.createElement('div');
    this.markers.className = 'guide-markers';
    viewport.append(this.markers);
  }

  /** The faces' guidance of the current layout (null: none known). */
  set(faces) {
    this.faces = Array.isArray(faces) ? faces : [];
    this.shown = -1;
    this.place();
  }

  /** The faces a node would help, with the place for it. */
  suggestions() {
    return this.faces.filter((g) => g.suggestion && Number.isInteger(g.suggestion.vertex));
  }

  /**
   * The suggestions, the most important first: the one "Show" last turned to, then the faces
   * that hold most curvature, then the most distorted.
   */
  ranked() {
    const focus = this.places()[this.shown]?.face;
    const weight = (g) => (g.face === focus ? 3 : g.needs_node ? 2 : 1);
    const size = (g) => (g.needs_node ? Math.abs(g.curvature_deg) : g.length_error ?? 0);
    return this.suggestions().sort((a, b) => weight(b) - weight(a) || size(b) - size(a));
  }

  /** One face's numbers in words (for the hint line and the Layout card), or null. */
  describe(f) {
    const g = this.faces[f];
    if (!g) return null;
    const parts = [`Face ${f}: encloses ${signed(g.curvature_deg)} of curvature`];
    if (g.needs_node) parts[0] += ' (too much to lie flat: it needs a node inside)';
    if (Number.isFinite(g.length_error)) parts.push(`lengths off by ${(100 * g.length_error).toFixed(1)} % in its chart`);
    return parts.join(' · ');
  }

  /**
   * What the Layout card's Faces row adds about curvature: how many faces hold too much for
   * a flat chart, short and in words (null when none does, or nothing is known). Inside that row, not a row of
   * its own, so the card keeps the Solve card on screen; every face's numbers are on hover.
   */
  facesNote() {
    const needy = this.needy();
    if (!needy.length) return null;
    return { text: `⚠ ${needy.length}`, words: `${needy.length} of the faces need${needy.length > 1 ? '' : 's'} a node inside (up to ${signed(needy[0].curvature_deg)} of curvature)` };
  }

  /** The faces that hold too much curvature for a flat chart, the most first. */
  needy() {
    return this.faces.filter((g) => g.needs_node)
      .sort((a, b) => Math.abs(b.curvature_deg) - Math.abs(a.curvature_deg));
  }

  /**
   * The next place where a node would help, going round the faces that need one (the most
   * curved first) one call at a time; null when none has a suggestion.
   */
  nextSuggestion() {
    const places = this.places();
    if (!places.length) return null;
    this.shown = ((this.shown ?? -1) + 1) % places.length;
    return places[this.shown].suggestion.at;
  }

  /** The faces that need a node and have a place for it, the most curved first: where "Show" goes round. */
  places() {
    return this.needy().filter((g) => g.suggestion);
  }

  /** Turns face f's suggestion into a node: an ordinary edit, undone like any other. */
  accept(f) {
    const s = this.faces[f]?.suggestion;
    if (!s) return;
    const there = this.ed.nodeVertex.indexOf(s.vertex);
    if (there >= 0) {
      this.ed.say(`nodes[${there}] is on that vertex already`);
      return;
    }
    this.ed.say(`Added a node in face ${f}: connect it to the face's sides with the Edge tool (E)`);
    this.ed.setMode('edge');
    const [doc, n] = L.addNode(this.ed.doc, s.vertex);
    this.ed.pending = n;
    return this.ed.apply(doc, { label: 'add suggested node' });
  }

  /**
   * Places the markers over the view: each at its point's pixel when the point is in front
   * of the surface, hidden otherwise; called after the camera moves or the layout changes.
   */
  place() {
    // Called from the controls' change event, before the frame that would update the
    // camera's matrices: project with the camera as it is now, not as last drawn.
    this.ed.viewer.camera.updateMatrixWorld();
    const rect = this.markers.parentElement.getBoundingClientRect();
    const seen = this.ranked()
      .map((g) => ({ g, s: this.ed.picker.visible(g.suggestion.at) ? this.ed.picker.screenOf(g.suggestion.at) : null }))
      .filter((m) => m.s);
    const full = fullLabels(seen.map((m) => m.s));
    const items = seen.map(({ g, s }, i) => {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = full[i] ? 'guide-marker' : 'guide-marker compact';
      b.dataset.face = String(g.face);
      b.textContent = full[i] ? '+ add a node here' : '+';
      b.setAttribute('aria-label', 'add a node here');
      b.title = `${this.describe(g.face)}. Click: a node here (${g.suggestion.reason === 'distortion' ? 'where its distortion concentrates' : 'where its curvature concentrates'}).`;
      b.style.left = `${s.x - rect.left}px`;
      b.style.top = `${s.y - rect.top}px`;
      b.addEventListener('click', () => this.accept(g.face));
      return b;
    });
    // The full labels last, so a small "+" never covers one.
    this.markers.replaceChildren(...items.filter((_, i) => !full[i]), ...items.filter((_, i) => full[i]));
  }
}

/** Degrees with their sign: "+92°", "−45°". */
function signed(deg) {
  if (!Number.isFinite(deg)) return '—';
  const r = Math.round(deg);
  return `${r > 0 ? '+' : r < 0 ? '−' : ''}${Math.abs(r)}°`;
}
