// The field view, for teaching: the mesh's smooth cross field (the directions a good quad
// layout follows) as small crosses on the surface, and its singularities (where the field
// turns: the layout's valence-3 and valence-5 nodes) as dots coloured by valence, with a
// legend. Drawn over the surface beside the layout's curves; the arrays come from the worker
// (protocol.js, FIELD), this module only builds three.js objects on them.
import * as THREE from 'three';
import { surfaceArea } from './mesh-measure.js';

/** Singularity colours by valence; `other` for the rare 2, 6, …. */
export const VALENCE_COLOR = { 3: '#3ddc84', 5: '#d16bff', other: '#00c2c7' };
const CROSS_COLOR = 0x22304a;
/** About this many crosses on the surface, spread evenly. */
const CROSSES = 2500;

export class FieldView {
  /**
   * @param {import('./viewer.js').Viewer} viewer
   * @param {HTMLElement} viewport where the legend goes
   */
  constructor(viewer, viewport) {
    this.viewer = viewer;
    this.layer = new THREE.Group();
    this.layer.name = 'field-view';
    this.layer.visible = false;
    viewer.scene.add(this.layer);
    this.legend = document.createElement('div');
    this.legend.className = 'field-legend';
    this.legend.id = 'field-legend';
    this.legend.hidden = true;
    viewport.append(this.legend);
  }

  get visible() {
    return this.layer.visible;
  }

  /**
   * Draws a field on the mesh.
   * @param {{positions: Float32Array, triangles: Uint32Array, summary: object}} mesh
   * @param {{directions: Float32Array, singularities: object[]}} field the worker's
   *   CrossField (protocol.js)
   * @returns {object} what is shown: { vertices, crosses, singularities: { 3, 5, other } }
   */
  show(mesh, field) {
    this.clear();
    const { positions, triangles } = mesh;
    const normals = vertexNormals(positions, triangles);
    const spacing = Math.sqrt(surfaceArea(positions, triangles) / CROSSES) || this.viewer.radius / 30;
    const picked = spreadVertices(positions, field.directions, spacing);
    const arm = 0.38 * spacing;
    const lift = 0.08 * spacing;
    const segments = new Float32Array(picked.length * 12);
    let o = 0;
    for (const v of picked) {
      const p = positions.subarray(3 * v, 3 * v + 3);
      const d = field.directions.subarray(3 * v, 3 * v + 3);
      const n = normals.subarray(3 * v, 3 * v + 3);
      const e = [n[1] * d[2] - n[2] * d[1], n[2] * d[0] - n[0] * d[2], n[0] * d[1] - n[1] * d[0]];
      for (const a of [d, e]) {
        for (const s of [-1, 1]) {
          for (let i = 0; i < 3; i++) segments[o++] = p[i] + lift * n[i] + s * arm * a[i];
        }
      }
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(segments, 3));
    const crosses = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: CROSS_COLOR, transparent: true, opacity: 0.85 }));
    crosses.renderOrder = 3;
    this.layer.add(crosses);

    const counts = { 3: 0, 5: 0, other: 0 };
    const sing = field.singularities;
    if (sing.length) {
      const dot = new THREE.SphereGeometry(Math.max(0.45 * spacing, this.viewer.radius * 0.008), 14, 10);
      const dots = new THREE.InstancedMesh(dot, new THREE.MeshBasicMaterial(), sing.length);
      const m = new THREE.Matrix4();
      const color = new THREE.Color();
      sing.forEach((s, i) => {
        const key = s.valence === 3 || s.valence === 5 ? s.valence : 'other';
        counts[key]++;
        m.makeTranslation(s.point[0], s.point[1], s.point[2]);
        dots.setMatrixAt(i, m);
        dots.setColorAt(i, color.set(VALENCE_COLOR[key]));
      });
      dots.renderOrder = 4;
      this.layer.add(dots);
    }
    this.layer.visible = true;
    this.renderLegend(counts, picked.length, mesh.summary);
    this.viewer.requestRender();
    return { vertices: positions.length / 3, crosses: picked.length, singularities: counts };
  }

  hide() {
    this.clear();
    this.layer.visible = false;
    this.legend.hidden = true;
    this.viewer.requestRender();
  }

  clear() {
    for (const child of this.layer.children) {
      child.geometry?.dispose();
      child.material?.dispose();
    }
    this.layer.clear();
  }

  renderLegend(counts, crosses, summary) {
    const row = (color, text, shape = 'dot') => {
      const r = document.createElement('div');
      r.className = 'field-legend-row';
      const swatch = document.createElement('span');
      swatch.className = `field-swatch ${shape}`;
      // A dot is filled with its colour; a cross is drawn in it (suggest.css).
      if (shape === 'cross') swatch.style.color = color;
      else swatch.style.background = color;
      r.append(swatch, text);
      return r;
    };
    const title = document.createElement('div');
    title.className = 'legend-title';
    title.textContent = 'Cross field';
    const total = counts[3] + counts[5] + counts.other;
    const note = document.createElement('div');
    note.className = 'legend-note';
    // Poincaré–Hopf: on a closed surface the indices (4 − valence)/4 add up to the Euler
    // characteristic (a boundary takes its share, so only closed meshes say it).
    const closed = summary && summary.boundary_loops === 0;
    const chi = closed ? (summary.components ?? []).reduce((s, c) => s + c.euler_characteristic, 0) : null;
    note.textContent = `${total} singularit${total === 1 ? 'y' : 'ies'}${chi != null ? ` · indices sum to χ = ${chi}` : ''}`;
    const cross = row(`#${CROSS_COLOR.toString(16)}`, `directions (${crosses.toLocaleString('en-US')} crosses)`, 'cross');
    this.legend.replaceChildren(
      title,
      cross,
      row(VALENCE_COLOR[3], `valence 3: ${counts[3]}`),
      row(VALENCE_COLOR[5], `valence 5: ${counts[5]}`),
      row(VALENCE_COLOR.other, `other valence: ${counts.other}`),
      note,
    );
    this.legend.dataset.singularities = String(total);
    this.legend.hidden = false;
  }
}

/** Area-weighted unit normals per vertex (the crosses lie in the tangent plane). */
function vertexNormals(p, t) {
  const n = new Float32Array(p.length);
  for (let i = 0; i < t.length; i += 3) {
    const a = 3 * t[i], b = 3 * t[i + 1], c = 3 * t[i + 2];
    const u = [p[b] - p[a], p[b + 1] - p[a + 1], p[b + 2] - p[a + 2]];
    const v = [p[c] - p[a], p[c + 1] - p[a + 1], p[c + 2] - p[a + 2]];
    const f = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    for (const k of [a, b, c]) for (let j = 0; j < 3; j++) n[k + j] += f[j];
  }
  for (let k = 0; k < n.length; k += 3) {
    const l = Math.hypot(n[k], n[k + 1], n[k + 2]) || 1;
    for (let j = 0; j < 3; j++) n[k + j] /= l;
  }
  return n;
}

/**
 * About one vertex per cube of side `spacing` (the one nearest its centre), so the crosses
 * spread evenly whatever the triangle sizes; vertices without a direction are skipped.
 */
function spreadVertices(positions, directions, spacing) {
  const best = new Map();
  for (let v = 0; v < positions.length / 3; v++) {
    if (directions[3 * v] === 0 && directions[3 * v + 1] === 0 && directions[3 * v + 2] === 0) continue;
    let key = '';
    let d2 = 0;
    for (let i = 0; i < 3; i++) {
      const x = positions[3 * v + i] / spacing;
      const cell = Math.floor(x);
      key += `${cell},`;
      d2 += (x - cell - 0.5) ** 2;
    }
    const held = best.get(key);
    if (!held || d2 < held.d2) best.set(key, { v, d2 });
  }
  return [...best.values()].map((b) => b.v);
}
