// Measures the room light that web/room-light.js keeps: three.js's RoomEnvironment drawn into a
// cube map and projected onto spherical harmonics (three's LightProbeGenerator). Not part of the
// app (a cube render and a read-back): tests/browser/room-light.test.mjs runs it against the
// three.js in node_modules and prints the coefficients to keep when they differ.
import * as THREE from 'three';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { LightProbeGenerator } from 'three/addons/lights/LightProbeGenerator.js';

/** The room's spherical harmonics: 9 RGB coefficients, [[r, g, b], ...], from a cube map of `size` px. */
export async function measureRoomLight({ size = 128 } = {}) {
  const renderer = new THREE.WebGLRenderer();
  const target = new THREE.WebGLCubeRenderTarget(size, { type: THREE.HalfFloatType });
  const room = new RoomEnvironment();
  try {
    new THREE.CubeCamera(0.1, 100, target).update(renderer, room);
    const probe = await LightProbeGenerator.fromCubeRenderTarget(renderer, target);
    return probe.sh.coefficients.map((c) => [c.x, c.y, c.z]);
  } finally {
    target.dispose();
    room.dispose();
    renderer.dispose();
  }
}
