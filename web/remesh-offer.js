// The offer to remesh a mesh file that read but cannot be edited: not semi-regular (remeshing), or
// not a closed 2-manifold (repair first). Runs lib/remesh.mjs in a worker (started at once with
// `auto`; the fields change it and run it again, cancel stops it); the result goes to `open` as a
// new model named after the file, and the notice says what was done. Into triangles, or into quads
// (lib/remesh-quad.mjs: Catmull-Clark levels; the default for a file of quads).
import { baseNameOf } from './models.js';

const $ = (id) => document.getElementById(id);

let worker = null;

export function hideRemeshOffer() {
  cancelRemesh();
  $('remesh-offer').hidden = true;
}

/** Stops a running remesh (the cancel button); false when none runs. */
export function cancelRemesh() {
  if (!worker) return false;
  worker.terminate();
  worker = null;
  $('remesh-progress').hidden = true;
  $('remesh-cancel').hidden = true;
  $('remesh-go').disabled = false;
  $('remesh-stage').textContent = 'cancelled';
  return true;
}

/**
 * source: { name, mesh: { positions, faces } } (or { name, text }: an OBJ); repair: start with the
 * repair stage checked; auto: start at once. open({ name, kind, text }) resolves true when the
 * result opened; notice(text) shows the outcome.
 */
const count = (n, one, many = `${one}s`) => `${n} ${n === 1 ? one : many}`;

/** What the repair did, in words: the counts that are not 0 (lib/repair.mjs's report). */
export function repairWords(report, piecesDropped) {
  const dropped = report.degenerateFaces + report.finFaces + report.duplicateFaces + report.nonManifoldFaces + report.foldedFaces;
  const done = [
    [report.weldedVertices, (n) => `${count(n, 'vertex', 'vertices')} welded`],
    [report.unusedVertices, (n) => `${count(n, 'unused vertex', 'unused vertices')} dropped`],
    [dropped, (n) => `${count(n, 'face')} dropped`],
    [report.reorientedFaces, (n) => `${count(n, 'face')} turned to agree`],
    [report.reversedComponents, (n) => `${count(n, 'piece')} turned outward`],
    [piecesDropped, (n) => `${count(n, 'piece')} dropped`],
    [report.holesFilled, (n) => `${count(n, 'hole')} closed`],
  ].filter(([n]) => n > 0).map(([n, words]) => words(n));
  return done.length ? done.join(', ') : 'nothing needed it';
}

/**
 * The remesher's message for the app: its hints name the CLI's flags and the API's options
 * (lib/remesh.mjs); here they name the form's repair box (which closes holes of up to 100 edges).
 */
export function remeshFailureWords(message) {
  return message
    .replace(' (--repair drops such faces and closes the holes)', ' (tick repair: it drops such faces and closes the holes)')
    .replace('close the holes first (or try --repair)', 'close the holes first, or tick repair (it closes holes of up to 100 edges)')
    .replace('holes larger than the repair closes are left (raise maxHoleEdges / --max-hole)',
             'the repair closes holes of up to 100 edges, and these are larger: close them in a modelling tool, or use the CLI\'s --max-hole')
    .replace('(--repair turns it)', '(tick repair: it turns it outward)');
}

export function offerRemesh(source, { repair = false, open, notice, auto = false, quads = false }) {
  cancelRemesh();
  // A question while nothing runs; while the worker runs, what it is doing (it was asked while the
  // work it asked about was already under way).
  // (named: another file's message may come to stand above it while it runs)
  const why = (running) => {
    $('remesh-why').textContent = `${source.name} is ` + (repair
      ? (running ? 'not a closed 2-manifold: repairing and remeshing it (the fields below run it again).' : 'not a closed 2-manifold: repair and remesh it?')
      : (running ? 'not semi-regular: remeshing it (the fields below run it again).' : 'not semi-regular: remesh it?'));
  };
  why(false);
  $('remesh-repair').checked = repair;
  $('remesh-largest').checked = false;
  $('remesh-into').value = quads ? 'quads' : 'triangles';
  $('remesh-smooth').disabled = !repair;
  $('remesh-repair').onchange = () => { $('remesh-smooth').disabled = !$('remesh-repair').checked; };
  $('remesh-offer').hidden = false;
  $('remesh-progress').hidden = true;
  $('remesh-stage').textContent = '';
  $('remesh-go').disabled = false;
  $('remesh-go').onclick = () => {
    const levels = Number($('remesh-levels').value), base = Number($('remesh-base').value);
    const repairing = $('remesh-repair').checked, smooth = Number($('remesh-smooth').value);
    const keepLargest = $('remesh-largest').checked;
    const intoQuads = $('remesh-into').value === 'quads';
    worker?.terminate();
    const running = new Worker(new URL('./remesh-worker.js', import.meta.url), { type: 'module', name: 'mrvol-remesh' });
    worker = running;
    // stays enabled: changed fields and a click run it again (the running job is replaced)
    // Indeterminate until the remesher reports (then its fraction done, never going back: a retry
    // on a larger base starts its fit over); the stage text says where it is.
    const bar = $('remesh-progress');
    bar.removeAttribute('value');
    bar.hidden = false;
    why(true);
    $('remesh-cancel').hidden = false;
    const started = performance.now();
    const finish = (stage) => {
      running.terminate();
      if (worker !== running) return false;
      worker = null;
      $('remesh-progress').hidden = true;
      $('remesh-cancel').hidden = true;
      $('remesh-go').disabled = false;
      $('remesh-stage').textContent = stage;
      why(false);
      return true;
    };
    running.onmessage = async ({ data }) => {
      if (worker !== running) return;
      if (data.type === 'stage') {
        $('remesh-stage').textContent = data.stage;
        return;
      }
      if (data.type === 'progress') {
        bar.max = 1;
        bar.value = Math.max(bar.hasAttribute('value') ? bar.value : 0, Math.min(1, data.fraction));
        $('remesh-stage').textContent = data.stage;
        return;
      }
      if (data.type === 'error') return finish(`remeshing failed: ${remeshFailureWords(data.message)}`);
      if (!finish('')) return;
      const r = data.report;
      const ok = await open({ name: `${baseNameOf(source.name)}-remeshed`, kind: 'file', text: data.text });
      // Pieces dropped: by "largest piece only", or closed but enclosing no volume.
      const dropped = r.input ? r.input.droppedComponents + r.input.droppedPieces : r.repair?.droppedComponents ?? 0;
      const fixes = r.repair ? `Repaired (${repairWords(r.repair, dropped)}), then remeshed` : `Remeshed${dropped > 0 ? ` (${count(dropped, 'piece')} dropped)` : ''}`;
      const pieces = r.components > 1 ? `${r.components} pieces, ` : '';
      if (ok && r.quads)
        notice(`${fixes} into quads in ${((performance.now() - started) / 1000).toFixed(1)} s: ${pieces}${r.levels} Catmull-Clark levels, ` +
          `${r.vertices} vertices, ${r.faces} quads, farthest vertex ${(100 * r.distanceToInput).toFixed(2)}% of the diagonal ` +
          `from the input, volume change ${(100 * r.volumeChange).toFixed(2)}%`);
      else if (ok)
        notice(`${fixes} in ${((performance.now() - started) / 1000).toFixed(1)} s: ${pieces}${r.levels} levels, ` +
          `${r.vertices} vertices, Hausdorff ${(100 * r.hausdorff).toFixed(2)}% of the diagonal, ` +
          `${r.flippedTriangles} flipped triangles, volume change ${(100 * r.volumeChange).toFixed(2)}%` +
          (r.baseGrown ? `; the first fit on ${r.baseGrown.asked} base faces folded, so the base was made larger (${r.baseFaces} faces)` : ''));
    };
    running.onerror = (e) => {
      e.preventDefault?.();
      finish(`remeshing failed: ${e.message || 'the worker could not start'}`);
    };
    const mesh = source.mesh ? { positions: source.mesh.positions, faces: source.mesh.faces } : undefined;
    // 0 levels: the remesher's default (from 2, more while the detail needs them; its cage goal), as the CLI's.
    running.postMessage({ text: source.text, mesh, levels: levels > 0 ? levels : undefined, baseFaces: base > 0 ? base : undefined,
      repair: repairing, keepLargest, smooth: repairing && smooth > 0 ? smooth : undefined, quads: intoQuads });
  };
  $('remesh-cancel').onclick = () => {
    cancelRemesh();
    why(false);
  };
  if (auto) $('remesh-go').onclick();
}
