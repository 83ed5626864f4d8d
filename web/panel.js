// The control panel (lil-gui). It edits a settings object and calls the app's actions; every
// control carries a data-testid so that tests drive the real UI.
import GUI from 'lil-gui';
import { FREE_SET_MODES, MAX_PARTS } from '../lib/three/session.mjs';

export { MAX_PARTS };
const SCHEMES = ['loop', 'butterfly', 'linear'];
// The session's free-set modes (lib/three/session.mjs) under their names in the panel.
const FREE_SET_NAMES = { 'minus-held': 'cage minus held', all: 'all cage', painted: 'painted region', parts: 'parts' };
const FREE_SETS = Object.fromEntries(FREE_SET_MODES.map((mode) => [FREE_SET_NAMES[mode], mode]));
/** Pointer tools: drag handles, paint the free set, assign handles to parts. */
export const TOOLS = { 'drag handles': 'drag', 'paint free set': 'paint', 'assign to part': 'assign' };
const TOLERANCES = { '1e-4': 1e-4, '1e-5': 1e-5, '1e-6': 1e-6, '1e-7': 1e-7, '1e-8': 1e-8 };

function tag(controller, id) {
  const element = controller.$input ?? controller.$select ?? controller.$button;
  if (element) element.dataset.testid = id;
  controller.domElement.dataset.testid = `${id}-row`;
  return controller;
}

function formatBytes(n) {
  if (n >= 1 << 20) return `${(n / (1 << 20)).toFixed(1)} MB`;
  if (n >= 1 << 10) return `${(n / (1 << 10)).toFixed(0)} kB`;
  return `${n} B`;
}

/**
 * settings: { model, scheme, level, preserve, freeSet, tolerance, flat, showMesh, showCage, tool, part,
 *             showApprox, approxLevel, showDetails }
 * actions: { openSample(name), openFile(), changeScheme(), changeLevel(), changePreserve(),
 *            changeFreeSet(), changeTool(), clearPainted(), clearParts(), changeView(), changeLayers(),
 *            setReference(), exportObj(), exportCage(), reset(), recomputeTheta(), refreshCache(), clearCache() }
 */
export function createPanel({ settings, samples, actions }) {
  const gui = new GUI({ title: 'mrvol' });
  gui.domElement.dataset.testid = 'panel';

  const model = gui.addFolder('Model');
  const modelChoice = tag(model.add(settings, 'model', samples).name('sample').onChange((name) => actions.openSample(name)), 'model-select');
  tag(model.add({ open: () => actions.openFile() }, 'open').name('open OBJ file…'), 'open-button');
  tag(model.add({ exportObj: () => actions.exportObj() }, 'exportObj').name('export OBJ'), 'export');
  tag(model.add({ exportCage: () => actions.exportCage() }, 'exportCage').name('export cage OBJ'), 'export-cage');
  tag(model.add({ reset: () => actions.reset() }, 'reset').name('reset (forget edits)'), 'reset');

  const edit = gui.addFolder('Editing');
  tag(edit.add(settings, 'scheme', SCHEMES).onChange(() => actions.changeScheme()), 'scheme');
  const level = tag(edit.add(settings, 'level', [0]).name('level e').onChange(() => actions.changeLevel()), 'level');
  const preserve = tag(edit.add(settings, 'preserve').name('preserve volume').onChange(() => actions.changePreserve()), 'preserve');
  tag(edit.add(settings, 'freeSet', FREE_SETS).name('free set').onChange(() => actions.changeFreeSet()), 'free-set');
  tag(edit.add(settings, 'tool', TOOLS).name('pointer').onChange(() => actions.changeTool()), 'tool');
  const part = tag(edit.add(settings, 'part', 1, MAX_PARTS, 1).name('part to assign'), 'part-number');
  const clearPainted = tag(edit.add({ clear: () => actions.clearPainted() }, 'clear').name('clear painted region'), 'clear-painted');
  const clearParts = tag(edit.add({ clear: () => actions.clearParts() }, 'clear').name('clear parts'), 'clear-parts');
  tag(edit.add(settings, 'tolerance', TOLERANCES).onChange(() => actions.changeTolerance()), 'tolerance');
  tag(edit.add({ setReference: () => actions.setReference() }, 'setReference').name('reference = current volume'), 'set-reference');
  tag(edit.add({ recompute: () => actions.recomputeTheta() }, 'recompute').name('compute θ again'), 'theta-recompute');
  tag(edit.add({ undo: () => actions.undo() }, 'undo').name('undo (Ctrl+Z)'), 'undo');
  tag(edit.add({ redo: () => actions.redo() }, 'redo').name('redo (Ctrl+Shift+Z)'), 'redo');

  const view = gui.addFolder('View');
  tag(view.add(settings, 'showMesh').name('fine mesh').onChange(() => actions.changeView()), 'show-mesh');
  tag(view.add(settings, 'showCage').name('cage').onChange(() => actions.changeView()), 'show-cage');
  tag(view.add(settings, 'flat').name('flat shading').onChange(() => actions.changeView()), 'flat');
  tag(view.add(settings, 'showApprox').name('level-l approximation').onChange(() => actions.changeLayers()), 'show-approx');
  const approxLevel = tag(view.add(settings, 'approxLevel', 0, 1, 1).name('l').onChange(() => actions.changeLayers()), 'approx-level');
  tag(view.add(settings, 'showDetails').name('detail vectors').onChange(() => actions.changeLayers()), 'show-details');

  const cache = gui.addFolder('θ cache (IndexedDB)');
  cache.close();
  cache.$title.dataset.testid = 'cache-folder';
  const list = document.createElement('div');
  list.className = 'cache-list';
  list.dataset.testid = 'cache-list';
  cache.$children.appendChild(list);
  tag(cache.add({ refresh: () => actions.refreshCache() }, 'refresh').name('refresh list'), 'cache-refresh');
  tag(cache.add({ clear: () => actions.clearCache() }, 'clear').name('clear cache'), 'cache-clear');

  return {
    gui,
    /** The levels this model offers: 0..n. */
    setLevels(n) {
      level.options(Array.from({ length: n + 1 }, (_, i) => i));
      tag(level, 'level');
      level.updateDisplay();
      approxLevel.max(Math.max(n, 1));
      approxLevel.updateDisplay();
    },
    /** Shows the controls of the painted region and of the parts when they apply. */
    showModeControls() {
      const painting = settings.freeSet === 'painted' || settings.tool === 'paint';
      const parts = settings.freeSet === 'parts' || settings.tool === 'assign';
      clearPainted.show(painting);
      part.show(parts);
      clearParts.show(parts);
    },
    update() {
      for (const c of gui.controllersRecursive()) c.updateDisplay();
    },
    /** Shows the model's name even when it is not a sample. */
    setModelLabel() {
      modelChoice.updateDisplay();
    },
    showCache(entries, status) {
      if (status) {
        list.textContent = status;
        return;
      }
      if (entries.length === 0) {
        list.textContent = 'empty';
        return;
      }
      const total = entries.reduce((s, e) => s + e.bytes, 0);
      list.textContent = entries.map((e) => {
        const [fingerprint, scheme, , , level] = e.key.split(':');
        return `${e.model ?? fingerprint.slice(0, 8)} ${scheme} e=${level}  ${formatBytes(e.bytes)}`;
      }).join('\n') + `\ntotal ${formatBytes(total)}`;
    },
    preserveController: preserve,
  };
}
