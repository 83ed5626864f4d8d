// Shared by the demos: two editing sessions (lib/three/session.mjs, as in the editor) on one mesh,
// one without and one with volume preservation, driven by the same cage targets; side-by-side
// drawing, volume chart and readouts.
import { EditingSession } from '../../lib/three/session.mjs';
import { Stage, THREE, surface, wire, Chart, readoutTable } from './stage.js';

/**
 * Two sessions on `mr` (the caller's; mrvol its API object) at `level`: panels 'volume free' and 'volume preserved',
 * their fine meshes and cages drawn, a chart of V / V_ref over time. drive(target, held) deforms both.
 */
export function twinEditors({ mrvol, mr, level = 0, scheme, layout, floorY = null, schemeOptions = {} }) {
  const options = { level, scheme, ...schemeOptions, tolerance: 1e-5 };
  const free = new EditingSession(mrvol, { ...options, preserve: false });
  const kept = new EditingSession(mrvol, { ...options, preserve: true });
  free.open(mr, { name: 'free' });
  kept.open(mr, { name: 'preserved' });
  const faces = free.model.faces;
  const cageVertices = free.cageVertices;
  const cageEdges = free.cageEdges();
  const stage = new Stage(layout.stage, ['volume free', 'volume preserved']);
  const parts = [free, kept].map((editor, p) => {
    const scene = stage.panels[p].scene;
    const mesh = surface(editor.positions(), faces, { color: p ? 0x9fc3a0 : 0xd9a08a });
    const cage = wire(editor.cagePositions(), cageEdges);
    scene.add(mesh, cage);
    if (floorY !== null) {
      const grid = new THREE.GridHelper(8, 16, 0x8c959f, 0xc9d1d9);
      grid.position.y = floorY;
      scene.add(grid);
    }
    return { editor, mesh, cage };
  });
  layout.bottom.hidden = false;
  const chart = new Chart(layout.bottom, { title: 'volume / reference volume over time' });
  chart.add('free', '#cf222e');
  chart.add('preserved', '#1a7f37');
  const set = readoutTable(layout.readouts, [
    ['reference volume', 'demo-reference'], ['free volume', 'demo-free'], ['preserved volume', 'demo-preserved'],
    ['preserved rel. error', 'demo-error'], ['free: min / max ratio', 'demo-free-range'], ['last step', 'demo-step'],
  ]);
  const reference = kept.referenceVolume();
  set('demo-reference', reference.toPrecision(8), reference);
  const stats = { steps: 0, maxError: 0, minRatio: 1, maxRatio: 1, lastReport: null, failures: 0 };

  kept.addEventListener('error', ({ detail }) => {
    stats.failures++;
    layout.status.textContent = `A step was refused: ${detail.error.message}`;
  });

  function drive(target, held) {
    free.setCage(target, new Uint8Array(free.cageSize));
    const report = kept.setCage(target, held);
    if (!report) return;
    stats.steps++;
    stats.lastReport = report;
    for (const part of parts) {
      part.mesh.update(part.editor.positions());
      part.cage.update(part.editor.cagePositions());
    }
    const vFree = free.volume(), vKept = kept.volume();
    const error = Math.abs(vKept - reference) / Math.abs(reference);
    stats.maxError = Math.max(stats.maxError, error);
    stats.minRatio = Math.min(stats.minRatio, vFree / reference);
    stats.maxRatio = Math.max(stats.maxRatio, vFree / reference);
    chart.push([vFree / reference, vKept / reference]);
    set('demo-free', `${vFree.toPrecision(8)} (${((vFree / reference - 1) * 100).toFixed(1)} %)`, vFree);
    set('demo-preserved', vKept.toPrecision(8), vKept);
    set('demo-error', error.toExponential(2), error);
    set('demo-free-range', `${stats.minRatio.toFixed(3)} / ${stats.maxRatio.toFixed(3)}`);
    set('demo-step', `${report.iterations} it, ${report.path}${report.converged ? '' : ' (not converged)'}`);
  }

  return {
    stage, chart, free, kept, reference, stats, drive, cageVertices,
    debug: () => ({
      steps: stats.steps, reference, free: free.volume(), preserved: kept.volume(), maxError: stats.maxError,
      minRatio: stats.minRatio, maxRatio: stats.maxRatio, failures: stats.failures, frames: stage.frames ?? 0,
      lastIterations: stats.lastReport?.iterations ?? null,
    }),
    dispose() {
      stage.dispose();
      free.dispose();
      kept.dispose();
    },
  };
}

/**
 * The clock of a demo: play / pause / restart buttons over the stage's animation loop, which calls
 * advance(dt), started at once; and the view the router mounts (dispose, actions pause and run,
 * debug). `twins()` gives the current twin editors (a demo may rebuild them).
 */
export function runDemo({ layout, el, mr, twins, advance, restart, dt, actions = {}, debug }) {
  const start = () => twins().stage.animate(advance);
  const stop = () => twins().stage.stop();
  const controls = playControls(layout, el, { start, stop, restart });
  start();
  return {
    start,
    controls,
    view: {
      dispose() {
        twins()?.dispose();
        mr.delete();
      },
      actions: {
        pause: stop,
        /** Advances the simulation by `count` steps of `step` seconds (tests). */
        run(count, step = dt) {
          for (let i = 0; i < count; i++) advance(step);
          twins().stage.render();
        },
        ...actions,
      },
      debug,
    },
  };
}

/** Play / pause / restart buttons over a stage loop. */
export function playControls(layout, el, { start, stop, restart }) {
  const row = el('div', { class: 'learn-row' });
  const toggle = el('button', { type: 'button', testid: 'demo-play', text: '❚❚ pause' });
  let playing = true;
  toggle.addEventListener('click', () => {
    playing = !playing;
    toggle.textContent = playing ? '❚❚ pause' : '▶ play';
    if (playing) start();
    else stop();
  });
  const again = el('button', { type: 'button', testid: 'demo-restart', text: '↺ restart' });
  again.addEventListener('click', restart);
  row.append(toggle, again);
  layout.controls.append(row);
  return { playing: () => playing };
}
