// The control panel (lil-gui). It edits a settings object and calls the app's actions; every
// control carries a data-testid so that tests drive the real UI.
import GUI from 'lil-gui';
import { FREE_SET_MODES, MAX_PARTS } from '../lib/three/session.mjs';

export { MAX_PARTS };
const SCHEMES = ['loop', 'butterfly', 'linear'];
// A quad model's one scheme (lib/three/session.mjs QUAD_SCHEME).
const QUAD_SCHEMES = ['catmull-clark'];
// The session's free-set modes (lib/three/session.mjs) under their names in the panel.
const FREE_SET_NAMES = { 'minus-held': 'cage minus held', all: 'all cage', painted: 'painted region', parts: 'parts' };
const FREE_SETS = Object.fromEntries(FREE_SET_MODES.map((mode) => [FREE_SET_NAMES[mode], mode]));
/** Pointer tools: drag handles, paint the free set, assign handles to parts. */
export const GRADIENTS = { 'cage polynomial': 'polynomial', 'volume tensor θ (the paper\'s)': 'tensor' };
export const TOOLS = { 'drag handles': 'drag', 'paint free set': 'paint', 'assign to part': 'assign' };
const TOLERANCES = { '1e-4': 1e-4, '1e-5': 1e-5, '1e-6': 1e-6, '1e-7': 1e-7, '1e-8': 1e-8 };

// The tooltip of every control, by its data-testid: what it does, in plain words.
const TITLES = {
  'model-select': 'Open one of the sample models',
  'open-button': 'Open a mesh file from this computer: OBJ, STL, PLY, OFF, glTF or GLB (or drop one on the page)',
  export: 'Download the edited fine mesh as an OBJ file (an OBJ file keeps its own texture coordinates, normals and groups)',
  'export-glb': 'Download the edited fine mesh as a GLB (binary glTF) file (a glTF or GLB file opened as it came keeps its materials and attributes; a remeshed one is written plain; quads are written as triangles: export OBJ keeps them)',
  'export-cage': 'Download the cage (the coarse mesh you drag) at level e as an OBJ file',
  reset: 'Forget the edits and settings of this model and open it as it was',
  glossary: 'What the words in this panel mean',
  scheme: 'The wavelet scheme that splits the mesh into a coarse cage plus details (Loop, modified Butterfly, linear)',
  level: 'Level e of the cage you drag: 0 is the coarsest; higher levels give more, finer handles',
  preserve: 'Keep the enclosed volume constant while dragging (the other handles move a little to make up for it)',
  'free-set': 'Which handles may move to keep the volume: all but the dragged ones, all of them, a painted region, or parts that each keep their own volume',
  tool: 'What a press on a handle does: drag it, paint it into the free set, or assign it to a part',
  'part-number': 'The part that "assign to part" puts handles into',
  'clear-painted': 'Empty the painted region',
  'clear-parts': 'Remove every handle from every part',
  tolerance: 'How close the volume must come to the reference volume (relative error) in each step',
  'set-reference': 'Make the current volume the volume to keep from now on (undoable)',
  'theta-recompute': 'Forget the stored volume tensor θ of this level and compute it again',
  gradient: 'How each drag step gets the volume gradient: the cage polynomial (built from the mesh in a moment, small) or the paper\'s volume tensor θ (computed in the background, can be large; the same steps)',
  undo: 'Undo the last edit, level or scheme change, reference change or preservation toggle (Ctrl+Z)',
  redo: 'Redo what was undone (Ctrl+Shift+Z or Ctrl+Y)',
  'show-mesh': 'Show the fine (full-resolution) mesh',
  'show-cage': 'Show the cage: the level-e mesh whose vertices are the handles',
  flat: 'Flat shading (each triangle one shade) or smooth shading',
  'show-approx': 'Show the shape rebuilt from levels 0..l only (no finer details), semi-transparent',
  'approx-level': 'Level l of that approximation',
  'show-details': 'Show the detail vectors: from the level-l approximation to the fine vertices',
  frame: 'Point the camera at the whole model again (F)',
  screenshot: 'Download the view as a PNG image',
  'share-link': 'A link that opens this sample with its edits and settings (copied to the clipboard)',
  'save-project': 'Download a project file (JSON): the model, its edits and the settings, to open again later',
  'open-project': 'Open a project file (.json) saved here, or an OBJ file',
  'keys-help': 'The keyboard and pointer controls (?)',
  'cache-refresh': 'List the volume tensors stored in this browser again',
  'cache-clear': 'Delete every volume tensor stored in this browser',
};

function tag(controller, id) {
  const element = controller.$input ?? controller.$select ?? controller.$button;
  if (element) element.dataset.testid = id;
  controller.domElement.dataset.testid = `${id}-row`;
  // a name of its own for assistive technology (the row's label can be scrolled out of view)
  if (element && controller._name) element.setAttribute('aria-label', controller._name);
  const title = TITLES[id];
  if (title) {
    controller.domElement.title = title;
    if (element) element.title = title;
  }
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
 *            setReference(), exportObj(), exportGlb(), exportCage(), reset(), recomputeTheta(), refreshCache(), clearCache() }
 */
export function createPanel({ settings, samples, actions, learnViews = [] }) {
  const gui = new GUI({ title: 'mrvol', container: document.getElementById('panel-host') });
  gui.domElement.dataset.testid = 'panel';

  const model = gui.addFolder('Model');
  const modelChoice = tag(model.add(settings, 'model', samples).name('sample').onChange((name) => actions.openSample(name)), 'model-select');
  tag(model.add({ open: () => actions.openFile() }, 'open').name('open mesh file… (Ctrl+O)'), 'open-button');
  tag(model.add({ exportObj: () => actions.exportObj() }, 'exportObj').name('export OBJ'), 'export');
  tag(model.add({ exportGlb: () => actions.exportGlb() }, 'exportGlb').name('export GLB'), 'export-glb');
  tag(model.add({ exportCage: () => actions.exportCage() }, 'exportCage').name('export cage OBJ'), 'export-cage');
  tag(model.add({ reset: () => actions.reset() }, 'reset').name('reset (forget edits)'), 'reset');
  tag(model.add({ glossary: () => actions.showGlossary() }, 'glossary').name('glossary: what the words mean'), 'glossary');

  const recentFolder = model.addFolder('recent models');
  recentFolder.close();
  recentFolder.$title.dataset.testid = 'recent-folder';
  const recentList = document.createElement('div');
  recentList.className = 'recent-list';
  recentList.dataset.testid = 'recent-list';
  recentFolder.$children.appendChild(recentList);

  const edit = gui.addFolder('Editing');
  const scheme = tag(edit.add(settings, 'scheme', SCHEMES).onChange(() => actions.changeScheme()), 'scheme');
  const level = tag(edit.add(settings, 'level', [0]).name('cage level e').onChange(() => actions.changeLevel()), 'level');
  const preserve = tag(edit.add(settings, 'preserve').name('preserve volume').onChange(() => actions.changePreserve()), 'preserve');
  const freeSet = tag(edit.add(settings, 'freeSet', FREE_SETS).name('free set (what moves)').onChange(() => actions.changeFreeSet()), 'free-set');
  let freeSetModes = FREE_SET_MODES;
  const tool = tag(edit.add(settings, 'tool', TOOLS).name('pointer').onChange(() => actions.changeTool()), 'tool');
  const part = tag(edit.add(settings, 'part', 1, MAX_PARTS, 1).name('part to assign'), 'part-number');
  const clearPainted = tag(edit.add({ clear: () => actions.clearPainted() }, 'clear').name('clear painted region'), 'clear-painted');
  const clearParts = tag(edit.add({ clear: () => actions.clearParts() }, 'clear').name('clear parts'), 'clear-parts');
  tag(edit.add(settings, 'tolerance', TOLERANCES).onChange(() => actions.changeTolerance()), 'tolerance');
  tag(edit.add({ setReference: () => actions.setReference() }, 'setReference').name('reference = current volume'), 'set-reference');
  tag(edit.add(settings, 'gradient', GRADIENTS).name('gradient from').onChange(() => actions.changeGradient()), 'gradient');
  tag(edit.add({ recompute: () => actions.recomputeTheta() }, 'recompute').name('compute θ again'), 'theta-recompute');
  tag(edit.add({ undo: () => actions.undo() }, 'undo').name('undo (Ctrl+Z)'), 'undo');
  tag(edit.add({ redo: () => actions.redo() }, 'redo').name('redo (Ctrl+Shift+Z)'), 'redo');

  const view = gui.addFolder('View');
  tag(view.add(settings, 'showMesh').name('fine mesh').onChange(() => actions.changeView()), 'show-mesh');
  tag(view.add(settings, 'showCage').name('cage').onChange(() => actions.changeView()), 'show-cage');
  tag(view.add(settings, 'flat').name('flat shading').onChange(() => actions.changeView()), 'flat');
  tag(view.add(settings, 'showApprox').name('level-l approximation').onChange(() => actions.changeLayers()), 'show-approx');
  const approxLevel = tag(view.add(settings, 'approxLevel', 0, 1, 1).name('approximation level l').onChange(() => actions.changeLayers()), 'approx-level');
  tag(view.add(settings, 'showDetails').name('detail vectors').onChange(() => actions.changeLayers()), 'show-details');

  const tools = gui.addFolder('Tools');
  tag(tools.add({ frame: () => actions.frame() }, 'frame').name('frame the model (F)'), 'frame');
  tag(tools.add({ screenshot: () => actions.screenshot() }, 'screenshot').name('screenshot (PNG)'), 'screenshot');
  tag(tools.add({ share: () => actions.shareLink() }, 'share').name('share link'), 'share-link');
  tag(tools.add({ save: () => actions.saveProject() }, 'save').name('save project file (Ctrl+S)'), 'save-project');
  tag(tools.add({ open: () => actions.openFile() }, 'open').name('open project or OBJ…'), 'open-project');
  tag(tools.add({ keys: () => actions.showKeyboardHelp() }, 'keys').name('keyboard help (?)'), 'keys-help');

  const learn = gui.addFolder('Learn: the paper\'s figures');
  learn.close();
  const links = document.createElement('nav');
  links.className = 'learn-links';
  links.setAttribute('aria-label', 'Teaching views');
  for (const view of learnViews) {
    const a = document.createElement('a');
    a.href = `#${view.route}`;
    a.textContent = view.title;
    a.title = `The teaching view "${view.title}" (#${view.route}), computed from the model on screen`;
    a.dataset.testid = `learn-link-${view.route.replace('/', '-')}`;
    links.append(a);
  }
  learn.$children.appendChild(links);

  const cache = gui.addFolder('θ cache (IndexedDB)');
  cache.close();
  cache.$title.dataset.testid = 'cache-folder';
  const list = document.createElement('div');
  list.className = 'cache-list';
  list.dataset.testid = 'cache-list';
  cache.$children.appendChild(list);
  tag(cache.add({ refresh: () => actions.refreshCache() }, 'refresh').name('refresh list'), 'cache-refresh');
  tag(cache.add({ clear: () => actions.clearCache() }, 'clear').name('clear cache'), 'cache-clear');

  for (const folder of [gui, ...gui.foldersRecursive()]) folder.$title.title = `Show or hide "${folder._title}"`;

  return {
    gui,
    /** The levels this model offers: lowest..n (lowest: 1 for a quad mesh on a cube's base). */
    setLevels(n, lowest = 0) {
      level.options(Array.from({ length: n + 1 - lowest }, (_, i) => lowest + i));
      tag(level, 'level');
      level.updateDisplay();
      approxLevel.max(Math.max(n, 1));
      approxLevel.updateDisplay();
    },
    /** The schemes the model takes: Catmull-Clark for a quad model, else Loop, Butterfly, linear. */
    setQuad(quad) {
      scheme.options(quad ? QUAD_SCHEMES : SCHEMES);
      tag(scheme, 'scheme');
      scheme.updateDisplay();
    },
    /** The free-set modes the editor takes (the session's freeSetModes), and the pointer tools that go with them. */
    setFreeSets(modes) {
      if (modes.length === freeSetModes.length && modes.every((m, i) => m === freeSetModes[i])) return;
      freeSetModes = modes;
      freeSet.options(Object.fromEntries(modes.map((mode) => [FREE_SET_NAMES[mode], mode])));
      tag(freeSet, 'free-set');
      const needs = { paint: 'painted', assign: 'parts' };
      tool.options(Object.fromEntries(Object.entries(TOOLS).filter(([, t]) => !needs[t] || modes.includes(needs[t]))));
      tag(tool, 'tool');
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
    /** The recent models' sessions: [{ id, name, kind, saved, current }], a button each. */
    showRecent(entries) {
      recentList.replaceChildren(...entries.map(({ id, name, kind, saved, copy, current }) => {
        const button = document.createElement('button');
        button.type = 'button';
        button.dataset.testid = 'recent-item';
        button.dataset.id = id;
        button.textContent = `${name}${kind === 'file' ? ' (file)' : ''}${copy ? ` (${copy})` : ''}${current ? ' ·' : ''}`;
        button.title = `Reopen ${name} with its edits (last saved ${new Date(saved).toLocaleString()})`;
        button.addEventListener('click', () => actions.openRecent(id));
        return button;
      }));
      if (entries.length === 0) recentList.textContent = 'none yet';
    },
    preserveController: preserve,
  };
}
