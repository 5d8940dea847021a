// The layout editor's input: pointer and keys turned into edits of the layout document. A
// click does what the current tool says (add a node, connect nodes, split an edge at a
// T-vertex, tag an edge, cycle a face's chart type, delete); a drag in Bend mode moves or adds
// a waypoint, a drag on a node in Node or Bend mode moves the node, the core tracing the
// curves through the new place as the pointer moves (one undoable edit on release); the
// hint line says what a click would do.
import * as L from './layout-doc.js';
import { dist2, nearestVertex } from './picking.js';
import { MODES } from './editor-toolbar.js';

/** Pointer travel (px) below which a press and release is a click, not an orbit. */
const CLICK_SLOP = 5;

export class EditorInput {
  /** @param {import('./editor.js').Editor} ed the editor the input edits */
  constructor(ed) {
    this.ed = ed;
    this.viewer = ed.viewer;
    this.canvas = ed.canvas;
    this.viewport = ed.viewport;
    this.down = null;
    this.drag = null;
    this.lastPointer = null;
    this.hoverQueued = false;
    /** What a click under the pointer would do, for the hint line (null: the tool's hint). */
    this.hoverHint = null;
    this.listen();
  }

  listen() {
    // Capture on the viewport: runs before OrbitControls' own listener on the canvas, so a
    // waypoint drag can switch the orbit off before it starts.
    this.viewport.addEventListener('pointerdown', (e) => this.onDown(e), true);
    this.viewport.addEventListener('pointermove', (e) => this.onMove(e), true);
    this.viewport.addEventListener('pointerup', (e) => this.onUp(e), true);
    this.canvas.addEventListener('pointerleave', () => {
      if (this.drag) return;
      this.setHover(null);
      this.ed.drawing.drawTransient(null);
      this.hoverHint = null;
      this.ed.updateUi();
    });
    this.viewer.controls.addEventListener('change', () => {
      this.ed.drawing.updateLabels();
      this.ed.guide.place();
    });
    window.addEventListener('keydown', (e) => this.onKey(e));
  }

  onDown(event) {
    if (event.target !== this.canvas || event.button !== 0 || !this.ed.mesh) return;
    this.down = { x: event.clientX, y: event.clientY };
    if (this.ed.mode !== 'bend' && this.ed.mode !== 'node') return;
    const hit = this.ed.picker.pick(event.clientX, event.clientY);
    if (hit?.kind === 'node') {
      this.drag = { node: hit.index, target: null };
    } else if (this.ed.mode !== 'bend') {
      return;
    } else if (hit?.kind === 'via') {
      this.drag = { edge: hit.index, k: hit.via, insert: false, target: null };
    } else if (hit?.kind === 'edge') {
      this.drag = { edge: hit.index, k: this.viaInsertIndex(hit.index, hit.segment), insert: true, target: null };
    } else {
      return;
    }
    this.viewer.controls.enabled = false;
    this.canvas.setPointerCapture(event.pointerId);
  }

  onMove(event) {
    if (!this.ed.mesh) return;
    this.lastPointer = { x: event.clientX, y: event.clientY, onCanvas: event.target === this.canvas };
    if (this.hoverQueued) return;
    this.hoverQueued = true;
    // At most one pick per frame, however fast the pointer moves.
    requestAnimationFrame(() => {
      this.hoverQueued = false;
      this.updatePointer(event.buttons);
    });
  }

  /** Hover highlight, ghost dot and rubber band for the pointer's last position. */
  updatePointer(buttons = 0) {
    const p = this.lastPointer;
    if (!p || !this.ed.mesh) return;
    {
      if (this.drag) {
        const hit = this.ed.picker.surfaceAt(p.x, p.y);
        if (hit && hit.vertex !== this.drag.vertex) {
          this.drag.vertex = hit.vertex;
          this.drag.target = this.ed.session.position(hit.vertex);
          this.previewDrag();
        }
        this.ed.drawing.drawTransient(this.drag.target);
        return;
      }
      if (p.onCanvas && this.ed.mode === 'view' && !(buttons & 1 && this.down) && this.ed.guide.faces.length) {
        // Looking only: the face under the pointer in words.
        const hint = this.ed.guide.describe(this.ed.picker.faceAt(this.ed.picker.pick(p.x, p.y)));
        if (hint !== this.hoverHint) {
          this.hoverHint = hint;
          this.ed.updateUi();
        }
        return;
      }
      if (!p.onCanvas || this.ed.mode === 'view' || (buttons & 1 && this.down)) {
        this.setHover(null);
        this.ed.drawing.drawTransient(null);
        if (this.hoverHint) {
          this.hoverHint = null;
          this.ed.updateUi();
        }
        return;
      }
      const hit = this.ed.picker.pick(p.x, p.y);
      this.setHover(hit && hit.kind !== 'surface' ? hit : null);
      const ghost = (this.ed.mode === 'node' || this.ed.mode === 'edge') && hit?.kind === 'surface' ? this.ed.session.position(hit.vertex) : null;
      const target = hit?.kind === 'node' ? hit.point : ghost;
      this.ed.drawing.drawTransient(target, { ghost: Boolean(ghost) });
      this.canvas.style.cursor = hit && hit.kind !== 'surface' ? 'pointer' : this.ed.mode === 'view' ? '' : 'crosshair';
      const hint = this.describe(hit);
      if (hint !== this.hoverHint) {
        this.hoverHint = hint;
        this.ed.updateUi();
      }
    }
  }

  onUp(event) {
    if (event.button !== 0 || !this.down) return;
    const moved = Math.hypot(event.clientX - this.down.x, event.clientY - this.down.y);
    this.down = null;
    if (this.drag) {
      const drag = this.endDrag(event.pointerId);
      const edit = moved > CLICK_SLOP && drag.vertex >= 0 ? this.dragEdit(drag) : null;
      if (edit) this.ed.apply(this.dragDoc(drag), { label: edit });
      else if (drag.previewed) this.ed.apply(this.ed.doc, { record: false, save: false }); // the worker holds a preview
      // A node pressed and released in place: the click it was.
      if (drag.node != null && moved <= CLICK_SLOP && event.target === this.canvas) this.click(event.clientX, event.clientY);
      return;
    }
    if (moved > CLICK_SLOP || event.target !== this.canvas) return;
    this.click(event.clientX, event.clientY);
  }

  /** The edit a finished drag makes (its history label), or null when it makes none. */
  dragEdit(drag) {
    if (drag.node == null) return drag.insert ? 'bend edge' : 'move waypoint';
    const there = this.ed.nodeVertex.indexOf(drag.vertex);
    if (there === drag.node) return null;
    if (there >= 0) {
      this.ed.say(`nodes[${there}] is on that vertex already`);
      return null;
    }
    return 'move node';
  }

  /** The document with the dragged node or waypoint where the pointer is. */
  dragDoc(drag) {
    if (drag.node != null) return L.moveNode(this.ed.doc, drag.node, drag.vertex);
    return drag.insert
      ? L.insertVia(this.ed.doc, drag.edge, drag.k, drag.vertex)
      : L.moveVia(this.ed.doc, drag.edge, drag.k, drag.vertex);
  }

  /**
   * Has the core trace the dragged edge through the waypoint's current place (or the dragged
   * node's edges to it), one request at a time (the latest place wins), so the curves follow
   * the pointer.
   */
  async previewDrag() {
    const drag = this.drag;
    if (!drag || !(drag.vertex >= 0)) return;
    if (drag.inFlight) {
      drag.stale = true;
      return;
    }
    drag.inFlight = true;
    drag.stale = false;
    drag.previewed = true;
    let curves = null;
    const moved = new Set(drag.node != null ? this.incidentEdges(drag.node) : [drag.edge]);
    try {
      const view = await this.ed.client.setLayout(JSON.stringify(L.inNumbering(this.dragDoc(drag), this.ed.mesh)));
      curves = view.curves.filter((c) => moved.has(L.edgeIndex(c.source))).map((c) => c.points);
    } catch {
      // an invalid place: the dashed lines show it until the next one
    }
    drag.inFlight = false;
    if (this.drag !== drag) return;
    drag.curves = curves?.length ? curves : null;
    this.ed.drawing.drawTransient(drag.target);
    if (drag.stale) this.previewDrag();
  }

  /** The edges that end at node `n`. */
  incidentEdges(n) {
    return (this.ed.doc.edges ?? []).flatMap((e, i) => (e.nodes?.includes(n) ? [i] : []));
  }

  /** Stops a node or waypoint drag; returns it. */
  endDrag(pointerId) {
    const drag = this.drag;
    this.drag = null;
    this.viewer.controls.enabled = true;
    if (pointerId != null && this.canvas.hasPointerCapture(pointerId)) this.canvas.releasePointerCapture(pointerId);
    this.ed.drawing.drawTransient(null);
    return drag;
  }

  /** A click at page pixel (x, y) in the current mode. */
  click(x, y) {
    let hit = this.ed.picker.pick(x, y);
    if (hit?.kind === 'surface' && this.ed.nodeVertex.includes(hit.vertex)) {
      const n = this.ed.nodeVertex.indexOf(hit.vertex);
      hit = { kind: 'node', index: n, point: this.ed.session.position(hit.vertex) };
    }
    const doc = this.ed.doc;
    switch (this.ed.mode) {
      case 'node': {
        if (!hit) return;
        if (hit.kind === 'edge') return this.splitAt(hit);
        if (hit.kind === 'node') return this.ed.say(`nodes[${hit.index}] is already here`);
        if (hit.kind !== 'surface') return;
        return this.ed.apply(L.addNode(doc, hit.vertex)[0], { label: 'add node' });
      }
      case 'edge': {
        if (!hit) {
          this.ed.pending = null;
          return this.ed.draw();
        }
        if (hit.kind === 'node') {
          const n = hit.index;
          if (this.ed.pending == null || this.ed.pending === n) {
            this.ed.pending = this.ed.pending === n ? null : n;
            this.ed.draw();
            return this.ed.updateUi();
          }
          const a = this.ed.pending;
          this.ed.pending = n;
          if (L.findEdge(doc, a, n) >= 0) {
            this.ed.draw();
            return this.ed.say(`nodes[${a}] and nodes[${n}] are connected already`);
          }
          return this.ed.apply(L.addEdge(doc, a, n)[0], { label: 'add edge' });
        }
        let next, n;
        if (hit.kind === 'edge') {
          const split = this.splitDoc(hit);
          if (!split) return;
          [next, n] = split;
        } else if (hit.kind === 'surface') {
          [next, n] = L.addNode(doc, hit.vertex);
        } else {
          return;
        }
        if (this.ed.pending != null) next = L.addEdge(next, this.ed.pending, n)[0];
        this.ed.pending = n;
        return this.ed.apply(next, { label: 'add edge' });
      }
      case 'align':
        if (hit?.kind === 'edge') return this.ed.apply(L.toggleAlign(doc, hit.index), { label: 'tag edge' });
        return;
      case 'chart':
        return this.cycleChart(hit);
      case 'delete':
        return this.deleteHit(hit);
      default:
    }
  }

  deleteHit(hit) {
    if (hit?.kind === 'via') return this.ed.apply(L.deleteVia(this.ed.doc, hit.index, hit.via), { label: 'delete waypoint' });
    if (hit?.kind === 'node') {
      if (this.ed.pending === hit.index) this.ed.pending = null;
      else if (this.ed.pending > hit.index) this.ed.pending--;
      return this.ed.apply(L.deleteNode(this.ed.doc, hit.index), { label: 'delete node' });
    }
    if (hit?.kind === 'edge') return this.ed.apply(L.deleteEdge(this.ed.doc, hit.index), { label: 'delete edge' });
  }

  /** Index in edge i's `via` at which a waypoint at curve segment `segment` belongs. */
  viaInsertIndex(i, segment) {
    const pts = this.ed.drawing.edgePoints[i];
    const via = this.ed.doc.edges[i].via ?? [];
    let k = 0;
    for (const w of via) {
      const p = this.ed.session.viaPosition(w);
      if (p && nearestPointIndex(pts, p) <= segment) k++;
    }
    return k;
  }

  /** [doc, new node] with edge hit.index split at the mesh vertex nearest the picked point. */
  splitDoc(hit) {
    const through = this.ed.picker.surfaceAt(...Object.values(this.ed.picker.screenOf(hit.point)));
    let vertex = through ? this.ed.picker.ensureBvh().nearestCorner(through.triangle, hit.point) : nearestVertex(this.ed.mesh.positions, hit.point);
    if (through && dist2(this.ed.mesh.positions, vertex, hit.point) > (this.ed.radius * 0.05) ** 2) {
      vertex = nearestVertex(this.ed.mesh.positions, hit.point);
    }
    const at = this.ed.nodeVertex.indexOf(vertex);
    if (at >= 0) {
      this.ed.say(`nodes[${at}] is on that vertex already`);
      return null;
    }
    return L.splitEdge(this.ed.doc, hit.index, vertex, this.viaInsertIndex(hit.index, hit.segment));
  }

  splitAt(hit) {
    const split = this.splitDoc(hit);
    if (split) this.ed.apply(split[0], { label: 'split edge' });
  }

  cycleChart(hit) {
    if (!this.ed.view) return this.ed.say('chart types can be set once the layout is valid');
    const f = this.ed.picker.faceAt(hit);
    if (f < 0) return;
    const corners = this.ed.view.summary.face_list[f].corners;
    const now = L.chartOf(this.ed.doc, corners);
    const next = L.CHARTS[(L.CHARTS.indexOf(now) + 1) % L.CHARTS.length];
    this.ed.say(`face ${f}: ${next} chart`);
    return this.ed.apply(L.setChart(this.ed.doc, corners, next), { label: `chart ${next}` });
  }

  /** What a click on `hit` would do now, for the hint line; null: the tool's own hint. */
  describe(hit) {
    if (!hit) return null;
    const face = hit.kind === 'surface' && this.ed.mode !== 'chart' ? this.ed.guide.describe(this.ed.picker.faceAt(hit)) : null;
    return this.describeClick(hit) ?? face;
  }

  /** What a click on `hit` would do in the current tool, or null when nothing. */
  describeClick(hit) {
    const edges = (n) => (this.ed.doc.edges ?? []).filter((e) => e.nodes?.includes(n)).length;
    const what = hit.kind === 'edge' ? `edges[${hit.index}]` : hit.kind === 'node' ? `nodes[${hit.index}]` : null;
    switch (this.ed.mode) {
      case 'node':
        if (hit.kind === 'edge') return `Click: split ${what} at a new node (T-vertex).`;
        if (hit.kind === 'node') return `Drag: move ${what} (its edges follow).`;
        return null;
      case 'edge':
        if (hit.kind === 'node') {
          if (this.ed.pending == null) return `Click: start an edge at ${what}.`;
          if (this.ed.pending === hit.index) return `Click: end the chain at ${what}.`;
          return `Click: connect nodes[${this.ed.pending}] to ${what}.`;
        }
        if (hit.kind === 'edge') return `Click: a new node on ${what} (T-vertex)${this.ed.pending != null ? `, connected to nodes[${this.ed.pending}]` : ''}.`;
        return null;
      case 'bend':
        if (hit.kind === 'via') return `Drag: move waypoint ${hit.via} of edges[${hit.index}].`;
        if (hit.kind === 'node') return `Drag: move ${what} (its edges follow).`;
        if (hit.kind === 'edge') return `Drag: bend ${what} through a new waypoint.`;
        return null;
      case 'align':
        if (hit.kind === 'edge') return `Click: ${this.ed.doc.edges[hit.index].align ? 'untag' : 'tag'} ${what} ${this.ed.doc.edges[hit.index].align ? '(thin blue)' : 'for alignment (thick orange)'}.`;
        return null;
      case 'chart': {
        const f = this.ed.picker.faceAt(hit);
        if (f < 0) return null;
        const face = this.ed.view.summary.face_list[f];
        const next = L.CHARTS[(L.CHARTS.indexOf(face.chart) + 1) % 3];
        const guide = this.ed.guide.describe(f);
        return `Face ${f} (corners ${face.corners.join(', ')}): ${face.chart} chart. Click: ${next}.${guide ? ` ${guide.replace(/^Face \d+: /, '')}.` : ''}`;
      }
      case 'delete':
        if (hit.kind === 'via') return `Click: delete waypoint ${hit.via} of edges[${hit.index}].`;
        if (hit.kind === 'node') {
          const k = edges(hit.index);
          return `Click: delete ${what}${k ? ` and its ${k} edge${k === 1 ? '' : 's'}` : ''}.`;
        }
        if (hit.kind === 'edge') return `Click: delete ${what}.`;
        return null;
      default:
        return null;
    }
  }

  setHover(hit) {
    const same = (a, b) => (a == null && b == null) || (a && b && a.kind === b.kind && a.index === b.index && a.via === b.via);
    if (same(hit, this.ed.hover)) return;
    this.ed.hover = hit;
    this.ed.draw();
  }

  onKey(event) {
    if (event.target.closest?.('input, textarea, select, [contenteditable]') || !this.ed.mesh) return;
    const key = event.key.toLowerCase();
    if (event.ctrlKey || event.metaKey) {
      if (this.drag) return;
      if (key === 'z' && !event.shiftKey) this.ed.undo();
      else if ((key === 'z' && event.shiftKey) || key === 'y') this.ed.redo();
      else if (key === 's') this.ed.save();
      else return;
      event.preventDefault();
      return;
    }
    if (event.altKey) return;
    if (key === 'escape') {
      if (this.drag) {
        const drag = this.endDrag();
        this.down = null;
        if (drag.previewed) this.ed.apply(this.ed.doc, { record: false, save: false });
      } else if (this.ed.pending != null) {
        this.ed.pending = null;
        this.ed.draw();
        this.ed.drawing.drawTransient(null);
        this.ed.updateUi();
      } else {
        this.ed.setMode('view');
      }
      return;
    }
    if ((key === 'delete' || key === 'backspace') && this.ed.hover) {
      event.preventDefault();
      this.deleteHit(this.ed.hover);
      return;
    }
    const mode = Object.keys(MODES).find((m) => MODES[m].key === key);
    if (mode) this.ed.setMode(mode);
  }

}

/** Index of the polyline point nearest to p. */
function nearestPointIndex(pts, p) {
  let best = 0, bestD = Infinity;
  for (let j = 0; j < pts.length; j += 3) {
    const d = (pts[j] - p[0]) ** 2 + (pts[j + 1] - p[1]) ** 2 + (pts[j + 2] - p[2]) ** 2;
    if (d < bestD) { bestD = d; best = j / 3; }
  }
  return best;
}

