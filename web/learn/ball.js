// #demo/ball: the bouncing spiky ball of Figure 6 (paper section 5). The level-0 cage (an
// icosahedron) follows a 1D physical model: the centre falls under gravity and, in contact with the
// floor, the ball is squashed vertically by a spring. The same cage targets drive two editors: left
// without preservation (the volume drops at every impact), right with it (section 4: the minimal
// correction restores the volume; the details ride along).
import { explain, fetchSample, control, select } from './stage.js';
import { twinEditors, runDemo } from './demo-common.js';

export async function mount({ mrvol, layout, el, stale }) {
  explain(layout.text, 'Bouncing spiky ball (Figure 6, section 5)', [
    'The spiky ball (N = 642, n = 3) is analysed to level e = 0: its coarse mesh is an icosahedron and the ' +
      'spikes are details. As in the paper, the coarse mesh is animated by simple physical 1D equations: the ' +
      'centre falls under gravity; while the ball touches the floor a spring squashes it vertically.',
    '<b>Volume free</b> (red): the squashed cage as it is, the volume changes (upper row of Figure 6). <b>Volume preserved</b> (green): every frame ' +
      'the same target goes through the volume-preserving correction of section 4 (closed form (6), iterated to ' +
      'a relative error of 1e-5) with the vertices on the floor held: the ball bulges sideways, as a soft ' +
      'incompressible ball would (lower row). The details (spikes) are kept by the multiresolution representation.',
    'The chart plots both volumes over time, divided by the reference volume.',
  ]);
  const text = await fetchSample('spiky-ball');
  if (stale()) return null;
  const mr = mrvol.openMesh(mrvol.readObj(text));
  const rest = mr.positions();
  let bottom = Infinity;
  for (let i = 1; i < rest.length; i += 3) bottom = Math.min(bottom, rest[i]);
  const R = -bottom; // from the centre down to the lowest point of the fine mesh
  const twins = twinEditors({ mrvol, mr, level: 0, scheme: 'loop', layout, floor: { y: 0, size: 2.6 * R } });
  const restCage = twins.kept.cagePositions();
  let lowest = Infinity;
  for (let i = 1; i < restCage.length; i += 3) lowest = Math.min(lowest, restCage[i]);
  twins.stage.frame([0, 1.5 * R, 0], 1.7 * R, [0, 0.2, 1]);

  const squashes = { '0.5': 0.5, '0.35': 0.35, '0.2': 0.2 };
  const squashSelect = control(layout.controls, 'max squash', select(Object.keys(squashes).map((k) => [k, `${Math.round(squashes[k] * 100)} % of the height`]), '0.35', 'ball-squash'));
  const g = 9.81, drop = 2.2 * R;
  const sim = { t: 0, h: drop, v: 0, k: 0 };
  function setStiffness() {
    const impact = Math.sqrt(2 * g * (drop - R));
    const x = squashes[squashSelect.value] * R; // deepest compression
    sim.k = impact * impact / (x * x); // (1/2) k x^2 = (1/2) v^2 per unit mass
  }
  function restart() {
    Object.assign(sim, { t: 0, h: drop, v: 0 });
    setStiffness();
  }
  restart();
  squashSelect.addEventListener('change', setStiffness);

  const target = new Float64Array(restCage.length);
  const held = new Uint8Array(twins.kept.cageSize);
  function advance(dt) {
    // Semi-implicit Euler in 1 ms sub-steps.
    for (let left = dt; left > 1e-9; left -= 0.001) {
      const step = Math.min(0.001, left);
      const contact = sim.h < R ? sim.k * (R - sim.h) : 0;
      sim.v += (contact - g) * step;
      sim.h += sim.v * step;
      sim.t += step;
    }
    const s = Math.min(1, sim.h / R); // vertical scale of the ball about its centre
    held.fill(0);
    for (let i = 0; i < restCage.length; i += 3) {
      target[i] = restCage[i];
      target[i + 2] = restCage[i + 2];
      target[i + 1] = sim.h + restCage[i + 1] * s;
      if (s < 1 && restCage[i + 1] <= lowest + 1e-9) held[i / 3] = 1; // on the floor: stays there
    }
    twins.drive(target, held);
    twins.chart.draw();
  }
  advance(0);
  return runDemo({
    layout, el, mr, twins: () => twins, advance, restart, dt: 1 / 60,
    actions: {
      /** Runs until the free ball has lost `fraction` of its volume (at most 600 steps; tests, screenshots). */
      /** Viewport x range of the floor's corners in each panel, and the panel's cell (tests: no floor reaches a panel edge). */
      floorScreen() {
        const half = 1.3 * R;
        return twins.stage.cells.map((cell, p) => {
          const xs = [[-half, -half], [-half, half], [half, -half], [half, half]].map(([x, z]) => twins.stage.screenOf([x, 0, z], p)[0]);
          const left = twins.stage.renderer.domElement.getBoundingClientRect().left;
          return { min: Math.min(...xs), max: Math.max(...xs), cellLeft: left + cell.x, cellRight: left + cell.x + cell.width };
        });
      },
      runUntilSquashed(fraction = 0.2, dt = 1 / 60) {
        for (let i = 0; i < 600 && twins.free.volume() > (1 - fraction) * twins.reference; i++) advance(dt);
        twins.stage.render();
      },
    },
    debug: () => ({ ...twins.debug(), t: sim.t, height: sim.h }),
  }).view;
}
