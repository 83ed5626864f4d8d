// #demo/balance: the bunny's ears pulled, keeping its balance. The volume constraint alone (left)
// keeps the volume, but the pulled ears carry mass up and forward: the centre of mass wanders, and
// a statue would tip over. Keeping the first moments too (right: four constraints, the volume and
// V c, solved together as in the paper's formula (6) with four rows) holds the centre of mass in
// place. Markers show each centre of mass and its plumb line to the floor; the chart plots how far
// each has drifted, as a fraction of the model's size.
import { sampleModels } from 'virtual:mrvol-models';
import { THREE, Stage, surface, wire, Chart, explain, fetchSample, control, select, bounds, edgesOf, readoutTable } from './stage.js';
import { playControls } from './demo-common.js';
import { pickEars } from './bunny.js';

const FREE = '#cf222e', KEPT = '#1a7f37';

export async function mount({ mrvol, layout, el, stale }) {
  const name = sampleModels.includes('bunny-remeshed') ? 'bunny-remeshed' : 'blob';
  const isBunny = name.startsWith('bunny');
  explain(layout.text, 'Keeping balance (beyond the paper, section 6)', [
    'The paper ends with what its machinery also allows: "the center of mass ... could be computed in the MR basis", ' +
      'since all it needs is a multi-linear quantity. The first moments V c = (1/24) Σ det(a, b, c)(a + b + c) over the ' +
      'triangles are such a quantity (quadrilinear), so the centre of mass c can be kept like the volume.',
    `The ${isBunny ? "bunny's two ears" : "blob's two most protruding control vertices"} are pulled out and back. ` +
      '<b>Volume kept</b> (the first panel): the volume is kept (one constraint); the ears carry mass outwards and the centre of mass (red) drifts. ' +
      '<b>Volume and balance kept</b> (the second): volume and centre of mass are kept (four constraints, δ = Jᵀ(J Jᵀ)⁻¹ r); the rest of the body ' +
      'leans the other way so that the centre (green) stays over the same point of the floor.',
    'The chart: each centre\'s distance from where it started, in % of the bounding-box diagonal.',
  ]);
  const text = await fetchSample(name);
  if (stale()) return null;
  const mesh = mrvol.readObj(text);
  const mr = mrvol.openMesh(mesh);
  const amplitudeSelect = control(layout.controls, 'pull', select([['0.3', '30 %'], ['0.6', '60 %'], ['1', '100 %']], '1', 'balance-pull'));
  const b = bounds(mesh.positions);
  const lo = [0, 1, 2].map((k) => Math.min(...mesh.positions.filter((_, i) => i % 3 === k)));
  const hi = [0, 1, 2].map((k) => Math.max(...mesh.positions.filter((_, i) => i % 3 === k)));
  const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  const floorY = lo[1];

  const editors = [mr.createEditor({ level: 0, keep: ['volume'] }), mr.createEditor({ level: 0, keep: ['volume', 'centroid'] })];
  const stage = new Stage(layout.stage, ['volume kept', 'volume and balance kept']);
  const faces = mr.faces();
  const cageVertices = editors[0].cageVertices();
  const edges = edgesOf(mr.levelFaces(0), new Map(Array.from(cageVertices, (v, i) => [v, i])));
  const start = Array.from(editors[0].centroid());
  const parts = editors.map((editor, p) => {
    const scene = stage.panels[p].scene;
    const body = surface(editor.positions(), faces, { color: p ? 0x4fae68 : 0xe5765a });
    const cage = wire(editor.cagePositions(), edges);
    const color = p ? KEPT : FREE;
    const material = new THREE.MeshBasicMaterial({ color, depthTest: false, transparent: true });
    const marker = new THREE.Mesh(new THREE.SphereGeometry(0.018 * diagonal, 20, 14), material);
    marker.renderOrder = 10;
    // The plumb line's foot on the floor: over the ring while balanced.
    const foot = new THREE.Mesh(new THREE.CircleGeometry(0.012 * diagonal, 24), new THREE.MeshBasicMaterial({ color, depthTest: false, transparent: true, side: THREE.DoubleSide }));
    foot.rotation.x = -Math.PI / 2;
    foot.renderOrder = 11;
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
      new THREE.LineBasicMaterial({ color, depthTest: false, transparent: true }));
    line.renderOrder = 10;
    // Where the centre started: a ring on the floor.
    const ring = new THREE.Mesh(new THREE.RingGeometry(0.022 * diagonal, 0.03 * diagonal, 40), new THREE.MeshBasicMaterial({ color: 0x24292f, side: THREE.DoubleSide, depthTest: false, transparent: true }));
    ring.rotation.x = -Math.PI / 2;
    ring.renderOrder = 10;
    ring.position.set(start[0], floorY, start[2]);
    const plate = new THREE.Mesh(new THREE.PlaneGeometry(1.6 * diagonal, 1.6 * diagonal), new THREE.MeshStandardMaterial({ color: 0xdfe3e8, roughness: 1, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2 }));
    plate.rotation.x = -Math.PI / 2;
    plate.position.set(b.center[0], floorY - 1e-4 * diagonal, b.center[2]);
    scene.add(plate, ring, body, cage, marker, line, foot);
    return { editor, body, cage, marker, line, foot };
  });
  // Room above for the pulled ears, the floor in view below.
  stage.frame([b.center[0], b.center[1] + 0.3 * b.radius, b.center[2]], 1.6 * b.radius, [0.15, 0.25, 1]);

  layout.bottom.hidden = false;
  const chartRow = el('div', { class: 'learn-charts' });
  layout.bottom.append(chartRow);
  const chart = new Chart(chartRow, { title: 'centre of mass drift, % of the diagonal', testid: 'balance-chart' });
  chart.add('volume kept', FREE);
  chart.add('volume and balance kept', KEPT);
  const set = readoutTable(layout.readouts, [
    ['drift, volume kept', 'balance-drift-free'], ['drift, balance kept', 'balance-drift-kept'],
    ['volume error (both)', 'balance-volume-error'], ['last step (4 rows)', 'balance-step'],
  ]);

  const restCage = editors[0].cagePositions();
  const { ears, centroid: cageCentre } = pickEars(restCage, isBunny);
  const held = new Uint8Array(editors[0].cageSize);
  for (const e of ears) held[e] = 1;
  const target = new Float64Array(restCage.length);
  const sim = { t: 0 };
  const stats = { steps: 0, maxDrift: [0, 0], drift: [0, 0], volumeError: 0, failures: 0, lastMs: 0 };
  const reference = editors[0].referenceVolume();

  function apply() {
    const amount = Number(amplitudeSelect.value) * 0.5 * (1 - Math.cos(1.5 * sim.t)); // out and back
    target.set(restCage);
    for (const e of ears)
      for (let k = 0; k < 3; k++) target[3 * e + k] += amount * (restCage[3 * e + k] - cageCentre[k]);
    parts.forEach((part, p) => {
      const started = performance.now();
      const report = part.editor.deformCage(target, held, { tolerance: 1e-5 });
      if (p === 1) stats.lastMs = performance.now() - started;
      if (!report.converged) {
        stats.failures++;
        layout.status.textContent = `A step did not converge: ${report.message}`;
      }
      part.body.update(part.editor.positions());
      part.cage.update(part.editor.cagePositions());
      const c = part.editor.centroid();
      part.marker.position.set(c[0], c[1], c[2]);
      part.line.geometry.setFromPoints([new THREE.Vector3(c[0], c[1], c[2]), new THREE.Vector3(c[0], floorY, c[2])]);
      part.foot.position.set(c[0], floorY, c[2]);
      stats.drift[p] = Math.hypot(c[0] - start[0], c[1] - start[1], c[2] - start[2]) / diagonal;
      stats.maxDrift[p] = Math.max(stats.maxDrift[p], stats.drift[p]);
      stats.volumeError = Math.max(stats.volumeError, Math.abs(part.editor.volume() - reference) / Math.abs(reference));
    });
    stats.steps++;
    chart.push(stats.drift.map((d) => 100 * d));
    chart.draw();
    set('balance-drift-free', `${(100 * stats.drift[0]).toFixed(3)} %`, stats.drift[0]);
    set('balance-drift-kept', `${(100 * stats.drift[1]).toExponential(2)} %`, stats.drift[1]);
    set('balance-volume-error', stats.volumeError.toExponential(2), stats.volumeError);
    set('balance-step', `${stats.lastMs.toFixed(1)} ms`, stats.lastMs);
  }
  const advance = (dt) => {
    sim.t += dt;
    apply();
  };
  const startLoop = () => stage.animate(advance);
  const stopLoop = () => stage.stop();
  // Back to the rest shape, the chart and the worst drifts from there.
  const restart = () => {
    sim.t = 0;
    chart.clear();
    stats.maxDrift = [0, 0];
    stats.volumeError = 0;
    apply();
    stage.resetView();
    stage.requestRender();
  };
  const controls = playControls(layout, el, { start: startLoop, stop: stopLoop, restart });
  // A new pull shows at once, paused too.
  amplitudeSelect.addEventListener('change', () => {
    apply();
    stage.requestRender();
  });
  apply();
  startLoop();
  return {
    dispose() {
      stage.stop();
      stage.dispose();
      for (const e of editors) e.delete();
      mr.delete();
    },
    actions: {
      pause: () => controls.pause(),
      restart,
      /** Advances the pull by `count` steps of `step` seconds (tests). */
      run(count, step = 1 / 30) {
        for (let i = 0; i < count; i++) advance(step);
        stage.render();
      },
    },
    debug: () => ({
      model: name, ears: ears.map((e) => cageVertices[e]), t: sim.t, steps: stats.steps, drift: [...stats.drift],
      maxDrift: [...stats.maxDrift], volumeError: stats.volumeError, failures: stats.failures, playing: controls.playing(),
      keeps: editors.map((e) => e.keepsCentroid()),
    }),
  };
}
