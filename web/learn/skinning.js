// #demo/skinning: Figure 8 (paper section 5), volume preservation combined with skinning. A small
// skeleton (three bones in a chain) drives the level-0 cage of a ridged tube by linear blend
// skinning; left the skinned cage as it is, right the same target through the volume-preserving
// correction (section 4). Linear blend skinning loses volume where bones bend and twist (the
// "candy wrapper"); the correction gives it back.
import { THREE, explain } from './stage.js';
import { twinEditors, runDemo } from './demo-common.js';

const RINGS = 7, SEGMENTS = 6, RADIUS = 0.55, HALF = 3, LEVELS = 2;
const JOINTS = [-1, 1]; // x of the two joints (the root bone is fixed)

/** The base mesh: a capped tube along x, rings of SEGMENTS vertices at x = -3..3, caps at +-3.5. */
export function tubeBase() {
  const positions = [-HALF - 0.5, 0, 0];
  for (let i = 0; i < RINGS; i++) {
    const x = -HALF + (2 * HALF) * i / (RINGS - 1);
    for (let j = 0; j < SEGMENTS; j++) {
      const t = 2 * Math.PI * j / SEGMENTS;
      positions.push(x, RADIUS * Math.cos(t), RADIUS * Math.sin(t));
    }
  }
  positions.push(HALF + 0.5, 0, 0);
  const last = 1 + RINGS * SEGMENTS;
  const ring = (i, j) => 1 + i * SEGMENTS + (j % SEGMENTS);
  const faces = [];
  for (let j = 0; j < SEGMENTS; j++) faces.push(0, ring(0, j + 1), ring(0, j));
  for (let i = 0; i + 1 < RINGS; i++)
    for (let j = 0; j < SEGMENTS; j++) {
      const a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
      // alternating diagonals: irregular valences, a less uniform tube
      if ((i + j) % 2) faces.push(a, d, c, a, b, d);
      else faces.push(a, b, c, b, d, c);
    }
  for (let j = 0; j < SEGMENTS; j++) faces.push(last, ring(RINGS - 1, j), ring(RINGS - 1, j + 1));
  return { positions: Float64Array.from(positions), faces: Uint32Array.from(faces) };
}

/** Ridges on the fine surface: the radius grows by up to 18 % on bands across the tube. */
function ridged(positions) {
  const out = positions.slice();
  for (let i = 0; i < out.length; i += 3) {
    const x = out[i];
    const bump = 1 + 0.18 * Math.max(0, Math.cos(2 * Math.PI * x / 1.0)) ** 3 * (Math.abs(x) < HALF ? 1 : 0);
    out[i + 1] *= bump;
    out[i + 2] *= bump;
  }
  return out;
}

const smooth = (t) => (t <= 0 ? 0 : t >= 1 ? 1 : t * t * (3 - 2 * t));

/** Bone weights of a point at x: [root, middle, tip], a partition of unity blending over 1.2 units. */
function weights(x) {
  const s1 = smooth((x - JOINTS[0]) / 1.2 + 0.5), s2 = smooth((x - JOINTS[1]) / 1.2 + 0.5);
  return [1 - s1, s1 - s2, s2];
}

/** Bone matrices for the pose: bend a1 at the first joint, bend a2 and twist tw at the second. */
function pose(a1, a2, tw, out) {
  const about = (x, rotation) => new THREE.Matrix4().makeTranslation(x, 0, 0).multiply(rotation).multiply(new THREE.Matrix4().makeTranslation(-x, 0, 0));
  out[0].identity();
  out[1].copy(about(JOINTS[0], new THREE.Matrix4().makeRotationZ(a1)));
  out[2].copy(out[1]).multiply(about(JOINTS[1], new THREE.Matrix4().makeRotationZ(a2).multiply(new THREE.Matrix4().makeRotationX(tw))));
  return out;
}

export async function mount({ mrvol, layout, el }) {
  explain(layout.text, 'Skinning (Figure 8, section 5)', [
    'The paper animates a horse through its control mesh with a skeleton (skinning) and keeps the volume of the ' +
      'fine mesh. Here a ridged tube (N = 674 vertices, n = 2, control mesh of 44 vertices at e = 0) is moved by ' +
      'three bones in a chain: the middle bone bends, the last one bends and twists.',
    'Each frame, <b>linear blend skinning</b> moves every control vertex by the weighted sum of its bones\' ' +
      'transforms. <b>Volume free</b> (red): that target as it is; linear blend skinning shrinks the tube where it bends ' +
      'and collapses it where it twists. <b>Volume preserved</b> (green): the same target through the volume-preserving correction ' +
      '(section 4, formula (6), iterated to 1e-5): the control mesh swells a little everywhere instead; the ridges ' +
      '(details) ride along.',
    'The chart plots both volumes over time, divided by the reference volume. The skeleton is the dark line. Each ' +
      'panel also shows the other tube, faint (red: free, green: preserved): where the faint one shows through, the ' +
      'tubes differ.',
  ]);
  const mr = mrvol.subdivide(tubeBase(), { levels: LEVELS, scheme: 'loop' });
  mr.setPositions(ridged(mr.positions()));
  const twins = twinEditors({ mrvol, mr, level: 0, scheme: 'loop', layout, ghostOther: true });
  twins.stage.frame([0, 0.6, 0], 3.2, [0.15, 0.9, 1]);
  const restCage = twins.kept.cagePositions();
  const cageWeights = [];
  for (let i = 0; i < restCage.length; i += 3) cageWeights.push(weights(restCage[i]));

  const bones = twins.stage.panels.map(({ scene }) => {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(12), 3));
    const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0x24292f, depthTest: false }));
    const joints = new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0x24292f, size: 9, sizeAttenuation: false, depthTest: false }));
    line.renderOrder = joints.renderOrder = 3;
    line.frustumCulled = joints.frustumCulled = false;
    scene.add(line, joints);
    return geometry;
  });

  const matrices = [new THREE.Matrix4(), new THREE.Matrix4(), new THREE.Matrix4()];
  const target = new Float64Array(restCage.length);
  const held = new Uint8Array(twins.kept.cageSize);
  const p = new THREE.Vector3(), q = new THREE.Vector3(), sum = new THREE.Vector3();
  const sim = { t: 0 };
  function apply() {
    const t = sim.t;
    pose(0.7 * Math.sin(1.3 * t), 0.8 * Math.sin(1.3 * t + 1), 1.6 * Math.sin(0.65 * t), matrices);
    for (let i = 0; i < restCage.length; i += 3) {
      p.fromArray(restCage, i);
      sum.set(0, 0, 0);
      cageWeights[i / 3].forEach((w, b) => { if (w) sum.addScaledVector(q.copy(p).applyMatrix4(matrices[b]), w); });
      sum.toArray(target, i);
    }
    twins.drive(target, held);
    const chain = [[-HALF - 0.5, 0], [JOINTS[0], 1], [JOINTS[1], 2], [HALF + 0.5, 2]];
    for (const geometry of bones) {
      const a = geometry.getAttribute('position');
      chain.forEach(([x, b], k) => {
        q.set(x, 0, 0).applyMatrix4(matrices[b]);
        a.setXYZ(k, q.x, q.y, q.z);
      });
      a.needsUpdate = true;
    }
    twins.chart.draw();
  }
  function advance(dt) {
    sim.t += dt;
    apply();
  }
  apply();
  return runDemo({
    layout, el, mr, twins: () => twins, advance, restart: () => { sim.t = 0; apply(); }, dt: 1 / 30,
    debug: () => ({ ...twins.debug(), t: sim.t, vertices: mr.vertexCount, cageSize: twins.kept.cageSize,
      colors: twins.parts.map((p) => p.mesh.material.color.getHex()) }),
  }).view;
}
