// Shared by the demos: two editing sessions (lib/three/session.mjs, as in the editor) on one mesh,
// one without and one with volume preservation, driven by the same cage targets; side-by-side
// drawing, volume chart and readouts.
import { EditingSession } from '../../lib/three/session.mjs';
import { Stage, THREE, surface, wire, Chart, readoutTable } from './stage.js';

/**
 * Two sessions on `mr` (the caller's; mrvol its API object) at `level`: panels 'volume free' and 'volume preserved',
 * their fine meshes and cages drawn, a chart of V / V₀ over time (V₀ the reference volume). drive(target, held) deforms both.
 */
export const FREE_COLOR = 0xe5765a, KEPT_COLOR = 0x4fae68; // the chart's red and green, lighter for shading

export function twinEditors({ mrvol, mr, level = 0, scheme, layout, floor = null, ghostOther = false, dragCharts = false, schemeOptions = {} }) {
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
    const mesh = surface(editor.positions(), faces, { color: p ? KEPT_COLOR : FREE_COLOR });
    const cage = wire(editor.cagePositions(), cageEdges);
    scene.add(mesh, cage);
    if (floor) {
      // A square floor under the model only (a grid to the panel's edges would meet its twin's in a V).
      const plate = new THREE.Mesh(new THREE.PlaneGeometry(floor.size, floor.size), new THREE.MeshStandardMaterial({ color: 0xdfe3e8, roughness: 1, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2 }));
      plate.rotation.x = -Math.PI / 2;
      const grid = new THREE.GridHelper(floor.size, 8, 0xa5adb6, 0xc4cad1);
      plate.position.y = grid.position.y = floor.y;
      scene.add(plate, grid);
    }
    return { editor, mesh, cage };
  });
  // Each panel also shows the other's surface, faint: where they differ is what the correction did.
  const ghosts = ghostOther ? parts.map((part, p) => {
    const ghost = surface(parts[1 - p].editor.positions(), faces, { color: p ? FREE_COLOR : KEPT_COLOR, opacity: 0.28 });
    ghost.renderOrder = 1;
    stage.panels[p].scene.add(ghost);
    return ghost;
  }) : [];
  const labels = () => {
    const ratio = (v) => `${(100 * v / reference).toFixed(1)} %`;
    stage.panels[0].tag.textContent = `volume free: ${ratio(free.volume())}`;
    stage.panels[1].tag.textContent = `volume preserved: ${ratio(kept.volume())}`;
    stage.panels[0].tag.style.color = '#cf222e';
    stage.panels[1].tag.style.color = '#1a7f37';
  };
  layout.bottom.hidden = false;
  const chartRow = document.createElement('div');
  chartRow.className = 'learn-charts';
  layout.bottom.append(chartRow);
  const chart = new Chart(chartRow, { title: dragCharts ? 'V / V₀ over time' : 'volume / reference volume over time' });
  chart.add('free', '#cf222e');
  chart.add('preserved', '#1a7f37');
  const set = readoutTable(layout.readouts, [
    ['reference volume', 'demo-reference'], ['free volume', 'demo-free'], ['preserved volume', 'demo-preserved'],
    ['preserved rel. error', 'demo-error'], ['free: min / max ratio', 'demo-free-range'], ['last step', 'demo-step'],
    ['multiplier λ', 'demo-lambda'],
  ]);
  const reference = kept.referenceVolume();
  labels();
  // During a drag: the correction's multiplier and the volumes, from the drag's start.
  let lambdaChart = null, dragVolumeChart = null;
  if (dragCharts) {
    lambdaChart = new Chart(chartRow, { title: 'drag: multiplier λ', height: 150, maxPoints: 300, testid: 'drag-lambda-chart', grow: true, empty: 'drag a control vertex: λ is plotted here' });
    lambdaChart.add('λ', '#8250df');
    dragVolumeChart = new Chart(chartRow, { title: 'drag: V / V₀', height: 150, maxPoints: 300, testid: 'drag-volume-chart', grow: true, empty: 'and both volumes here' });
    dragVolumeChart.add('free', '#cf222e');
    dragVolumeChart.add('preserved', '#1a7f37');
    requestAnimationFrame(() => { lambdaChart.draw(); dragVolumeChart.draw(); }); // once laid out
  }
  const hierarchyIndex = new Map(Array.from(mr.hierarchyOrder(), (v, h) => [v, h]));
  let lastTarget = kept.cagePositions(), lastHeld = new Uint8Array(kept.cageSize);
  set('demo-reference', reference.toPrecision(8), reference);
  const stats = { steps: 0, maxError: 0, minRatio: 1, maxRatio: 1, lastReport: null, failures: 0, lambda: 0, dragSamples: 0 };

  kept.addEventListener('error', ({ detail }) => {
    stats.failures++;
    layout.status.textContent = `A step was refused: ${detail.error.message}`;
  });

  /**
   * The correction's multiplier: the preserved cage minus the target on the free vertices, as a
   * multiple λ of the volume gradient there (least squares; formula (6) moves along the gradient).
   */
  function multiplier(target, held) {
    const gradient = kept.editor.gradient('matrix-free'); // hierarchy order
    const cage = kept.cagePositions();
    let dg = 0, gg = 0;
    kept.cageVertices.forEach((v, c) => {
      if (held[c]) return;
      const h = hierarchyIndex.get(v);
      for (let k = 0; k < 3; k++) {
        dg += (cage[3 * c + k] - target[3 * c + k]) * gradient[3 * h + k];
        gg += gradient[3 * h + k] ** 2;
      }
    });
    return gg > 0 ? dg / gg : 0;
  }

  function drive(target, held, { dragging = false } = {}) {
    lastTarget = Float64Array.from(target);
    lastHeld = Uint8Array.from(held);
    free.setCage(target, new Uint8Array(free.cageSize));
    const report = kept.setCage(target, held);
    if (!report) return;
    const lambda = multiplier(target, held);
    stats.lambda = lambda;
    set('demo-lambda', lambda.toExponential(3), lambda);
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
    if (dragging && lambdaChart) {
      lambdaChart.push([lambda]);
      dragVolumeChart.push([vFree / reference, vKept / reference]);
      lambdaChart.draw();
      dragVolumeChart.draw();
      stats.dragSamples++;
    }
    // (The animation draws the time chart each frame; a drag of a paused demo does here.)
    if (dragging) chart.draw();
    labels();
    for (const [p, ghost] of ghosts.entries()) ghost.update(parts[1 - p].editor.positions());
    set('demo-free', `${vFree.toPrecision(8)} (${((vFree / reference - 1) * 100).toFixed(1)} %)`, vFree);
    set('demo-preserved', vKept.toPrecision(8), vKept);
    set('demo-error', error.toExponential(2), error);
    set('demo-free-range', `${stats.minRatio.toFixed(3)} / ${stats.maxRatio.toFixed(3)}`);
    set('demo-step', `${report.iterations} it, ${report.path}${report.converged ? '' : ' (not converged)'}`);
  }

  /** A restart: the charts, the extremes and the error over the run forgotten. */
  function resetHistory() {
    for (const c of [chart, lambdaChart, dragVolumeChart]) c?.clear();
    Object.assign(stats, { maxError: 0, minRatio: 1, maxRatio: 1, dragSamples: 0 });
    for (const c of [chart, lambdaChart, dragVolumeChart]) c?.draw();
  }

  /** A new drag: its charts start empty. */
  function startDragCharts() {
    for (const c of [lambdaChart, dragVolumeChart]) if (c) for (const series of c.series) series.values.length = 0;
    stats.dragSamples = 0;
  }

  return {
    stage, chart, free, kept, reference, stats, drive, cageVertices, parts, startDragCharts, resetHistory,
    lastTarget: () => lastTarget, lastHeld: () => lastHeld,
    debug: () => ({
      steps: stats.steps, reference, free: free.volume(), preserved: kept.volume(), maxError: stats.maxError,
      minRatio: stats.minRatio, maxRatio: stats.maxRatio, failures: stats.failures, frames: stage.frames ?? 0,
      lastIterations: stats.lastReport?.iterations ?? null, lambda: stats.lambda, dragSamples: stats.dragSamples,
      labels: stage.panels.map((p) => p.tag.textContent), ghosts: ghosts.length,
      ticks: chart.ticks ?? [], lambdaTicks: lambdaChart?.ticks ?? [], chartPoints: chart.series[0].values.length,
      chartLast: chart.series.map((x) => x.values.at(-1) ?? null), camera: stage.camera.position.toArray(),
      lambdas: lambdaChart?.series[0].values.slice() ?? [], dragVolumes: dragVolumeChart?.series.map((x) => x.values.slice()) ?? [],
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
  // The start again, whether playing or paused: the model, the charts and readouts, the view.
  const restartAll = () => {
    restart();
    twins().resetHistory();
    advance(0);
    twins().stage.resetView();
    twins().stage.requestRender();
  };
  const controls = playControls(layout, el, { start, stop, restart: restartAll });
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
  return {
    playing: () => playing,
    pause() {
      if (!playing) return;
      playing = false;
      toggle.textContent = '▶ play';
      stop();
    },
  };
}

/**
 * Dragging a cage vertex with the pointer, in either panel: the nearest handle within 16 px of
 * the press; it moves in the plane facing the camera, held, the others stay at the last target
 * (the preserved side corrects them). onStart() runs when a drag begins (a demo pauses). Returns
 * { dragging(), dispose() }.
 */
export function cageDragging(twins, { onStart = () => {} } = {}) {
  const { stage } = twins;
  const canvas = stage.renderer.domElement;
  let drag = null;
  const point = new THREE.Vector3();
  function down(e) {
    const at = stage.panelAt(e.clientX, e.clientY);
    if (!at) return;
    const cage = twins.parts[at.index].editor.cagePositions();
    let best = null;
    for (let c = 0; c < cage.length / 3; c++) {
      const [x, y] = stage.screenOf([cage[3 * c], cage[3 * c + 1], cage[3 * c + 2]], at.index);
      const d = Math.hypot(x - e.clientX, y - e.clientY);
      if (d < 16 && (!best || d < best.d)) best = { c, d };
    }
    if (!best) return;
    onStart();
    stage.controls.enabled = false;
    canvas.setPointerCapture?.(e.pointerId);
    const base = Float64Array.from(twins.lastTarget());
    const depth = point.fromArray(base, 3 * best.c).project(stage.camera).z;
    drag = { vertex: best.c, panel: at.index, base, depth };
    twins.startDragCharts();
    e.preventDefault();
    e.stopImmediatePropagation();
  }
  function move(e) {
    if (!drag) return;
    const c = stage.cells[drag.panel];
    const rect = canvas.getBoundingClientRect();
    const ndcX = (e.clientX - rect.left - c.x) / c.width * 2 - 1, ndcY = 1 - (e.clientY - rect.top - c.y) / c.height * 2;
    point.set(ndcX, ndcY, drag.depth).unproject(stage.camera);
    const target = Float64Array.from(drag.base);
    point.toArray(target, 3 * drag.vertex);
    const held = new Uint8Array(twins.kept.cageSize);
    held[drag.vertex] = 1;
    twins.drive(target, held, { dragging: true });
    stage.requestRender();
  }
  function up() {
    if (!drag) return;
    drag = null;
    stage.controls.enabled = true;
  }
  canvas.addEventListener('pointerdown', down, { capture: true }); // before OrbitControls: a press on a handle does not orbit
  canvas.addEventListener('pointermove', move);
  canvas.addEventListener('pointerup', up);
  canvas.addEventListener('pointercancel', up);
  return {
    dragging: () => drag !== null,
    dispose() {
      canvas.removeEventListener('pointerdown', down, { capture: true });
      canvas.removeEventListener('pointermove', move);
      canvas.removeEventListener('pointerup', up);
      canvas.removeEventListener('pointercancel', up);
    },
  };
}
