// The 3D view: three.js scene, camera, orbit controls, lights and the surface mesh.
// It renders on demand (after a change, a camera move or a resize), never in a busy loop.
// Later layers (layout curves, nodes, textures) go into `viewer.overlays` and call
// `viewer.requestRender()`.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

/** The viewport's background; the e2e test reads it from the screenshot's border. */
export const BACKGROUND = 0x1f232b;
const SURFACE = 0xc6cbd2;
/** Direction the camera looks from, relative to the mesh's centre (y up): front, a little
 * from the right and above. */
const VIEW_FROM = new THREE.Vector3(0.7, 0.5, 1).normalize();

export class Viewer {
  /** @param {HTMLElement} container the element the canvas fills */
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, powerPreference: 'high-performance' });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.domElement.classList.add('viewport-canvas');
    container.prepend(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);

    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
    this.scene.add(this.camera);
    this.addLights();

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.dampingFactor = 0.12;
    this.controls.addEventListener('change', () => this.requestRender());

    this.material = new THREE.MeshStandardMaterial({
      color: SURFACE,
      roughness: 0.62,
      metalness: 0.0,
      flatShading: true,
      side: THREE.DoubleSide,
      // Pushed back a little so the wireframe drawn at the same depth stays visible.
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    this.wireMaterial = new THREE.MeshBasicMaterial({
      color: 0x0b0d12,
      wireframe: true,
      transparent: true,
      opacity: 0.22,
      depthWrite: false,
    });

    /** The surface mesh (null until a mesh is set); later used for picking. */
    this.mesh = null;
    this.wire = null;
    /** Layers drawn over the surface (layout curves, nodes, ...). */
    this.overlays = new THREE.Group();
    this.resolution = new THREE.Vector2(1, 1);
    this.scene.add(this.overlays);

    this.framePending = false;
    this.frameWaiters = [];
    this.home = null;
    /** CSS pixels at the view's sides covered by controls drawn over it: meshes are framed
     * in the rest, its middle where the camera looks. */
    this.insets = { top: 0, right: 0, bottom: 0, left: 0 };

    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  addLights() {
    // A dim sky/ground ambient keeps the unlit side readable; the shape comes from the key.
    // (three's physical lights: a surface facing a light of intensity I gets I/π × albedo.)
    this.scene.add(new THREE.HemisphereLight(0xeef2ff, 0x2a2622, 1.4));
    // Key and fill ride with the camera, so the side the viewer sees is always lit: the key
    // from the upper left, the fill low from the right. (Positions are in the camera's frame.)
    const key = new THREE.DirectionalLight(0xfff6ea, 3.4);
    key.position.set(-0.8, 1.4, 0.2);
    const fill = new THREE.DirectionalLight(0xcfdcff, 0.9);
    fill.position.set(1.2, -0.4, 0.4);
    for (const light of [key, fill]) {
      light.target.position.set(0, 0, -1);
      this.camera.add(light, light.target);
    }
  }

  /**
   * Shows a triangle mesh, replacing the previous one, and frames the camera on it.
   * @param {{positions: Float32Array, triangles: Uint32Array}} mesh
   * @returns {Promise<void>} settles once a frame with the new mesh has been rendered
   */
  setMesh({ positions, triangles }) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(triangles, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    geometry.computeBoundingBox();

    if (this.mesh) {
      this.scene.remove(this.mesh, this.wire);
      this.mesh.geometry.dispose();
    }
    this.mesh = new THREE.Mesh(geometry, this.material);
    this.wire = new THREE.Mesh(geometry, this.wireMaterial);
    this.wire.visible = this.wireframe ?? false;
    this.wire.renderOrder = 1;
    this.scene.add(this.mesh, this.wire);

    this.home = this.fitView(positions, geometry.boundingSphere);
    this.resetView();
    return this.nextFrame();
  }

  /**
   * Replaces the layers drawn over the surface with `group` (null clears them), and the
   * surface's per-vertex colours with `colors` (null: plain surface).
   */
  setOverlay(group, colors = null) {
    for (const child of [...this.overlays.children]) {
      this.overlays.remove(child);
      child.traverse((o) => {
        o.geometry?.dispose();
      });
    }
    if (group) this.overlays.add(group);
    this.setSurfaceColors(colors);
    return this.nextFrame();
  }

  /** The surface's per-vertex colours (rgb per vertex), or the plain surface with null. */
  setSurfaceColors(colors) {
    if (this.mesh) {
      const geometry = this.mesh.geometry;
      if (colors) geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
      else geometry.deleteAttribute('color');
      this.material.vertexColors = Boolean(colors);
      this.material.color.set(colors ? 0xffffff : SURFACE);
      this.material.needsUpdate = true;
    }
    this.requestRender();
  }

  /** The mesh's bounding radius (to size overlays), 1 before a mesh is set. */
  get radius() {
    return this.home?.radius ?? 1;
  }

  /**
   * Says how much of the view controls cover at each side ({ top, right, bottom, left } in CSS
   * pixels): the camera's picture is shifted so the point it looks at is in the middle of the
   * rest, and meshes are framed to fit in it.
   */
  setInsets(insets) {
    this.insets = { top: 0, right: 0, bottom: 0, left: 0, ...insets };
    this.resize();
  }

  /** Looks from direction `dir` ([x, y, z] from the mesh's centre) when framing meshes. */
  setViewFrom(dir) {
    this.viewFrom = new THREE.Vector3(...dir).normalize();
  }

  /** @param {'flat'|'smooth'} mode */
  setShading(mode) {
    this.material.flatShading = mode === 'flat';
    this.material.needsUpdate = true;
    this.requestRender();
  }

  /** Shows or hides the subtle wireframe over the surface. */
  setWireframe(on) {
    this.wireframe = on;
    if (this.wire) this.wire.visible = on;
    this.requestRender();
  }

  /**
   * Flies the camera to look at point `at` ([x, y, z] on the surface) head-on, from the side
   * its nearest vertex's normal points to, and marks it with a ring drawn over everything.
   * @returns {Promise<void>} settles when the camera is there
   */
  flyTo(at) {
    if (!this.mesh) return Promise.resolve();
    const point = new THREE.Vector3(...at);
    const geometry = this.mesh.geometry;
    const positions = geometry.getAttribute('position');
    let nearest = 0, best = Infinity;
    for (let v = 0; v < positions.count; v++) {
      const d = point.distanceToSquared(new THREE.Vector3().fromBufferAttribute(positions, v));
      if (d < best) { best = d; nearest = v; }
    }
    const normal = new THREE.Vector3().fromBufferAttribute(geometry.getAttribute('normal'), nearest);
    if (normal.lengthSq() < 1e-12) normal.copy(this.camera.position).sub(this.controls.target);
    const distance = this.radius * 1.2;
    const position = point.clone().addScaledVector(normal.normalize(), distance);
    this.setMarker(at);
    const from = { target: this.controls.target.clone(), position: this.camera.position.clone() };
    const t0 = performance.now();
    const ms = 500;
    return new Promise((resolve) => {
      const step = () => {
        const s = Math.min(1, (performance.now() - t0) / ms);
        const e = s * s * (3 - 2 * s);
        this.controls.target.lerpVectors(from.target, point, e);
        this.camera.position.lerpVectors(from.position, position, e);
        this.controls.update();
        this.requestRender();
        if (s < 1) requestAnimationFrame(step);
        else this.nextFrame().then(resolve);
      };
      requestAnimationFrame(step);
    });
  }

  /** A ring marking point `at` ([x, y, z]), drawn over the surface; null removes it. */
  setMarker(at) {
    if (this.marker) {
      this.scene.remove(this.marker);
      this.marker.geometry.dispose();
      this.marker.material.dispose();
      this.marker = null;
    }
    if (at) {
      const r = this.radius;
      this.marker = new THREE.Mesh(
        new THREE.SphereGeometry(r * 0.035, 24, 16),
        new THREE.MeshBasicMaterial({ color: 0xff9d2e, transparent: true, opacity: 0.55, depthTest: false, depthWrite: false }),
      );
      this.marker.position.set(...at);
      this.marker.renderOrder = 7;
      this.scene.add(this.marker);
    }
    this.requestRender();
  }

  /** Back to the view chosen when the mesh was loaded. */
  resetView() {
    if (!this.home) return;
    const { target, position, radius } = this.home;
    this.camera.position.copy(position);
    this.camera.up.set(0, 1, 0);
    this.camera.near = radius / 200;
    this.camera.far = radius * 60;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(target);
    this.controls.minDistance = radius / 100;
    this.controls.maxDistance = radius * 20;
    this.controls.update();
    this.requestRender();
  }

  /**
   * The camera placement that fits all vertices into the view from VIEW_FROM, with a margin.
   * Uses the vertices rather than the bounding sphere so the mesh fills the viewport.
   */
  fitView(positions, sphere) {
    const back = (this.viewFrom ?? VIEW_FROM).clone();
    const right = new THREE.Vector3(0, 1, 0).cross(back).normalize();
    const up = back.clone().cross(right);
    const c = sphere.center;
    // Extents in the camera's frame, around the sphere's centre.
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (let i = 0; i < positions.length; i += 3) {
      const dx = positions[i] - c.x, dy = positions[i + 1] - c.y, dz = positions[i + 2] - c.z;
      const x = dx * right.x + dy * right.y + dz * right.z;
      const y = dx * up.x + dy * up.y + dz * up.z;
      if (x < x0) x0 = x;
      if (x > x1) x1 = x;
      if (y < y0) y0 = y;
      if (y > y1) y1 = y;
    }
    const target = c.clone()
      .addScaledVector(right, (x0 + x1) / 2)
      .addScaledVector(up, (y0 + y1) / 2);
    // Distance at which every vertex projects inside the frustum, less the covered sides
    // (margin 15 %).
    const free = this.freeShare();
    const tanV = (Math.tan(THREE.MathUtils.degToRad(this.camera.fov) / 2) / 1.15) * free.y;
    const tanH = (tanV / free.y) * this.camera.aspect * free.x;
    let distance = 0;
    for (let i = 0; i < positions.length; i += 3) {
      const dx = positions[i] - target.x, dy = positions[i + 1] - target.y, dz = positions[i + 2] - target.z;
      const x = dx * right.x + dy * right.y + dz * right.z;
      const y = dx * up.x + dy * up.y + dz * up.z;
      const z = dx * back.x + dy * back.y + dz * back.z;
      distance = Math.max(distance, z + Math.abs(x) / tanH, z + Math.abs(y) / tanV);
    }
    const radius = Math.max(sphere.radius, 1e-9);
    if (!(distance > 0) || !Number.isFinite(distance)) distance = radius * 3;
    return { target, position: target.clone().addScaledVector(back, distance), radius };
  }

  /** Asks for one frame; several requests before it is drawn give one frame. */
  requestRender() {
    if (this.framePending) return;
    this.framePending = true;
    requestAnimationFrame(() => this.render());
  }

  /** A promise that settles after the next rendered frame. */
  nextFrame() {
    return new Promise((resolve) => {
      this.frameWaiters.push(resolve);
      this.requestRender();
    });
  }

  render() {
    this.framePending = false;
    // With damping the controls keep moving after the pointer stops; update() then sends
    // 'change', which asks for the next frame, until the motion settles.
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
    const waiters = this.frameWaiters;
    this.frameWaiters = [];
    for (const resolve of waiters) resolve();
  }

  /** The share of the view's width and height the insets leave free. */
  freeShare() {
    const { clientWidth: w, clientHeight: h } = this.container;
    const { top, right, bottom, left } = this.insets;
    if (!(w > 0 && h > 0)) return { x: 1, y: 1 };
    return { x: Math.max(0.3, (w - left - right) / w), y: Math.max(0.3, (h - top - bottom) / h) };
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    // Thick lines (LineMaterial) need the canvas size in pixels.
    this.resolution.set(w, h);
    this.camera.aspect = w / h;
    // The picture shifted by half the difference of opposite insets: what the camera looks
    // at lands in the middle of the uncovered part.
    const { top, right, bottom, left } = this.insets;
    if (top || right || bottom || left) this.camera.setViewOffset(w, h, -(left - right) / 2, -(top - bottom) / 2, w, h);
    else this.camera.clearViewOffset();
    this.camera.updateProjectionMatrix();
    // Drawn at once: the resized canvas is blank until the next render.
    this.render();
  }

  dispose() {
    this.resizeObserver.disconnect();
    this.controls.dispose();
    this.mesh?.geometry.dispose();
    this.material.dispose();
    this.wireMaterial.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }
}
