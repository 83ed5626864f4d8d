// The three.js objects an editing view draws, shared by the mrvol/three component, the web editor's
// viewer and the teaching views: a shaded surface that takes new positions, a cage (edges seen and
// hidden, round handle dots with a colour each), arrows, bounds. They draw arrays they are given.
import * as THREE from 'three';

import { AUTO_HANDLE_SIZE, handleSizeForSpacing, medianEdgeSpacing } from './handle-size.mjs';

export { edgesOf, quadEdgesOf, trianglesOfQuads } from './edges.mjs';
export { AUTO_HANDLE_SIZE, handleSizeForSpacing, medianEdgeSpacing } from './handle-size.mjs';

export const SURFACE_COLOR = 0xc9b8a0;
export const CAGE_COLOR = 0x1f6feb;

/**
 * A shaded surface (THREE.Mesh) over flat positions (3 per vertex) and faces; `colors` (3 per
 * vertex, 0..1) optional. setPositions() takes new positions of the same vertices.
 */
export class SurfaceMesh extends THREE.Mesh {
  #flat;
  #color;
  constructor(positions, faces, { color = SURFACE_COLOR, colors = null, flat = true, opacity = 1, material = null } = {}) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(faces), 1));
    if (colors) geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(colors), 3));
    super(geometry, material ?? SurfaceMesh.material({ color: colors ? 0xffffff : color, vertexColors: Boolean(colors), flat, opacity }));
    this.ownsMaterial = !material;
    this.#flat = this.material.flatShading;
    this.#color = color;
    if (!this.#flat) geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
  }

  /** The surface material: double-sided (open meshes show their inside), pushed back behind lines. */
  static material({ color = SURFACE_COLOR, vertexColors = false, flat = true, opacity = 1 } = {}) {
    return new THREE.MeshStandardMaterial({
      color, vertexColors, roughness: 0.65, metalness: 0, flatShading: flat, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1, transparent: opacity < 1, opacity,
      depthWrite: opacity >= 1,
    });
  }

  setPositions(positions) {
    const attribute = this.geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    if (!this.material.flatShading) this.geometry.computeVertexNormals();
    this.geometry.computeBoundingSphere();
  }

  setColors(colors) {
    const geometry = this.geometry;
    if (!geometry.getAttribute('color')) {
      geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(colors), 3));
      this.material.vertexColors = true;
      this.material.color.set(0xffffff);
      this.material.needsUpdate = true;
    } else {
      geometry.getAttribute('color').array.set(colors);
      geometry.getAttribute('color').needsUpdate = true;
    }
  }

  clearColors() {
    if (!this.geometry.getAttribute('color')) return;
    this.geometry.deleteAttribute('color');
    this.material.vertexColors = false;
    this.material.color.set(this.#color);
    this.material.needsUpdate = true;
  }

  dispose() {
    this.geometry.dispose();
    if (this.ownsMaterial) this.material.dispose();
  }
}

/** A round dot with a dark rim, for handle points (needs a 2D canvas: browsers). */
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

/** Opacity of a handle seen through the surface (the cage's hidden edges: 0.22). */
export const HIDDEN_HANDLE_OPACITY = 0.3;
// The seen handles are drawn this much of their distance nearer the camera (same place on the
// screen): a dot on a surface sloped away is not cut in half by it.
const SEEN_HANDLE_DEPTH_SCALE = 0.98;
const scratchMatrix = new THREE.Matrix4();
const scratchSize = new THREE.Vector2();

/**
 * A cage: its edges (solid where seen, faint through the surface) and a dot per handle with a
 * colour of its own (setHandleColors), drawn twice: at full strength where the surface does not
 * hide it, faint through the surface (handles picked out with setHandleColors' `strong` stay at
 * full strength there). `positions` keeps the handle positions (Float64Array, 3 per handle) for
 * picking. `handleSize`: CSS px, or 'auto' (default): sized to the cage's spacing on the screen
 * (lib/three/handle-size.mjs), measured again before a frame when the camera, the view's size or
 * the cage changed. Materials given (CageObject.materials()) stay the caller's.
 */
export class CageObject extends THREE.Group {
  #autoSize;
  #key = new Float64Array(19).fill(NaN);
  #version = 0;
  constructor(positions, edges, { color = CAGE_COLOR, handles = true, handleSize = 'auto', opacity = 1, materials = null } = {}) {
    super();
    if (handleSize !== 'auto' && !(Number(handleSize) > 0)) throw new TypeError(`handleSize: a number of CSS pixels or 'auto', not ${handleSize}`);
    this.count = positions.length / 3;
    this.positions = Float64Array.from(positions);
    this.edges = Uint32Array.from(edges);
    this.ownsMaterials = !materials;
    const fixed = handleSize === 'auto' ? AUTO_HANDLE_SIZE.max : Number(handleSize);
    this.materials = materials ?? CageObject.materials({ color, handleSize: fixed, opacity, points: handles });
    this.#autoSize = handleSize === 'auto';
    /** The handle dot size (CSS px) last drawn or measured. */
    this.handlePixelSize = fixed;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setIndex(new THREE.BufferAttribute(this.edges, 1));
    this.lines = new THREE.LineSegments(geometry, this.materials.lines);
    this.hiddenLines = new THREE.LineSegments(geometry, this.materials.hidden);
    this.hiddenLines.renderOrder = 1;
    this.add(this.lines, this.hiddenLines);
    this.handles = null;
    this.hiddenHandles = null;
    if (handles) {
      const points = new THREE.BufferGeometry();
      points.setAttribute('position', geometry.getAttribute('position'));
      points.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * this.count), 3));
      // through the surface: the same points, colours with an alpha (faint, or full for `strong` handles)
      const behind = new THREE.BufferGeometry();
      behind.setAttribute('position', geometry.getAttribute('position'));
      behind.setAttribute('color', new THREE.BufferAttribute(new Float32Array(4 * this.count), 4));
      this.hiddenHandles = new THREE.Points(behind, this.materials.hiddenHandles);
      this.hiddenHandles.renderOrder = 2;
      this.handles = new THREE.Points(points, this.materials.handles);
      this.handles.renderOrder = 3;  // over the faint dots
      const size = (renderer, scene, camera) => {
        if (renderer.getRenderTarget() !== null) return;  // a shadow or an off-screen pass
        renderer.getSize(scratchSize);
        this.updateHandleSize(camera, scratchSize.x, scratchSize.y, { matrices: false });
      };
      this.hiddenHandles.onBeforeRender = size;
      this.handles.onBeforeRender = size;
      this.add(this.hiddenHandles, this.handles);
      this.baseColor = new THREE.Color(color);
      this.setHandleColors(() => this.baseColor);
    }
    for (const object of this.children) object.frustumCulled = false;
  }

  /** 'auto' or the fixed size in CSS px. */
  get handleSize() { return this.#autoSize ? 'auto' : this.handlePixelSize; }

  /**
   * The handle size (CSS px) for `camera` on a `width` x `height` CSS-pixel view, set on the handle
   * materials. 'auto': from the cage's median edge length on the screen, measured only when the
   * camera, the view, this object's place or the cage moved since the last call. `matrices`:
   * update the camera's and this object's world matrices first (a render has).
   */
  updateHandleSize(camera, width, height, { matrices = true } = {}) {
    if (!this.#autoSize || !this.handles) return this.handlePixelSize;
    if (matrices) {
      camera.updateMatrixWorld();
      this.updateWorldMatrix(true, false);
    }
    const m = scratchMatrix.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).multiply(this.matrixWorld).elements;
    const key = this.#key;
    let same = key[16] === width && key[17] === height && key[18] === this.#version;
    for (let i = 0; i < 16 && same; i++) same = key[i] === m[i];
    if (same) return this.handlePixelSize;
    key.set(m);
    key[16] = width;
    key[17] = height;
    key[18] = this.#version;
    const size = handleSizeForSpacing(medianEdgeSpacing(this.positions, this.edges, m, width, height));
    this.handlePixelSize = size;
    this.materials.handles.size = size;
    if (this.materials.hiddenHandles) this.materials.hiddenHandles.size = size;
    return size;
  }

  /**
   * { lines, hidden, handles, hiddenHandles }: solid edges, edges through the surface (no depth
   * test), handle dots where seen (vertex colours; depth-tested, drawn a little nearer the camera)
   * and through the surface (no depth test, vertex colours with alpha: every handle can be seen
   * and grabbed).
   */
  static materials({ color = CAGE_COLOR, handleSize = 13, opacity = 1, points = true } = {}) {
    const map = points ? discTexture() : null;
    const handles = points ? new THREE.PointsMaterial({
      size: handleSize, sizeAttenuation: false, vertexColors: true, map, alphaTest: 0.5,
      // in the transparent list with the faint dots, after them (renderOrder): drawn over them
      transparent: true, depthWrite: false,
    }) : null;
    if (handles) {
      handles.onBeforeCompile = (shader) => {
        shader.vertexShader = shader.vertexShader.replace('#include <project_vertex>', `#include <project_vertex>
  if ( isPerspectiveMatrix( projectionMatrix ) ) {
    mvPosition.xyz *= ${SEEN_HANDLE_DEPTH_SCALE.toFixed(4)};
    gl_Position = projectionMatrix * mvPosition;
  }`);
      };
      handles.customProgramCacheKey = () => 'mrvol-seen-handles';
    }
    return {
      lines: new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity }),
      hidden: new THREE.LineBasicMaterial({ color, transparent: true, opacity: 0.22 * opacity, depthTest: false }),
      handles,
      hiddenHandles: points ? new THREE.PointsMaterial({
        size: handleSize, sizeAttenuation: false, vertexColors: true, map, transparent: true, opacity,
        depthTest: false, depthWrite: false,
      }) : null,
    };
  }

  setPositions(positions) {
    this.positions.set(positions);
    this.#version++;
    const attribute = this.lines.geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    this.lines.geometry.computeBoundingSphere();
  }

  /**
   * colorOf(i) -> THREE.Color for every handle i; strong(i) -> true: handle i is drawn at full
   * strength through the surface too (default: the handles not of the base colour).
   */
  setHandleColors(colorOf, strong = null) {
    if (!this.handles) return;
    const colors = this.handles.geometry.getAttribute('color');
    const behind = this.hiddenHandles.geometry.getAttribute('color');
    for (let i = 0; i < this.count; i++) {
      const c = colorOf(i);
      colors.setXYZ(i, c.r, c.g, c.b);
      const full = strong ? strong(i) : !c.equals(this.baseColor);
      behind.setXYZW(i, c.r, c.g, c.b, full ? 1 : HIDDEN_HANDLE_OPACITY);
    }
    colors.needsUpdate = true;
    behind.needsUpdate = true;
  }

  dispose() {
    this.lines.geometry.dispose();
    this.handles?.geometry.dispose();
    this.hiddenHandles?.geometry.dispose();
    if (this.ownsMaterials) {
      this.materials.handles?.map?.dispose();
      for (const material of Object.values(this.materials)) material?.dispose();
    }
  }
}

/** Arrows as line segments from points `from` along vectors `vectors` (same length, flat) scaled by `scale`. */
export function arrows(from, vectors, { color = 0xd1242f, scale = 1 } = {}) {
  const count = from.length / 3;
  const p = new Float32Array(count * 6 * 3);
  const a = new THREE.Vector3(), v = new THREE.Vector3(), side = new THREE.Vector3(), up = new THREE.Vector3();
  let n = 0;
  for (let i = 0; i < count; i++) {
    a.fromArray(from, 3 * i);
    v.fromArray(vectors, 3 * i).multiplyScalar(scale);
    const length = v.length();
    if (length < 1e-12) continue;
    const tip = a.clone().add(v);
    side.crossVectors(v, Math.abs(v.y) < 0.9 * length ? up.set(0, 1, 0) : up.set(1, 0, 0)).setLength(0.12 * length);
    const back = tip.clone().addScaledVector(v, -0.25);
    for (const [s, t] of [[a, tip], [tip, back.clone().add(side)], [tip, back.clone().sub(side)]]) {
      s.toArray(p, 3 * n++);
      t.toArray(p, 3 * n++);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(p.slice(0, 3 * n), 3));
  const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color }));
  lines.frustumCulled = false;
  return lines;
}

/** Bounding sphere of flat positions: { center: [x, y, z], radius }. */
export function bounds(positions) {
  const box = new THREE.Box3();
  const p = new THREE.Vector3();
  for (let i = 0; i < positions.length; i += 3) box.expandByPoint(p.fromArray(positions, i));
  const center = box.getCenter(new THREE.Vector3());
  let r2 = 0;
  for (let i = 0; i < positions.length; i += 3) r2 = Math.max(r2, center.distanceToSquared(p.fromArray(positions, i)));
  return { center: center.toArray(), radius: Math.max(Math.sqrt(r2), 1e-6) };
}

/**
 * Puts a perspective camera (and a controls' target, when given) on a bounding sphere seen from
 * `direction`, `margin` times the distance at which it just fits.
 */
export function frameSphere(camera, { center, radius }, { controls = null, direction = [0.45, 0.35, 1], margin = 1.3 } = {}) {
  const vertical = THREE.MathUtils.degToRad(camera.fov / 2);
  const horizontal = Math.atan(Math.tan(vertical) * camera.aspect);
  const distance = Math.max(radius, 1e-6) / Math.sin(Math.min(vertical, horizontal)) * margin;
  const d = new THREE.Vector3(...direction).normalize();
  camera.position.set(...center).addScaledVector(d, distance);
  camera.near = distance / 100;
  camera.far = distance * 100;
  camera.lookAt(...center);
  camera.updateProjectionMatrix();
  if (controls) {
    controls.target.set(...center);
    controls.update();
  }
}
