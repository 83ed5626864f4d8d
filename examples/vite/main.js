// A minimal vite page using mrvol in the browser: loads the WASM core (the package's browser entry
// finds its .wasm through new URL(..., import.meta.url), which vite copies into the build), opens
// the spiky ball (public/spiky-ball.obj, a copy of examples/models/spiky-ball.obj), moves one vertex
// of its level-0 cage and shows the volume before and after.
//
//   npm install mrvol vite && cp node_modules/mrvol/examples/models/spiky-ball.obj public/
//   npx vite            (or: npx vite build && npx vite preview)
import { createMrvol } from 'mrvol';

const out = document.querySelector('#result');

async function main() {
  const mrvol = await createMrvol();
  const response = await fetch(new URL('spiky-ball.obj', document.baseURI));
  if (!response.ok) throw new Error(`spiky-ball.obj: HTTP ${response.status}`);
  const mr = mrvol.openMesh(mrvol.readObj(await response.text()));
  const editor = mr.createEditor({ level: 0 });
  const vertex = editor.cageVertices()[0];
  // The cage holds coarse coefficients: the moved vertex's cage position moves by the offset, the
  // fine surface follows smoothly.
  const c = editor.cageIndexOf(vertex);
  const cageBefore = editor.cagePositions();
  const report = editor.moveVertices([{ vertex, offset: [0.25, 0, 0] }]);
  const positions = editor.positions();
  const volume = mrvol.volume({ positions, faces: mr.faces() });
  const result = {
    vertices: mr.vertexCount,
    levels: mr.levels,
    vertex,
    movedBy: editor.cagePositions()[3 * c] - cageBefore[3 * c],
    volumeBefore: report.volumeReference,
    volumeAfter: volume,
    relativeChange: Math.abs(volume - report.volumeReference) / Math.abs(report.volumeReference),
    iterations: report.iterations,
    path: report.path,
  };
  mr.delete();
  return result;
}

main().then(
  (result) => {
    out.textContent = JSON.stringify(result, null, 2);
    out.dataset.state = 'done';
  },
  (e) => {
    out.textContent = `error: ${e.message}`;
    out.dataset.state = 'error';
  },
);
