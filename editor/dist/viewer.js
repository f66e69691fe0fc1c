// The three.js viewport: draws one solve response (surface, control net,
// boundary, normal arrows, operators, handles), orbits the camera, and drags
// handles. It knows nothing about HTTP or the scene JSON: dragging reports
// positions through callbacks and the app decides what to do with them.
//
// Rendering is on demand (requestRender), not a continuous loop: the page
// stays idle when nothing moves, and `renderCount` counts real frames.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';
import { isList, srgbToLinear } from './util.js';

const COLORS = {
  background: 0x1d2026,
  net: 0x8d99a8,
  boundary: 0xffc53d,
  normals: 0x4fc3f7,
  operator: 0xff5fa2,
  target: 0xffffff,
  controlPoint: 0xe8ecf2,
  operatorHandle: 0xff5fa2,
  hover: 0xffd400,
  grid: 0x3a404b,
  gridCenter: 0x4a5260,
};

/** The default viewing direction (from the target towards the camera), z up. */
const DEFAULT_VIEW = new THREE.Vector3(0.85, -1.35, 0.95).normalize();

export class Viewer {
  /**
   * @param {HTMLElement} container  the element the canvas fills
   * @param {object} callbacks       { onHandleDrag(index, [x,y,z]), onHandleDragEnd(index), onRender(),
   *                                   constrainHandle(index, [x,y,z]) → where the dragged handle may be, or null,
   *                                   describeHandle(index) → the tooltip's text, or null for the position }
   */
  constructor(container, callbacks = {}) {
    this.container = container;
    this.callbacks = callbacks;
    this.renderCount = 0;
    this.handles = []; // the response's handle descriptors, same order as handleMeshes
    this.handleMeshes = [];
    this.drag = null; // { index, pointerId, plane, offset }
    this.hoverIndex = -1;
    this.scale = 1; // a length typical of the scene, fixed when the camera is framed
    this.framed = false;
    this.handlesLocked = false; // set while the handles drawn belong to a scene no longer loaded
    this.visibility = { surface: true, net: true, boundary: true, normals: true, operators: true, handles: true, grid: true };

    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    renderer.setClearColor(COLORS.background);
    this.renderer = renderer;
    this.canvas = renderer.domElement;
    this.canvas.dataset.testid = 'viewport-canvas';
    this.canvas.setAttribute('aria-label', 'Surface viewport: drag to orbit, right-drag to pan, wheel to zoom, drag a handle to move it');
    container.appendChild(this.canvas);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.copy(DEFAULT_VIEW).multiplyScalar(4);
    this.scene.add(this.camera);

    // Sky/ground fill plus a headlight that follows the camera, so the
    // surface is lit from wherever it is seen (CAD viewers do the same).
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x50525a, 1.6));
    const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
    headlight.position.set(0.3, 0.6, 1);
    this.camera.add(headlight);
    this.camera.add(headlight.target);

    // One group per toggleable layer.
    this.groups = {};
    for (const name of Object.keys(this.visibility)) {
      const g = new THREE.Group();
      g.name = name;
      this.groups[name] = g;
      this.scene.add(g);
    }

    // Materials live as long as the viewer: disposing a material frees its
    // shader program when nothing else uses it, and recompiling programs on
    // every live re-solve costs far more than the drawing itself.
    this.materials = {
      surface: new THREE.MeshStandardMaterial({
        vertexColors: true,
        side: THREE.DoubleSide,
        roughness: 0.55,
        metalness: 0.0,
        // Push the surface back a little so the net and boundary lying on
        // it are drawn cleanly on top.
        polygonOffset: true,
        polygonOffsetFactor: 1,
        polygonOffsetUnits: 1,
      }),
      net: new THREE.LineBasicMaterial({ color: COLORS.net, transparent: true, opacity: 0.85 }),
      netDots: new THREE.PointsMaterial({ color: COLORS.net, size: 4, sizeAttenuation: false }),
      boundary: new LineMaterial({ color: COLORS.boundary, linewidth: 3, worldUnits: false }),
      normalShaft: new THREE.LineBasicMaterial({ color: COLORS.normals }),
      normalHead: new THREE.MeshStandardMaterial({ color: COLORS.normals, roughness: 0.5 }),
      operator: new THREE.MeshStandardMaterial({ color: COLORS.operator, roughness: 0.4, emissive: 0x220011 }),
      operatorLine: new THREE.LineDashedMaterial({ color: COLORS.operator, dashSize: 0.02, gapSize: 0.014, transparent: true, opacity: 0.9 }),
      target: new THREE.MeshBasicMaterial({ color: COLORS.target, wireframe: true }),
      stem: new THREE.LineBasicMaterial({ color: COLORS.operatorHandle }),
    };
    this.handleGeometry = new THREE.SphereGeometry(1, 20, 14);
    this.handleMaterials = {
      control_point: new THREE.MeshStandardMaterial({ color: COLORS.controlPoint, roughness: 0.35, emissive: 0x222222 }),
      operator: new THREE.MeshStandardMaterial({ color: COLORS.operatorHandle, roughness: 0.35, emissive: 0x330011 }),
      hover: new THREE.MeshStandardMaterial({ color: COLORS.hover, roughness: 0.35, emissive: 0x553300 }),
    };

    this.raycaster = new THREE.Raycaster();
    this.tooltip = document.createElement('div');
    this.tooltip.className = 'tooltip';
    this.tooltip.hidden = true;
    container.appendChild(this.tooltip);

    // Handle dragging listens before OrbitControls is created: the same
    // pointerdown that grabs a handle must not also start an orbit.
    this.canvas.addEventListener('pointerdown', (e) => this.onPointerDown(e));
    this.canvas.addEventListener('pointermove', (e) => this.onPointerMove(e));
    this.canvas.addEventListener('pointerup', (e) => this.onPointerUp(e));
    this.canvas.addEventListener('pointercancel', (e) => this.onPointerUp(e));
    // Capture lost without a pointerup (the window lost focus, an alert):
    // the drag ends as if released.
    this.canvas.addEventListener('lostpointercapture', (e) => this.onPointerUp(e));
    this.canvas.addEventListener('pointerleave', () => this.setHover(-1));

    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.enableDamping = false; // damping needs a render loop
    this.controls.addEventListener('change', () => this.requestRender());

    this.initAxesGizmo();

    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  // ---------------------------------------------------------------- drawing

  /**
   * Draws a solve response. `frame` re-aims the camera (first solve of a
   * newly loaded scene). A handle being dragged keeps its dragged position.
   */
  update(response, { frame = false } = {}) {
    this.setSurface(response.mesh);
    if (frame || !this.framed) this.scale = this.typicalLength(response);
    this.setNet(response.net);
    this.setBoundary(response.boundary || []);
    this.setNormals(response.normals || []);
    this.setOperators(response.operators || []);
    this.setHandles(response.handles || []);
    if (frame || !this.framed) this.frame();
    this.requestRender();
  }

  /** Removes every child of a layer and frees its geometry (materials are shared). */
  clearGroup(name) {
    const g = this.groups[name];
    for (const child of [...g.children]) {
      g.remove(child);
      child.traverse((o) => {
        if (o.geometry !== this.handleGeometry) o.geometry?.dispose();
        if (o.isInstancedMesh) o.dispose();
        if (o.userData.ownMaterial) o.material.dispose();
      });
    }
  }

  setSurface(mesh) {
    this.clearGroup('surface');
    if (!mesh || !isList(mesh.positions) || mesh.positions.length < 9) return;
    const geometry = new THREE.BufferGeometry();
    const positions = Float32Array.from(mesh.positions);
    const nVerts = positions.length / 3;
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    const colors = new Float32Array(nVerts * 3);
    if (isList(mesh.colors) && mesh.colors.length === positions.length) {
      // The server's colours are sRGB (like the legend's hex stops); three.js
      // wants vertex colours in linear light.
      for (let k = 0; k < colors.length; k++) colors[k] = srgbToLinear(mesh.colors[k]);
    } else {
      colors.fill(0.55);
    }
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    if (isList(mesh.indices) && mesh.indices.length >= 3) {
      const Index = nVerts > 65535 ? Uint32Array : Uint16Array;
      geometry.setIndex(new THREE.BufferAttribute(new Index(mesh.indices), 1));
    }
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    const m = new THREE.Mesh(geometry, this.materials.surface);
    m.name = 'surface';
    this.groups.surface.add(m);
  }

  setNet(net) {
    this.clearGroup('net');
    if (!net || !Array.isArray(net.points) || !Array.isArray(net.edges) || net.edges.length === 0) return;
    const pts = net.points;
    const arr = new Float32Array(net.edges.length * 6);
    let k = 0;
    for (const [a, b] of net.edges) {
      const p = pts[a], q = pts[b];
      if (!p || !q) continue;
      arr[k++] = p[0]; arr[k++] = p[1]; arr[k++] = p[2];
      arr[k++] = q[0]; arr[k++] = q[1]; arr[k++] = q[2];
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(arr.subarray(0, k), 3));
    const lines = new THREE.LineSegments(geometry, this.materials.net);
    lines.name = 'net';
    this.groups.net.add(lines);
    // Small dots at the net's points (the free ones included) so the net
    // reads as a net, not only as lines.
    const dotGeometry = new THREE.BufferGeometry();
    dotGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(pts.flat()), 3));
    const dots = new THREE.Points(dotGeometry, this.materials.netDots);
    this.groups.net.add(dots);
  }

  setBoundary(polylines) {
    this.clearGroup('boundary');
    const segs = [];
    for (const line of polylines) {
      for (let k = 0; k + 1 < line.length; k++) segs.push(...line[k], ...line[k + 1]);
    }
    if (segs.length === 0) return;
    // Screen-space wide lines: WebGL's own lines are always 1 px.
    const geometry = new LineSegmentsGeometry();
    geometry.setPositions(segs);
    const lines = new LineSegments2(geometry, this.materials.boundary);
    lines.name = 'boundary';
    this.groups.boundary.add(lines);
  }

  setNormals(normals) {
    this.clearGroup('normals');
    if (normals.length === 0) return;
    const shafts = new Float32Array(normals.length * 6);
    const cone = new THREE.ConeGeometry(0.5, 1, 10);
    cone.translate(0, -0.5, 0); // tip at the origin, pointing +y
    const heads = new THREE.InstancedMesh(cone, this.materials.normalHead, normals.length);
    const m = new THREE.Matrix4();
    const q = new THREE.Quaternion();
    const up = new THREE.Vector3(0, 1, 0);
    const dir = new THREE.Vector3();
    const tip = new THREE.Vector3();
    normals.forEach((n, k) => {
      const [x, y, z] = n.at;
      dir.set(...n.dir);
      const len = dir.length();
      tip.set(x, y, z).add(dir);
      shafts.set([x, y, z, tip.x, tip.y, tip.z], k * 6);
      if (len > 0) q.setFromUnitVectors(up, dir.clone().divideScalar(len));
      const s = len * 0.22;
      m.compose(tip, q, new THREE.Vector3(s * 0.6, s, s * 0.6));
      heads.setMatrixAt(k, m);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(shafts, 3));
    this.groups.normals.add(new THREE.LineSegments(geometry, this.materials.normalShaft));
    this.groups.normals.add(heads);
  }

  setOperators(operators) {
    this.clearGroup('operators');
    const r = this.scale * 0.018;
    this.materials.operatorLine.dashSize = r * 1.5;
    this.materials.operatorLine.gapSize = r;
    for (const op of operators) {
      if (!Array.isArray(op.at)) continue;
      const marker = new THREE.Mesh(new THREE.OctahedronGeometry(r * 1.3), this.materials.operator);
      marker.position.set(...op.at);
      marker.name = op.name || op.kind || 'operator';
      this.groups.operators.add(marker);
      if (Array.isArray(op.target)) {
        const geometry = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(...op.at), new THREE.Vector3(...op.target)]);
        const line = new THREE.Line(geometry, this.materials.operatorLine);
        line.computeLineDistances();
        this.groups.operators.add(line);
        const target = new THREE.Mesh(new THREE.SphereGeometry(r * 0.9, 12, 8), this.materials.target);
        target.position.set(...op.target);
        this.groups.operators.add(target);
      }
    }
  }

  /**
   * Sets the draggable handles. Meshes are reused when the count is
   * unchanged (live solves re-send the same handles many times a second).
   */
  setHandles(handles) {
    const dragged = this.drag ? this.handles[this.drag.index] : null;
    if (dragged && handles[this.drag.index]?.pointer !== dragged.pointer) {
      // The handles changed under the drag: it ends, and the page is told.
      const index = this.drag.index;
      this.endDrag();
      this.callbacks.onHandleDragEnd?.(index);
    }
    if (handles.length !== this.handleMeshes.length) {
      this.clearGroup('handles');
      this.handleMeshes = handles.map((_, k) => {
        const mesh = new THREE.Mesh(this.handleGeometry, this.handleMaterials.control_point);
        mesh.userData.index = k;
        this.groups.handles.add(mesh);
        return mesh;
      });
      this.hoverIndex = -1;
    }
    this.handles = handles;
    const r = this.scale * 0.014;
    handles.forEach((h, k) => {
      const mesh = this.handleMeshes[k];
      mesh.scale.setScalar(h.kind === 'operator' ? r * 1.15 : r);
      mesh.material = this.materialFor(k);
      // The handle being dragged stays under the mouse, not where the
      // (possibly older) response says it is.
      if (!(this.drag && this.drag.index === k)) mesh.position.set(...h.position);
    });
    this.updateStems();
  }

  /** The lines from direction handles to their anchors. */
  updateStems() {
    if (this.stems) {
      this.stems.removeFromParent();
      this.stems.geometry.dispose();
      this.stems = null;
    }
    const segs = [];
    this.handles.forEach((h, k) => {
      const a = h.edit?.type === 'direction' ? h.edit.anchor : null;
      const p = this.handleMeshes[k]?.position;
      if (Array.isArray(a) && a.length === 3 && p) segs.push(...a, p.x, p.y, p.z);
    });
    if (segs.length === 0) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(segs), 3));
    this.stems = new THREE.LineSegments(geometry, this.materials.stem);
    this.stems.name = 'stems';
    this.groups.handles.add(this.stems);
  }

  materialFor(k) {
    if (k === this.hoverIndex || (this.drag && this.drag.index === k)) return this.handleMaterials.hover;
    return this.handles[k]?.kind === 'operator' ? this.handleMaterials.operator : this.handleMaterials.control_point;
  }

  /** Half the diagonal of everything drawn: sizes handles, markers, the grid. */
  typicalLength(response) {
    const box = this.contentBox(response);
    if (box.isEmpty()) return 1;
    return Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-9);
  }

  contentBox(response) {
    const box = new THREE.Box3();
    const v = new THREE.Vector3();
    const p = response?.mesh?.positions;
    if (p) for (let k = 0; k + 2 < p.length; k += 3) box.expandByPoint(v.set(p[k], p[k + 1], p[k + 2]));
    for (const q of response?.net?.points || []) box.expandByPoint(v.set(...q));
    for (const h of response?.handles || []) box.expandByPoint(v.set(...h.position));
    return box;
  }

  /** Aims the camera at everything drawn, from the default direction the first time. */
  frame() {
    const box = new THREE.Box3();
    for (const name of ['surface', 'net', 'handles', 'operators']) {
      if (this.groups[name].children.length) box.expandByObject(this.groups[name]);
    }
    if (box.isEmpty()) return;
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const radius = Math.max(sphere.radius, 1e-6);
    const fov = THREE.MathUtils.degToRad(this.camera.fov);
    const fit = Math.min(fov, 2 * Math.atan(Math.tan(fov / 2) * this.camera.aspect));
    const distance = (radius / Math.sin(fit / 2)) * 1.05;
    const dir = this.framed
      ? this.camera.position.clone().sub(this.controls.target).normalize()
      : DEFAULT_VIEW.clone();
    this.controls.target.copy(sphere.center);
    this.camera.position.copy(sphere.center).addScaledVector(dir, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.setGrid(box);
    this.framed = true;
    this.requestRender();
  }

  /** A grid in the xy plane just under the content, sized in round units. */
  setGrid(box) {
    this.clearGroup('grid');
    const size = box.getSize(new THREE.Vector3());
    const extent = Math.max(size.x, size.y, this.scale) * 1.6;
    const step = Math.pow(10, Math.floor(Math.log10(extent / 4)));
    const divisions = Math.min(200, Math.ceil(extent / step));
    const grid = new THREE.GridHelper(divisions * step, divisions, COLORS.gridCenter, COLORS.grid);
    grid.rotation.x = Math.PI / 2; // GridHelper lies in xz; we are z-up
    const center = box.getCenter(new THREE.Vector3());
    grid.position.set(Math.round(center.x / step) * step, Math.round(center.y / step) * step, box.min.z - size.z * 0.02);
    grid.material.transparent = true;
    grid.material.opacity = 0.6;
    grid.userData.ownMaterial = true; // GridHelper makes its own
    this.groups.grid.add(grid);
  }

  setVisible(layer, visible) {
    this.visibility[layer] = visible;
    this.groups[layer].visible = visible;
    if (layer === 'handles' && !visible) this.setHover(-1);
    this.requestRender();
  }

  // --------------------------------------------------------------- rendering

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.render();
    });
  }

  render() {
    const r = this.renderer;
    r.setScissorTest(false);
    r.setViewport(0, 0, this.width, this.height);
    r.render(this.scene, this.camera);
    this.renderAxesGizmo();
    this.renderCount++;
    this.callbacks.onRender?.(this.renderCount);
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth);
    const h = Math.max(1, this.container.clientHeight);
    this.width = w;
    this.height = h;
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.materials.boundary.resolution.set(w, h);
    this.requestRender();
  }

  /** A small xyz triad in the lower right corner, turning with the camera. */
  initAxesGizmo() {
    this.gizmoScene = new THREE.Scene();
    this.gizmoCamera = new THREE.OrthographicCamera(-1.5, 1.5, 1.5, -1.5, 0.1, 10);
    const axes = [
      [new THREE.Vector3(1, 0, 0), '#ef5350', 'x'],
      [new THREE.Vector3(0, 1, 0), '#66bb6a', 'y'],
      [new THREE.Vector3(0, 0, 1), '#42a5f5', 'z'],
    ];
    for (const [dir, color, name] of axes) {
      const geometry = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), dir]);
      this.gizmoScene.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color })));
      const c = document.createElement('canvas');
      c.width = c.height = 64;
      const g = c.getContext('2d');
      g.fillStyle = color;
      g.font = 'bold 44px system-ui, sans-serif';
      g.textAlign = 'center';
      g.textBaseline = 'middle';
      g.fillText(name, 32, 34);
      const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
      sprite.position.copy(dir).multiplyScalar(1.3);
      sprite.scale.setScalar(0.55);
      this.gizmoScene.add(sprite);
    }
  }

  renderAxesGizmo() {
    const size = 84;
    const r = this.renderer;
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    this.gizmoCamera.position.copy(dir).multiplyScalar(4);
    this.gizmoCamera.up.copy(this.camera.up);
    this.gizmoCamera.lookAt(0, 0, 0);
    r.autoClear = false;
    r.clearDepth();
    r.setScissorTest(true);
    r.setScissor(this.width - size - 8, 8, size, size);
    r.setViewport(this.width - size - 8, 8, size, size);
    r.render(this.gizmoScene, this.gizmoCamera);
    r.setScissorTest(false);
    r.autoClear = true;
  }

  // ---------------------------------------------------------------- picking

  /** The pointer event's position as normalized device coordinates. */
  ndc(e) {
    const rect = this.canvas.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1, -((e.clientY - rect.top) / rect.height) * 2 + 1);
  }

  /** The index of the handle under the pointer, or -1. */
  pickHandle(e) {
    if (!this.visibility.handles || this.handlesLocked || this.handleMeshes.length === 0) return -1;
    this.raycaster.setFromCamera(this.ndc(e), this.camera);
    const hits = this.raycaster.intersectObjects(this.handleMeshes, false);
    return hits.length ? hits[0].object.userData.index : -1;
  }

  /** Where the handle `index` is drawn, in page CSS pixels (the test hook). */
  handleScreenPosition(index) {
    const mesh = this.handleMeshes[index];
    if (!mesh) return null;
    const v = mesh.position.clone().project(this.camera);
    const rect = this.canvas.getBoundingClientRect();
    return {
      x: rect.left + ((v.x + 1) / 2) * rect.width,
      y: rect.top + ((1 - v.y) / 2) * rect.height,
      inView: Math.abs(v.x) <= 1 && Math.abs(v.y) <= 1 && v.z > -1 && v.z < 1,
    };
  }

  setHover(index) {
    if (index === this.hoverIndex) return;
    const previous = this.hoverIndex;
    this.hoverIndex = index;
    for (const k of [previous, index]) if (this.handleMeshes[k]) this.handleMeshes[k].material = this.materialFor(k);
    this.canvas.style.cursor = index >= 0 ? 'grab' : '';
    this.showTooltip(index);
    this.requestRender();
  }

  showTooltip(index) {
    const h = this.handles[index];
    const mesh = this.handleMeshes[index];
    if (!h || !mesh) {
      this.tooltip.hidden = true;
      return;
    }
    const p = mesh.position;
    const f = (x) => String(Number(x.toPrecision(5)));
    // A handle whose value is not its position (a direction, an offset)
    // says its value, as the page describes it.
    this.tooltip.textContent = this.callbacks.describeHandle?.(index) ?? `${h.label || h.pointer}  (${f(p.x)}, ${f(p.y)}, ${f(p.z)})`;
    const s = this.handleScreenPosition(index);
    const rect = this.container.getBoundingClientRect();
    this.tooltip.style.left = `${s.x - rect.left + 14}px`;
    this.tooltip.style.top = `${s.y - rect.top - 30}px`;
    this.tooltip.hidden = false;
  }

  onPointerDown(e) {
    if (e.button !== 0 || this.drag) return;
    const index = this.pickHandle(e);
    if (index < 0) return;
    // Keep OrbitControls (registered later on the same element) out of it.
    e.preventDefault();
    e.stopImmediatePropagation();
    this.controls.enabled = false;
    this.canvas.setPointerCapture(e.pointerId);
    const mesh = this.handleMeshes[index];
    // Move in the plane through the handle facing the camera; remember
    // where on the sphere it was grabbed so it does not jump.
    const normal = this.camera.getWorldDirection(new THREE.Vector3());
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, mesh.position);
    this.raycaster.setFromCamera(this.ndc(e), this.camera);
    const hit = this.raycaster.ray.intersectPlane(plane, new THREE.Vector3()) || mesh.position.clone();
    this.drag = { index, pointerId: e.pointerId, plane, offset: mesh.position.clone().sub(hit) };
    this.setHover(index);
    this.canvas.style.cursor = 'grabbing';
  }

  onPointerMove(e) {
    if (this.drag) {
      if (e.pointerId !== this.drag.pointerId) return;
      this.raycaster.setFromCamera(this.ndc(e), this.camera);
      const hit = this.raycaster.ray.intersectPlane(this.drag.plane, new THREE.Vector3());
      if (!hit) return; // plane seen edge-on
      const pos = hit.add(this.drag.offset);
      // A handle that is not a free point (a direction, a plane's offset)
      // stays where its value puts it: on its sphere or line.
      const kept = this.callbacks.constrainHandle?.(this.drag.index, [pos.x, pos.y, pos.z]);
      if (kept) pos.set(...kept);
      const mesh = this.handleMeshes[this.drag.index];
      mesh.position.copy(pos);
      this.updateStems();
      this.callbacks.onHandleDrag?.(this.drag.index, [pos.x, pos.y, pos.z]);
      this.showTooltip(this.drag.index);
      this.requestRender();
      return;
    }
    if (e.buttons === 0) this.setHover(this.pickHandle(e));
  }

  onPointerUp(e) {
    if (!this.drag || e.pointerId !== this.drag.pointerId) return;
    const index = this.drag.index;
    this.endDrag();
    this.callbacks.onHandleDragEnd?.(index);
  }

  endDrag() {
    if (!this.drag) return;
    try {
      this.canvas.releasePointerCapture(this.drag.pointerId);
    } catch {
      /* already released */
    }
    const index = this.drag.index;
    this.drag = null;
    this.controls.enabled = true;
    if (this.handleMeshes[index]) this.handleMeshes[index].material = this.materialFor(index);
    this.canvas.style.cursor = this.hoverIndex >= 0 ? 'grab' : '';
    this.requestRender();
  }

  get dragging() {
    return this.drag !== null;
  }
}
