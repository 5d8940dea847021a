// The parameterization on the surface: the refined mesh with every triangle's corners at
// their uv in its face's chart, drawn as a checkerboard with isolines (cell = the target
// quad edge length, so a good map shows square cells of that size) or as the distortion
// heat map; and the quad mesh's edges over the surface. Added to the viewer's scene beside
// its input mesh, which is hidden while this shows.
import * as THREE from 'three';
import { glslHeat } from './heatmap.js';

/** Two tones per face: the face colours of layout-view.js, light and dark squares. */
const PALETTE = [0x9ad0ec, 0xf6c28b, 0xb5e2a0, 0xe7a9c9, 0xcdb4f0, 0xf3e58c, 0x9fe0d3, 0xf2a89b,
  0xa9bff5, 0xd7e89a, 0xf0b9e8, 0x8fd6b4];

const vertexShader = /* glsl */ `
attribute float distortion;
attribute float face;
varying vec2 vUv;
varying vec3 vView;
varying float vDistortion;
varying float vFace;
void main() {
  vUv = uv;
  vDistortion = distortion;
  vFace = face;
  vec4 mv = modelViewMatrix * vec4(position, 1.0);
  vView = mv.xyz;
  gl_Position = projectionMatrix * mv;
}`;

const fragmentShader = /* glsl */ `
uniform int mode;          // 0 checkerboard, 1 heat map
uniform float cell;        // checker cell size in chart units (surface units)
uniform vec2 range;        // log10 of the heat map's ends
uniform vec3 palette[${PALETTE.length}];
varying vec2 vUv;
varying vec3 vView;
varying float vDistortion;
varying float vFace;
${glslHeat()}
void main() {
  // The triangle's own (flat) normal, facing the eye, from the screen-space derivatives of
  // its view position: no normal attribute to build and send.
  vec3 n = normalize(cross(dFdx(vView), dFdy(vView)));
  // A headlight from the upper left and a soft ambient, in view space.
  float light = 0.38 + 0.62 * max(dot(n, normalize(vec3(-0.35, 0.55, 0.75))), 0.0);
  vec3 base;
  if (mode == 0) {
    vec2 g = vUv / cell;
    vec2 c = floor(g);
    float odd = mod(c.x + c.y, 2.0);
    int f = int(mod(vFace + 0.5, ${PALETTE.length.toFixed(1)}));
    vec3 tint = palette[0];
    for (int i = 0; i < ${PALETTE.length}; i++) if (i == f) tint = palette[i];
    base = mix(tint, tint * 0.42, odd);
    // Isolines of u and v at the cell borders, about one pixel wide.
    vec2 d = abs(fract(g - 0.5) - 0.5) / max(fwidth(g), vec2(1e-6));
    float line = 1.0 - clamp(min(d.x, d.y) - 0.25, 0.0, 1.0);
    base = mix(base, vec3(0.08, 0.09, 0.11), 0.55 * line);
  } else if (vDistortion < 0.0) {
    base = vec3(1.0, 0.16, 0.42); // flipped
  } else {
    float t = (log(max(vDistortion, 1e-30)) / log(10.0) - range.x) / (range.y - range.x);
    base = heat(t);
  }
  gl_FragColor = vec4(base * light, 1.0);
}`;

export class ParamView {
  /** @param {import('./viewer.js').Viewer} viewer */
  constructor(viewer) {
    this.viewer = viewer;
    this.group = new THREE.Group();
    this.group.name = 'parameterization';
    viewer.scene.add(this.group);
    this.material = new THREE.ShaderMaterial({
      vertexShader,
      fragmentShader,
      uniforms: {
        mode: { value: 0 },
        cell: { value: 1 },
        range: { value: new THREE.Vector2(-4, 1) },
        palette: { value: PALETTE.map((c) => new THREE.Color(c)) },
      },
      side: THREE.DoubleSide,
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    // Quad edges are chords under a curved surface: drawn pulled towards the eye by a part
    // of the edge length, so the finer surface does not hide half of each.
    this.quadMaterial = new THREE.ShaderMaterial({
      uniforms: { bias: { value: 0 }, color: { value: new THREE.Color(0x10131a) } },
      vertexShader: /* glsl */ `
        uniform float bias;
        void main() {
          vec4 mv = modelViewMatrix * vec4(position, 1.0);
          mv.xyz -= normalize(mv.xyz) * bias;
          gl_Position = projectionMatrix * mv;
        }`,
      fragmentShader: /* glsl */ `
        uniform vec3 color;
        void main() { gl_FragColor = vec4(color, 0.85); }`,
      transparent: true,
    });
    this.quadSurfaceMaterial = new THREE.MeshStandardMaterial({
      color: 0xb8c4d6,
      roughness: 0.6,
      metalness: 0,
      side: THREE.DoubleSide,
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    this.surface = null;
    this.quads = null;
    this.quadSurface = null;
    /** 'surface' (the input with its layout), 'checker', 'distortion' or 'quads' (the quad
     * mesh shaded, instead of the input). */
    this.mode = 'surface';
    /** Quad edges over the checkerboard, heat map or input (always over the quad mesh). */
    this.showQuads = false;
  }

  /**
   * Compiles the shaders of everything this view draws, once, before there is anything to
   * draw, by drawing an empty stand-in of each: a program is compiled and linked on first
   * use, which blocks the page's thread (most of a second in a software renderer), and that
   * should happen when a layout is placed, not at the moment a solve's result arrives.
   */
  warmUp() {
    if (this.warm) return;
    this.warm = true;
    const one = (attrs) => {
      const g = new THREE.BufferGeometry();
      for (const [name, size] of attrs) g.setAttribute(name, new THREE.BufferAttribute(new Float32Array(3 * size), size));
      return g;
    };
    const quad = one([['position', 3], ['normal', 3]]);
    quad.setIndex(new THREE.BufferAttribute(new Uint32Array([0, 1, 2]), 1));
    const stand = [
      new THREE.Mesh(one([['position', 3], ['uv', 2], ['distortion', 1], ['face', 1]]), this.material),
      new THREE.Mesh(quad, this.quadSurfaceMaterial),
      new THREE.LineSegments(one([['position', 3]]), this.quadMaterial),
    ];
    for (const o of stand) o.frustumCulled = false;
    this.group.add(...stand);
    try {
      this.viewer.renderer.render(this.viewer.scene, this.viewer.camera);
    } finally {
      this.group.remove(...stand);
      for (const o of stand) o.geometry.dispose();
      this.viewer.requestRender();
    }
  }

  /**
   * Shows a parameterization (ParamResult of protocol.js; its arrays become the geometry's).
   * @param {object} result
   * @param {[number, number]} range log10 ends of the heat map
   */
  setParam(result, range) {
    this.clearSurface();
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(result.position, 3));
    g.setAttribute('uv', new THREE.BufferAttribute(result.uv, 2));
    g.setAttribute('distortion', new THREE.BufferAttribute(result.cornerDistortion, 1));
    g.setAttribute('face', new THREE.BufferAttribute(result.cornerFace, 1));
    // The input mesh's bounds hold: the refined mesh is the same surface.
    g.boundingSphere = this.viewer.mesh?.geometry.boundingSphere?.clone() ?? null;
    if (!g.boundingSphere) g.computeBoundingSphere();
    this.surface = new THREE.Mesh(g, this.material);
    this.surface.name = 'param-surface';
    this.group.add(this.surface);
    this.material.uniforms.range.value.set(range[0], range[1]);
    this.apply();
  }

  /**
   * Shows the quad mesh: its edges over the surface, and shaded in mode 'quads'.
   * @param {{segments: Float32Array, positions: Float32Array, index: Uint32Array,
   *   normal: Float32Array}|null} quads the QuadResult of protocol.js; null: none
   */
  setQuads(quads) {
    if (this.quads) {
      this.group.remove(this.quads, this.quadSurface);
      this.quads.geometry.dispose();
      this.quadSurface.geometry.dispose();
      this.quads = null;
      this.quadSurface = null;
    }
    if (quads) {
      const { segments } = quads;
      const s = new THREE.BufferGeometry();
      s.setAttribute('position', new THREE.BufferAttribute(quads.positions, 3));
      s.setAttribute('normal', new THREE.BufferAttribute(quads.normal, 3));
      s.setIndex(new THREE.BufferAttribute(quads.index, 1));
      s.boundingSphere = this.viewer.mesh?.geometry.boundingSphere?.clone() ?? null;
      if (!s.boundingSphere) s.computeBoundingSphere();
      this.quadSurface = new THREE.Mesh(s, this.quadSurfaceMaterial);
      this.quadSurface.name = 'quad-surface';
      this.group.add(this.quadSurface);
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(segments, 3));
      g.boundingSphere = this.viewer.mesh?.geometry.boundingSphere?.clone() ?? null;
      if (!g.boundingSphere) g.computeBoundingSphere();
      this.quads = new THREE.LineSegments(g, this.quadMaterial);
      this.quads.name = 'quad-edges';
      this.quads.renderOrder = 2;
      this.group.add(this.quads);
    }
    this.apply();
  }

  /** @param {'surface'|'checker'|'distortion'|'quads'} mode */
  setMode(mode) {
    this.mode = mode;
    this.apply();
  }

  setShowQuads(on) {
    this.showQuads = on;
    this.apply();
  }

  /** Checker cell size (the target quad edge length). */
  setCell(length) {
    this.material.uniforms.cell.value = length;
    this.quadMaterial.uniforms.bias.value = 0.3 * length;
    this.viewer.requestRender();
  }

  get hasParam() {
    return this.surface !== null;
  }

  apply() {
    const quadShown = this.mode === 'quads' && this.quadSurface !== null;
    const param = !quadShown && this.mode !== 'surface' && this.mode !== 'quads' && this.surface !== null;
    if (this.surface) this.surface.visible = param;
    if (this.quadSurface) this.quadSurface.visible = quadShown;
    if (this.viewer.mesh) this.viewer.mesh.visible = !param && !quadShown;
    this.material.uniforms.mode.value = this.mode === 'distortion' ? 1 : 0;
    if (this.quads) this.quads.visible = this.showQuads || quadShown;
    this.viewer.requestRender();
  }

  clearSurface() {
    if (!this.surface) return;
    this.group.remove(this.surface);
    this.surface.geometry.dispose();
    this.surface = null;
  }

  /** Removes everything (a new mesh or layout). */
  clear() {
    this.clearSurface();
    this.setQuads(null);
  }
}
