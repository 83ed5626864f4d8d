// Moving a big mesh's editor from the file's worker to the page (issues 13, 14): the worker opens
// the mesh and makes the editor (seconds at 655k vertices), then hands over a copy of its module's
// whole memory; the page takes it into a fresh instance of the module (lib/api.mjs transferable /
// adoptTransferred), a copy of memory instead of seconds of work on its thread.
//
// embind keeps, in memory, an id per call site that indexes tables on the JS side of its instance;
// the copy is only right when both instances built those tables alike. So both run warmUp() (the
// same calls, the ones the worker's work makes, on a small mesh) before anything else: the worker
// on starting, the page on the fresh instance before it takes the copy.
import { triangleGradientChoice } from '../lib/three/session.mjs';

const ICOSAHEDRON = {
  positions: new Float64Array([0, -0.525731, 0.850651, 0.850651, 0, 0.525731, 0.850651, 0, -0.525731, -0.850651, 0, -0.525731,
    -0.850651, 0, 0.525731, -0.525731, 0.850651, 0, 0.525731, 0.850651, 0, 0.525731, -0.850651, 0, -0.525731, -0.850651, 0,
    0, -0.525731, -0.850651, 0, 0.525731, -0.850651, 0, 0.525731, 0.850651]),
  faces: new Uint32Array([1, 2, 6, 1, 7, 2, 3, 4, 5, 4, 3, 8, 6, 5, 11, 5, 6, 10, 9, 10, 2, 10, 9, 3, 7, 8, 9, 8, 7, 0, 11, 0, 1,
    0, 11, 4, 6, 2, 10, 1, 6, 11, 3, 5, 10, 5, 4, 11, 2, 7, 9, 7, 1, 0, 3, 9, 8, 4, 8, 0]),
};

/** The calls a transfer depends on, on a 642-vertex ball: run first in both instances. */
export function warmUp(mrvol) {
  for (const step of warmUpSteps(mrvol)) step();
}

/** warmUp a call or two at a time, awaiting `between()` after each (the page draws between them). */
export async function warmUpInSteps(mrvol, between) {
  for (const step of warmUpSteps(mrvol)) {
    step();
    await between();
  }
}

// The same calls in the same order, whichever way they are run.
function warmUpSteps(mrvol) {
  let ball, bytes, mesh, mr, editor, thetaBytes;
  return [
    () => {
      ball = mrvol.subdivide(ICOSAHEDRON, { levels: 3 });
      bytes = new TextEncoder().encode(mrvol.writeObj(ball.toMesh()));
      ball.delete();
    },
    () => {
      mrvol.detectFormat(bytes, 'warm-up.obj');
      mesh = mrvol.readMesh(bytes, { name: 'warm-up.obj' });
    },
    () => {
      mr = mrvol.openMesh(mesh);
      const again = mrvol.openMeshWithHierarchy(mesh, mr.hierarchyArrays());
      again.delete();
      mr.info();
    },
    // the limit surface's and the kept centre of mass's calls too (a rebuild with them: editor-worker.js),
    // and theta^e's estimate (the session's rule on a fine cage: triangleGradientChoice); a step each
    () => mr.estimateTheta({ level: 0, scheme: 'loop' }),
    ...[{ surface: 'limit' }, { keepCentroid: true }, { path: 'matrix-free' }].map((settings) => () => {
      const other = buildEditor(mrvol, mr, { level: 0, scheme: 'loop', ...settings });
      other.surface();
      other.keepsCentroid();
      other.delete();
    }),
    () => {
      // the tensor path's calls (editor-worker.js reads a cached theta^e and hands it to the editor),
      // on a 42-vertex ball: on the 642-vertex one theta^0 takes most of a second
      const small = mrvol.subdivide(ICOSAHEDRON, { levels: 1 });
      const computed = small.computeTheta({ level: 0, scheme: 'loop' });
      thetaBytes = computed.bytes();
      computed.delete();
      small.delete();
    },
    () => {
      const small = mrvol.subdivide(ICOSAHEDRON, { levels: 1 });
      const theta = mrvol.readTheta(thetaBytes);
      theta.info();
      const other = buildEditor(mrvol, small, { level: 0, scheme: 'loop', path: 'matrix-free' });
      other.useTheta(theta);
      other.delete();
      theta.delete();
      small.delete();
    },
    () => {
      editor = buildEditor(mrvol, mr, { level: 0, scheme: 'loop' });
      editor.positions();
    },
    () => {
      mrvol.transferable(mr, editor, { memory: false }); // its calls (no copy of the memory)
      editor.delete();
      mr.delete();
    },
  ];
}

/**
 * The editor the page's session would make (lib/three/session.mjs #buildEditor) for its settings:
 * the surface whose volume is kept, the centre of mass kept or not, the session's path ('auto': the
 * cage polynomial where the session would take it; 'matrix-free': until theta^e comes).
 */
export function buildEditor(mrvol, mr, { level, scheme, surface = 'mesh', keepCentroid = false, path = 'auto' }) {
  const keep = keepCentroid && surface !== 'limit' ? ['volume', 'centroid'] : undefined; // as EditingSession.open
  const editor = mr.createEditor({ level, scheme, path: 'matrix-free', surface, keep });
  // as the session: 'auto' takes the polynomial where its rule does; 'matrix-free' waits for theta^e
  if (path === 'auto' && triangleGradientChoice(mr, { level, scheme, surface, path }).path === 'polynomial') editor.usePolynomial();
  return editor;
}
