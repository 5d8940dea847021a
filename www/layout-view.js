// The layout's faces on the surface: a soft colour per face, for the per-vertex colours of
// the surface (the editor, editor.js, draws the curves and nodes over it).
import * as THREE from 'three';

/** Pastel face colours, picked so that neighbours rarely look alike. */
const PALETTE = [0x9ad0ec, 0xf6c28b, 0xb5e2a0, 0xe7a9c9, 0xcdb4f0, 0xf3e58c, 0x9fe0d3, 0xf2a89b,
  0xa9bff5, 0xd7e89a, 0xf0b9e8, 0x8fd6b4];
const NODE_GRAY = new THREE.Color(0xb9bec6);

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
    colors[3 * i] = c.r;
    colors[3 * i + 1] = c.g;
    colors[3 * i + 2] = c.b;
  });
  return colors;
}
