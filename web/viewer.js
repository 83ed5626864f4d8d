// The three.js view: the fine mesh (flat or smooth shading), the level-e cage over it (edges and
// handle points), orbit/pan/zoom, rendering on demand. It draws what it is given and projects
// handles to the screen; it knows nothing of the core.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const MESH_COLOR = 0xc9b8a0;
const CAGE_COLOR = 0x1f6feb;
const HANDLE_COLOR = new THREE.Color(0x1f6feb);
const SELECTED_COLOR = new THREE.Color(0xf0a020);
const HOVER_COLOR = new THREE.Color(0x3fb950);

// Scratch objects: pointer handlers and projections do not allocate.
const scratch = new THREE.Vector3();

function discTexture() {
  const size = 64;
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = size;
  const g = canvas.getContext('2d');
  g.beginPath();
  g.arc(size / 2, size / 2, size / 2 - 4, 0, 2 * Math.PI);
  g.fillStyle = '#ffffff';
  g.fill();
  g.lineWidth = 6;
  g.strokeStyle = '#202020';
  g.stroke();
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}

export class Viewer {
  /** @param {HTMLElement} container the element the canvas fills */
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setClearColor(0xf4f5f7);
    container.appendChild(this.renderer.domElement);
    this.canvas = this.renderer.domElement;

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.camera.position.set(0, 0, 6);
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 1.4));
    const key = new THREE.DirectionalLight(0xffffff, 1.8);
    key.position.set(2, 3, 4);
    this.camera.add(key); // the light follows the view

    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('change', () => this.requestRender());

    this.meshMaterial = new THREE.MeshStandardMaterial({
      color: MESH_COLOR, roughness: 0.65, metalness: 0.0, flatShading: true,
      side: THREE.DoubleSide, // open meshes show their inside
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.mesh = null;
    this.cageVisible = new THREE.LineBasicMaterial({ color: CAGE_COLOR });
    this.cageHidden = new THREE.LineBasicMaterial({ color: CAGE_COLOR, transparent: true, opacity: 0.22, depthTest: false });
    this.cageLines = null;
    this.cageLinesHidden = null;
    this.handleMaterial = new THREE.PointsMaterial({
      size: 13, sizeAttenuation: false, vertexColors: true, map: discTexture(), alphaTest: 0.5,
      depthTest: false, transparent: false,
    });
    this.handles = null;
    this.cageGroup = new THREE.Group();
    this.scene.add(this.cageGroup);

    this.cageCount = 0;
    this.cagePositions = null; // Float64Array, 3 per handle
    this.selection = new Set();
    this.hover = -1;
    this.flat = true;
    this.onFrame = null; // (renderMs) => void, called after each rendered frame

    this.frameRequested = false;
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  /**
   * Compiles the shader programs of the mesh, cage and handles ahead of the first model (software
   * WebGL takes a few hundred ms for them), while the core and the model are still loading.
   */
  precompile() {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9), 3));
    geometry.setIndex([0, 1, 2]);
    const placeholders = [
      new THREE.Mesh(geometry, this.meshMaterial),
      new THREE.LineSegments(geometry, this.cageVisible),
      new THREE.LineSegments(geometry, this.cageHidden),
      new THREE.Points(geometry, this.handleMaterial),
    ];
    this.scene.add(...placeholders);
    try {
      this.renderer.compile(this.scene, this.camera);
    } finally {
      this.scene.remove(...placeholders);
      geometry.dispose();
    }
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  requestRender() {
    if (this.frameRequested) return;
    this.frameRequested = true;
    requestAnimationFrame(() => {
      this.frameRequested = false;
      const started = performance.now();
      this.renderer.render(this.scene, this.camera);
      this.onFrame?.(performance.now() - started);
    });
  }

  /** Replaces the fine mesh. positions: Float64Array (3 per vertex), faces: Uint32Array. */
  setMesh(positions, faces) {
    if (this.mesh) {
      this.scene.remove(this.mesh);
      this.mesh.geometry.dispose();
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setIndex(new THREE.BufferAttribute(faces.length > 0 ? new Uint32Array(faces) : new Uint32Array(0), 1));
    this.mesh = new THREE.Mesh(geometry, this.meshMaterial);
    this.scene.add(this.mesh);
    if (!this.flat) geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    this.requestRender();
  }

  /** Points the camera at the mesh and the cage. */
  frameAll() {
    let sphere = null;
    if (this.mesh) sphere = this.mesh.geometry.boundingSphere.clone();
    if (this.cageLines) {
      this.cageLines.geometry.computeBoundingSphere();
      const cage = this.cageLines.geometry.boundingSphere;
      sphere = sphere ? sphere.union(cage) : cage.clone();
    }
    if (sphere) this.frame(sphere);
  }

  /** Points the camera at a bounding sphere. */
  frame(sphere) {
    const r = Math.max(sphere.radius, 1e-6);
    const vertical = THREE.MathUtils.degToRad(this.camera.fov / 2);
    const horizontal = Math.atan(Math.tan(vertical) * this.camera.aspect);
    const distance = r / Math.sin(Math.min(vertical, horizontal)) * 1.3; // room for the panels
    const direction = new THREE.Vector3(0.45, 0.35, 1).normalize();
    this.controls.target.copy(sphere.center);
    this.camera.position.copy(sphere.center).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  /** New fine positions, same connectivity. */
  updateMesh(positions) {
    const attribute = this.mesh.geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    if (!this.flat) this.mesh.geometry.computeVertexNormals();
    this.mesh.geometry.computeBoundingSphere();
    this.requestRender();
  }

  setFlat(flat) {
    this.flat = flat;
    this.meshMaterial.flatShading = flat;
    this.meshMaterial.needsUpdate = true;
    if (!flat && this.mesh) this.mesh.geometry.computeVertexNormals();
    this.requestRender();
  }

  setLayers({ mesh, cage }) {
    if (this.mesh) this.mesh.visible = mesh;
    this.cageGroup.visible = cage;
    this.requestRender();
  }

  /** Replaces the cage: positions (3 per handle) and edges (pairs of handle indices). */
  setCage(positions, edges) {
    for (const object of [this.cageLines, this.cageLinesHidden, this.handles]) {
      if (!object) continue;
      this.cageGroup.remove(object);
      object.geometry.dispose();
    }
    this.cageCount = positions.length / 3;
    this.cagePositions = Float64Array.from(positions);
    const lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    lineGeometry.setIndex(new THREE.BufferAttribute(new Uint32Array(edges), 1));
    this.cageLines = new THREE.LineSegments(lineGeometry, this.cageVisible);
    this.cageLinesHidden = new THREE.LineSegments(lineGeometry, this.cageHidden);
    this.cageLinesHidden.renderOrder = 1;
    const pointGeometry = new THREE.BufferGeometry();
    pointGeometry.setAttribute('position', lineGeometry.getAttribute('position'));
    pointGeometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * this.cageCount), 3));
    this.handles = new THREE.Points(pointGeometry, this.handleMaterial);
    this.handles.renderOrder = 2;
    for (const object of [this.cageLines, this.cageLinesHidden, this.handles]) object.frustumCulled = false;
    this.cageGroup.add(this.cageLines, this.cageLinesHidden, this.handles);
    this.selection = new Set();
    this.hover = -1;
    this.updateColors();
  }

  updateCage(positions) {
    this.cagePositions.set(positions);
    const attribute = this.cageLines.geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    this.requestRender();
  }

  setSelection(selection) {
    this.selection = new Set(selection);
    this.updateColors();
  }

  setHover(index) {
    if (index === this.hover) return;
    this.hover = index;
    this.updateColors();
  }

  updateColors() {
    if (!this.handles) return;
    const colors = this.handles.geometry.getAttribute('color');
    for (let i = 0; i < this.cageCount; i++) {
      const c = this.selection.has(i) ? SELECTED_COLOR : i === this.hover ? HOVER_COLOR : HANDLE_COLOR;
      colors.setXYZ(i, c.r, c.g, c.b);
    }
    colors.needsUpdate = true;
    this.requestRender();
  }

  /**
   * Handle positions on the screen: [x0, y0, x1, y1, ...] in CSS pixels relative to the canvas,
   * and the depth of each (NDC z) in `depths` when given.
   */
  projectHandles(out = new Float64Array(2 * this.cageCount), depths = null) {
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    this.camera.updateMatrixWorld();
    for (let i = 0; i < this.cageCount; i++) {
      scratch.fromArray(this.cagePositions, 3 * i).project(this.camera);
      out[2 * i] = (scratch.x + 1) / 2 * w;
      out[2 * i + 1] = (1 - scratch.y) / 2 * h;
      if (depths) depths[i] = scratch.z;
    }
    return out;
  }

  /** The handle nearest to a canvas point (CSS pixels) within `radius` pixels, or -1. */
  pickHandle(x, y, radius = 8) {
    if (!this.cageGroup.visible || this.cageCount === 0) return -1;
    const screen = this.projectHandles(undefined, this.pickDepths ??= new Float64Array(this.cageCount));
    let best = -1, bestD = Infinity, bestZ = Infinity;
    for (let i = 0; i < this.cageCount; i++) {
      const z = this.pickDepths[i];
      if (z < -1 || z > 1) continue; // behind the camera or clipped
      const dx = screen[2 * i] - x, dy = screen[2 * i + 1] - y;
      const d = dx * dx + dy * dy;
      if (d > radius * radius) continue;
      // nearest on screen; between handles about as near, the one in front
      if (best < 0 || d < bestD - 1 || (Math.abs(d - bestD) <= 1 && z < bestZ)) {
        best = i;
        bestD = d;
        bestZ = z;
      }
    }
    return best;
  }

  /** Ray through a canvas point (CSS pixels). */
  rayAt(x, y, ray = new THREE.Ray()) {
    const ndcX = x / this.canvas.clientWidth * 2 - 1, ndcY = 1 - y / this.canvas.clientHeight * 2;
    this.camera.updateMatrixWorld();
    ray.origin.setFromMatrixPosition(this.camera.matrixWorld);
    ray.direction.set(ndcX, ndcY, 0.5).unproject(this.camera).sub(ray.origin).normalize();
    return ray;
  }

  /** Camera's view direction (unit, world). */
  viewDirection(out = new THREE.Vector3()) {
    return this.camera.getWorldDirection(out);
  }
}

export { THREE };
