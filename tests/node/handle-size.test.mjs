// The handle dots' 'auto' size (lib/three/handle-size.mjs): the spacing -> size clamp, and the
// median on-screen edge length under a projection (checked against three.js's own projection).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import * as THREE from 'three';
import { AUTO_HANDLE_SIZE, handleSizeForSpacing, medianEdgeSpacing, SPACING_SAMPLES } from '../../lib/three/handle-size.mjs';

test('spacing -> size: k times the spacing, clamped to [min, max], max when unknown', () => {
  const { k, min, max } = AUTO_HANDLE_SIZE;
  assert.ok(k >= 0.5 && k <= 0.6 && min >= 5 && min <= 6 && max === 13);
  assert.equal(handleSizeForSpacing(1), min);
  assert.equal(handleSizeForSpacing(min / k - 1), min);
  assert.equal(handleSizeForSpacing(16), Math.round(4 * k * 16) / 4);
  assert.ok(handleSizeForSpacing(16) > min && handleSizeForSpacing(16) < max);
  assert.equal(handleSizeForSpacing(1000), max);
  for (const unknown of [NaN, 0, -3, Infinity]) assert.equal(handleSizeForSpacing(unknown), max);
  assert.equal(handleSizeForSpacing(10, { k: 1, min: 2, max: 8 }), 8);
  // monotone: a cage seen larger never gets smaller dots
  let last = 0;
  for (let s = 0.5; s < 60; s += 0.25) {
    const size = handleSizeForSpacing(s);
    assert.ok(size >= last, `size(${s}) = ${size} < ${last}`);
    last = size;
  }
});

/** A grid of n x n points spaced `step` apart in the plane z = 0, its horizontal and vertical edges. */
function grid(n, step) {
  const positions = [], edges = [];
  for (let j = 0; j < n; j++)
    for (let i = 0; i < n; i++) {
      positions.push(i * step, j * step, 0);
      if (i + 1 < n) edges.push(j * n + i, j * n + i + 1);
      if (j + 1 < n) edges.push(j * n + i, (j + 1) * n + i);
    }
  return { positions: new Float64Array(positions), edges: new Uint32Array(edges) };
}

test('the median edge length on the screen is the projected length three.js gives', () => {
  const { positions, edges } = grid(30, 0.1);  // 1740 edges: sampled
  assert.ok(edges.length / 2 > SPACING_SAMPLES);
  const width = 390, height = 844;
  const camera = new THREE.PerspectiveCamera(35, width / height, 0.01, 100);
  camera.position.set(1.45, 1.45, 6);  // straight on: every edge the same length on the screen
  camera.lookAt(1.45, 1.45, 0);
  camera.updateMatrixWorld();
  const m = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).elements;
  const screen = (x, y, z) => {
    const p = new THREE.Vector3(x, y, z).project(camera);
    return [(p.x + 1) / 2 * width, (1 - p.y) / 2 * height];
  };
  const [ax, ay] = screen(1.4, 1.4, 0), [bx, by] = screen(1.5, 1.4, 0);
  const expected = Math.hypot(ax - bx, ay - by);
  const spacing = medianEdgeSpacing(positions, edges, m, width, height);
  assert.ok(Math.abs(spacing - expected) / expected < 0.02, `${spacing} vs ${expected}`);
  // twice as near: twice the spacing
  camera.position.set(1.45, 1.45, 3);
  camera.updateMatrixWorld();
  const near = medianEdgeSpacing(positions, edges, new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).elements, width, height);
  assert.ok(Math.abs(near / spacing - 2) < 0.05, `ratio ${near / spacing}`);
  // behind the camera: nothing seen
  camera.position.set(1.45, 1.45, -3);
  camera.lookAt(1.45, 1.45, -10);
  camera.updateMatrixWorld();
  const behind = medianEdgeSpacing(positions, edges, new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).elements, width, height);
  assert.ok(Number.isNaN(behind));
  assert.equal(handleSizeForSpacing(behind), AUTO_HANDLE_SIZE.max);
});
