// window.mrvolDebug: a read-only hook for the browser tests and the web benchmark. Every function
// reads the app's state (the editing session, the view, the settings); none changes it.

import { openStages } from './open-stages.js';
import { sessionId } from './session-store.js';

/** Installs window.mrvolDebug over the app object of web/main.js. */
export function installDebugHook(app) {
  const editor = () => app.session?.editor ?? null;
  const hook = {
    /** Handle (cage) index -> [x, y] in CSS pixels of the page's viewport (what page.mouse uses). */
    cageScreenPositions() {
      if (!editor()) return [];
      const rect = app.viewer.canvas.getBoundingClientRect();
      const screen = app.viewer.projectHandles();
      const out = [];
      for (let i = 0; i < app.session.cageSize; i++) out.push([rect.left + screen[2 * i], rect.top + screen[2 * i + 1]]);
      return out;
    },
    /**
     * Handle dots: the setting ('auto' or CSS px), the size for the view now and the size last
     * drawn (CSS px), and each handle's alpha through the surface (faint, or 1: selected, hovered).
     */
    handleDots: () => {
      const cage = app.viewer.cage;
      if (!cage?.handles) return null;
      const behind = cage.hiddenHandles.geometry.getAttribute('color');
      return { setting: cage.handleSize, size: app.viewer.handlePixelSize, drawn: cage.materials.handles.size,
        alphaBehind: Array.from({ length: cage.count }, (_, i) => behind.getW(i)) };
    },
    volume: () => editor()?.volume() ?? null,
    referenceVolume: () => editor()?.referenceVolume() ?? null,
    thetaSource: () => app.theta?.source ?? null,
    thetaKey: () => app.theta?.key ?? null,
    modelName: () => app.model?.name ?? null,
    cageSize: () => app.session?.cageSize ?? 0,
    gradientPath: () => editor()?.path() ?? null,
    /** The editor in use: whose volume it keeps, whether it keeps the centre of mass, its path, whether a worker made it. */
    editorSettings: () => (editor() ? { surface: editor().surface?.() ?? 'mesh', keepsCentroid: editor().keepsCentroid?.() ?? false,
      path: editor().path(), madeElsewhere: editor().madeElsewhere === true, level: editor().level } : null),
    /** Threads of the page's core instance (1: the single-thread module; more where the page is cross-origin isolated). */
    coreThreads: () => app.mrvol?.threads ?? null,
    historySize: () => app.session?.history.size ?? { undo: 0, redo: 0 },
    /** The stored session's record id of the current model (a copy's has its own). */
    storedSessionId: () => (app.model ? sessionId(app.model) : null),
    /** The stored record of an id (its settings and undo history; not its arrays), or null. */
    storedSession: async (id) => (await app.store?.recent())?.find((r) => r.id === id) ?? null,
    /** The core's report of the last drag step (volumes, iterations, path), or null. */
    lastReport: () => {
      const report = app.session?.lastReport;
      return report ? { ...report, partVolumes: undefined, partReferences: undefined } : null;
    },
    /** The cage's edges as the view draws them: pairs of handle (cage) indices, flat. */
    cageEdges: () => Array.from(app.viewer.cage?.lines.geometry.index.array ?? []),
    /** The model's vertex of each handle (cage order). */
    cageVertices: () => Array.from(app.session?.cageVertices ?? []),
    /** Cage positions (world), 3 per handle, cage order. */
    cagePositions: () => (editor() ? Array.from(editor().cagePositions()) : []),
    selection: () => [...app.selection],
    settings: () => ({ ...app.settings }),
    /**
     * The floor shadow (web/floor-shadow.js): { visible, updates, darkened } where darkened is the
     * share of the view's pixels the shadow darkens (two frames drawn now, with and without the floor;
     * the view is left as it was).
     */
    floorShadow() {
      const viewer = app.viewer;
      if (!viewer?.mesh) return null;
      const { floor } = viewer.shadow;
      const shown = floor.visible;
      const withFloor = viewPixels(viewer);
      floor.visible = false;
      const without = viewPixels(viewer);
      floor.visible = shown;
      viewer.renderer.render(viewer.scene, viewer.camera);
      let darkened = 0;
      for (let i = 0; i < without.length; i += 4) if (without[i] + without[i + 1] + without[i + 2] - withFloor[i] - withFloor[i + 1] - withFloor[i + 2] > 15) darkened++;
      return { visible: shown, updates: viewer.shadow.updates, darkened: darkened / (without.length / 4) };
    },
    ready: () => app.ready,
    /**
     * The room light (web/room-light.js): { intensity, brightened } where brightened is the share
     * of the view's pixels it makes brighter (two frames drawn now, with and without it; the view
     * is left as it was).
     */
    roomLight() {
      const viewer = app.viewer;
      if (!viewer?.mesh) return null;
      const light = viewer.roomLight, intensity = light.intensity;
      const lit = viewPixels(viewer);
      light.intensity = 0;
      const unlit = viewPixels(viewer);
      light.intensity = intensity;
      viewer.renderer.render(viewer.scene, viewer.camera);
      let brightened = 0;
      for (let i = 0; i < lit.length; i += 4) if (lit[i] + lit[i + 1] + lit[i + 2] - unlit[i] - unlit[i + 1] - unlit[i + 2] > 15) brightened++;
      return { intensity, brightened: brightened / (lit.length / 4) };
    },
    thetaReady: () => app.ready && app.theta?.source != null && editor()?.path() === 'tensor',
    /** Drag steps on their fast path: the cage polynomial, or theta^e in use. */
    gradientReady: () => app.ready && (editor()?.path() === 'polynomial' || (app.theta?.source != null && editor()?.path() === 'tensor')),
    /** The live chart: volume points, multipliers λ of the current drag, their ticks. */
    chart: () => (app.chart ? { points: app.chart.current.length, lambdas: [...app.chart.lambdas], ticks: app.chart.volumePlot.tickValues, lambdaTicks: app.chart.lambdaPlot.tickValues } : null),
    /**
     * The model's file: name, format, bytes (null for samples and OBJ texts made here), and where its
     * levels were found and its first editor made ('worker': by the file's worker, the page opened them
     * without detecting / took the editor made there).
     */
    modelFile: () => (app.model ? { name: app.model.name, kind: app.model.kind, format: app.model.format ?? null, bytes: app.model.bytes?.byteLength ?? null, vertices: app.model.vertices ?? null, levelsFrom: app.model.levelsFrom ?? null, editorFrom: app.model.editorFrom ?? null } : null),
    /** ms since navigation: first drag-ready frame, theta in use; step and input-to-frame times. */
    /** The last big opening's or editor rebuild's stages: { what, since, stages: [{ stage, thread, ms }] } (web/open-stages.js). */
    openStages,
    stats: () => ({
      ...app.stats, steps: [...app.stats.steps], frames: [...app.stats.frames], renders: [...app.stats.renders],
      layers: [...app.stats.layers],
    }),
    /** The layers: shown or not, what the viewer draws (counts), the level l, updates and their cost. */
    layers: () => {
      const drawn = app.viewer.overlayInfo();
      const layers = app.layers;
      return {
        approx: { shown: app.settings.showApprox, ...drawn.approx },
        details: { shown: app.settings.showDetails, ...drawn.details },
        level: layers?.level ?? null, updates: layers?.updates ?? 0, lastMs: layers?.lastMs ?? null,
        deferred: Boolean(layers?.deferred),
      };
    },
    /**
     * What the view draws against the editor: the largest difference of the mesh's position
     * attribute from the editor's positions (relative to the mesh's size) and of its normal
     * attribute from normals three.js computes from those positions; the vertices the last upload
     * copied; whether drawing again now copies anything (it should not without an edit).
     */
    /** Whether a new editor's surface buffers still wait for an idle moment (the view draws the shape as it was). */
    surfacePending: () => Boolean(app.viewer.surfaceLater),
    drawnSurface: () => {
      const geometry = app.viewer.mesh?.geometry;
      if (!geometry || !editor()) return null;
      const positions = app.session.positions(), drawn = geometry.getAttribute('position').array;
      let size = 0, positionsError = 0;
      for (let i = 0; i < positions.length; i++) {
        size = Math.max(size, Math.abs(positions[i]));
        positionsError = Math.max(positionsError, Math.abs(drawn[i] - positions[i]));
      }
      const check = geometry.clone();
      check.getAttribute('position').array.set(positions);
      check.computeVertexNormals();
      const expected = check.getAttribute('normal').array, normals = geometry.getAttribute('normal')?.array;
      let normalsError = normals ? 0 : null;
      if (normals) for (let i = 0; i < expected.length; i++) normalsError = Math.max(normalsError, Math.abs(normals[i] - expected[i]));
      check.dispose();
      const lastCopied = { ...app.viewer.surfaceUpload?.lastCopied };
      const copiesAgain = app.viewer.surfaceUpload?.draw(geometry, editor(), { normals: !app.viewer.flat }) ?? null;
      return { vertices: positions.length / 3, positionsError: positionsError / size, normalsError, lastCopied, copiesAgain };
    },
    /** The free set: mode, pointer tool, painted handles and parts' handles (cage indices, sorted). */
    freeSet: () => {
      const cageIndex = app.session?.cageIndex;
      const toCage = (list) => list.map((v) => cageIndex?.get(v)).filter((i) => i !== undefined).sort((a, b) => a - b);
      return {
        mode: app.settings.freeSet, tool: app.settings.tool,
        painted: toCage(app.settings.painted), parts: app.settings.parts.map(toCage),
      };
    },
    /** Localized preservation: part numbers, their volumes now and their references; null without parts. */
    partVolumes: () => {
      const volumes = app.session?.partVolumes();
      return volumes ? { parts: [...app.session.parts], volumes, references: [...app.session.partReferences] } : null;
    },
  };
  Object.defineProperty(window, 'mrvolDebug', { value: Object.freeze(hook), writable: false, configurable: false });
}

/** The view's pixels (RGBA) of a frame drawn now (the drawing buffer holds it), for the checks above. */
function viewPixels(viewer) {
  viewer.renderer.render(viewer.scene, viewer.camera);
  const { width, height } = viewer.canvas;
  const copy = Object.assign(document.createElement('canvas'), { width, height }).getContext('2d', { willReadFrequently: true });
  copy.drawImage(viewer.canvas, 0, 0);
  return copy.getImageData(0, 0, width, height).data;
}
