// #demo/bunny: pulling ears, Figure 7 (paper section 5). A few control vertices are pulled out and
// back (the paper's direct manipulation in an editing tool, here scripted); the fine features ride
// along through the multiresolution representation. One panel without, one with the volume
// constraint: the pulled ears grow the free mesh, the preserved one keeps its volume and its
// proportions. The Stanford bunny when public/models has one, otherwise the blob sample.
import { sampleModels } from 'virtual:mrvol-models';
import { THREE, explain, fetchSample, control, select, bounds } from './stage.js';
import { twinEditors, runDemo, cageDragging } from './demo-common.js';

/**
 * Two "ears". upright (the bunny, y up): the highest cage vertex, then the highest one at least
 * 12 % of the size away from it. Otherwise: the vertex farthest from the centroid, then the
 * farthest one at least 45 degrees away.
 */
export function pickEars(cage, upright = false) {
  const n = cage.length / 3;
  const c = [0, 0, 0];
  for (let i = 0; i < n; i++) for (let k = 0; k < 3; k++) c[k] += cage[3 * i + k] / n;
  const dir = (i) => [0, 1, 2].map((k) => cage[3 * i + k] - c[k]);
  const len = (v) => Math.hypot(...v);
  if (upright) {
    const size = Math.max(...[...Array(n).keys()].map((i) => len(dir(i))));
    const high = [...Array(n).keys()].sort((a, b) => cage[3 * b + 1] - cage[3 * a + 1]);
    const top = high[0];
    const other = high.find((i) => len([0, 1, 2].map((k) => cage[3 * i + k] - cage[3 * top + k])) > 0.12 * size) ?? high[1];
    return { ears: [top, other], centroid: c };
  }
  const order = [...Array(n).keys()].sort((a, b) => len(dir(b)) - len(dir(a)));
  const first = order[0];
  const a = dir(first);
  const second = order.find((i) => {
    const b = dir(i);
    return i !== first && (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (len(a) * len(b)) < Math.cos(Math.PI / 4);
  }) ?? order[1];
  return { ears: [first, second], centroid: c };
}

export async function mount({ mrvol, layout, el, stale }) {
  const name = sampleModels.includes('bunny') ? 'bunny' : sampleModels.find((m) => m.startsWith('bunny')) ?? 'blob';
  const isBunny = name.startsWith('bunny');
  explain(layout.text, 'Pulling ears (Figure 7, section 5)', [
    'In Figure 7 the ears of the Stanford bunny (N = 2002, n = 2, e = 0) are pulled by moving a few vertices of ' +
      'its control mesh; the volume constraint keeps the proportions and the multiresolution keeps the fine features. ' +
      (isBunny ? `Here: the ${name} sample, its two highest control vertices (the ear tips) as the ears.` : 'There is no bunny among the samples yet: here the blob (N = 1026, n = 4) plays its part, ' +
        'its two most protruding control vertices as the ears.'),
    'The two ears (held) are pulled out and back along their direction from the centre. <b>Volume free</b> (red): nothing else moves, ' +
      'the volume grows with the ears. <b>Volume preserved</b> (green): the rest of the control mesh (the free set F: every cage vertex but ' +
      'the held ones, section 4.1) absorbs the minimal correction (6), so the body shrinks a little as the ears grow.',
    'Choose the level e of the control mesh: the coarser, the larger the pulled region.',
    '<b>Drag</b> any control vertex yourself (the animation pauses): the small charts follow the drag, the ' +
      'correction\'s multiplier λ (the preserved cage is the target plus λ times the volume gradient on the free ' +
      'vertices, formula (6)) and both volumes. Pull outwards and λ turns negative: the body shrinks to pay for it.',
  ]);
  const text = await fetchSample(name);
  if (stale()) return null;
  const mesh = mrvol.readObj(text);
  const mr = mrvol.openMesh(mesh);
  const n = mr.levels;
  const levelSelect = control(layout.controls, 'level e', select([...Array(n + 1).keys()].map((l) => [String(l), String(l)]), String(isBunny ? 0 : Math.min(2, n)), 'bunny-level'));
  const amplitudeSelect = control(layout.controls, 'pull', select([['0.3', '30 %'], ['0.6', '60 %'], ['1', '100 %']], '1', 'bunny-pull'));
  const b = bounds(mesh.positions);
  let twins = null, restCage, ears, centroid, target, held, dragging = null;
  const sim = { t: 0 };

  function build() {
    dragging?.dispose();
    twins?.dispose();
    layout.readouts.replaceChildren();
    layout.bottom.replaceChildren();
    const level = Number(levelSelect.value);
    twins = twinEditors({ mrvol, mr, level, scheme: 'loop', layout, dragCharts: true });
    dragging = cageDragging(twins, { onStart: () => demo?.controls.pause() });
    restCage = twins.kept.cagePositions();
    ({ ears, centroid } = pickEars(restCage, isBunny));
    // Seen across the plane of the two ears: both stick out of the silhouette.
    const [u, v] = ears.map((e) => [0, 1, 2].map((k) => restCage[3 * e + k] - centroid[k]));
    let view = new THREE.Vector3().crossVectors(new THREE.Vector3(...u), new THREE.Vector3(...v)).toArray();
    if (Math.hypot(...view) < 1e-9) view = [0.45, 0.35, 1];
    twins.stage.frame(b.center, (isBunny ? 1.2 : 1.5) * b.radius, view);
    target = new Float64Array(restCage.length);
    held = new Uint8Array(twins.kept.cageSize);
    for (const e of ears) held[e] = 1;
    sim.t = 0;
    apply();
  }

  function apply() {
    const amount = Number(amplitudeSelect.value) * 0.5 * (1 - Math.cos(1.5 * sim.t)); // out and back
    target.set(restCage);
    for (const e of ears)
      for (let k = 0; k < 3; k++) target[3 * e + k] += amount * (restCage[3 * e + k] - centroid[k]);
    twins.drive(target, held);
    twins.chart.draw();
  }
  function advance(dt) {
    sim.t += dt;
    apply();
  }
  let demo = null;
  build();
  demo = runDemo({
    layout, el, mr, twins: () => twins, advance, restart: () => { sim.t = 0; apply(); }, dt: 1 / 30,
    debug: () => ({ ...twins.debug(), model: name, level: Number(levelSelect.value), ears: ears.map((e) => twins.cageVertices[e]), t: sim.t,
      dragging: dragging.dragging(), playing: demo.controls.playing() }),
    actions: {
      /** Viewport pixels of cage vertex c (cage order) in panel p, for pointer tests. */
      screenOfCage(c, p = 1) {
        const cage = twins.parts[p].editor.cagePositions();
        return twins.stage.screenOf([cage[3 * c], cage[3 * c + 1], cage[3 * c + 2]], p);
      },
    },
  });
  // A new pull shows at once, paused too.
  amplitudeSelect.addEventListener('change', () => {
    apply();
    twins.stage.requestRender();
  });
  levelSelect.addEventListener('change', () => {
    build();
    if (demo.controls.playing()) demo.start();
  });
  return demo.view;
}
