// Draws a layout on the surface: every curve as a thick line (tagged edges orange, others
// blue, mesh boundary pieces white), nodes as dots, and a soft colour per face.
import * as THREE from 'three';
import { Line2 } from 'three/addons/lines/Line2.js';
import { LineGeometry } from 'three/addons/lines/LineGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';

const COLORS = { aligned: 0xff9d2e, free: 0x4fa8ff, boundary: 0xf2f4f8, node: 0xff4d6d };
/** Pastel face colours, picked so that neighbours rarely look alike. */
const PALETTE = [0x9ad0ec, 0xf6c28b, 0xb5e2a0, 0xe7a9c9, 0xcdb4f0, 0xf3e58c, 0x9fe0d3, 0xf2a89b,
  0xa9bff5, 0xd7e89a, 0xf0b9e8, 0x8fd6b4];
const NODE_GRAY = new THREE.Color(0xb9bec6);

/**
 * The overlay group of a layout (curves and nodes).
 * @param {{curves: {source: string, align: boolean, points: number[]}[]}} view from the core
 * @param {number} radius the mesh's bounding radius, to size lines and dots
 * @param {THREE.Vector2} resolution the canvas size in pixels (LineMaterial needs it)
 */
export function layoutOverlay(view, radius, resolution) {
  const group = new THREE.Group();
  group.name = 'layout';
  const materials = {};
  const material = (kind) => (materials[kind] ??= new LineMaterial({
    color: COLORS[kind],
    linewidth: kind === 'aligned' ? 4 : 3,
    resolution,
    worldUnits: false,
  }));
  const ends = [];
  for (const c of view.curves) {
    const kind = c.source.startsWith('boundary') ? 'boundary' : c.align ? 'aligned' : 'free';
    const geometry = new LineGeometry();
    geometry.setPositions(c.points);
    const line = new Line2(geometry, material(kind));
    line.computeLineDistances();
    line.userData.source = c.source;
    group.add(line);
    const p = c.points;
    ends.push([p[0], p[1], p[2]], [p[p.length - 3], p[p.length - 2], p[p.length - 1]]);
  }
  const dot = new THREE.SphereGeometry(radius * 0.012, 12, 8);
  const dots = new THREE.InstancedMesh(dot, new THREE.MeshBasicMaterial({ color: COLORS.node }), ends.length);
  const m = new THREE.Matrix4();
  ends.forEach((e, i) => dots.setMatrixAt(i, m.makeTranslation(e[0], e[1], e[2])));
  group.add(dots);
  return group;
}

/**
 * Per-vertex colours showing the face of every vertex (nodes gray).
 * @param {number[]} vertexFace face index per vertex, -1 for nodes
 */
export function faceColors(vertexFace) {
  const colors = new Float32Array(vertexFace.length * 3);
  const c = new THREE.Color();
  vertexFace.forEach((f, i) => {
    if (f < 0) c.copy(NODE_GRAY);
    else c.setHex(PALETTE[f % PALETTE.length]);
    colors.set([c.r, c.g, c.b], 3 * i);
  });
  return colors;
}
