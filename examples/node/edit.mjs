// Edits a multiresolution mesh with mrvol in Node: opens a semi-regular OBJ, moves one vertex of
// its coarsest cage (level 0), lets mrvol restore the enclosed volume, checks it, and writes the
// edited OBJ.
//
//   npm install mrvol
//   node edit.mjs [IN.obj] [OUT.obj]     (default: the spiky ball shipped in examples/models/)
import { readFile, writeFile } from 'node:fs/promises';
import { createMrvol } from 'mrvol';

const input = process.argv[2] ?? new URL('../models/spiky-ball.obj', import.meta.url);
const output = process.argv[3] ?? 'edited.obj';

const mrvol = await createMrvol();
const mesh = mrvol.readObj(await readFile(input, 'utf8'));
// Detects the hierarchy of 1-to-4 splits (in any vertex order); a mesh without one opens with 0
// levels (its only cage is the mesh itself: `mrvol remesh` makes a semi-regular mesh of it).
const mr = mrvol.openMesh(mesh);
const info = mr.info();
console.log(`opened ${input}: ${info.vertices} vertices, ${info.levels} levels, volume ${info.volume}`);

// An editing session on the level-0 cage; its vertices are the mesh's own indices.
const editor = mr.createEditor({ level: 0 });
const vertex = editor.cageVertices()[0];
const offset = [0.25, 0, 0];
const report = editor.moveVertices([{ vertex, offset }]);

// The volume of the edited mesh, measured anew: the reference volume, up to the tolerance (1e-5).
const edited = { positions: editor.positions(), faces: mr.faces() };
const volume = mrvol.volume(edited);
const relativeChange = Math.abs(volume - report.volumeReference) / Math.abs(report.volumeReference);
console.log(`moved cage vertex ${vertex} by (${offset.join(', ')}): volume ${report.volumeReference} -> ${volume}` +
            ` (relative change ${relativeChange.toExponential(2)}, ${report.iterations} iterations, ${report.path} gradient)`);
if (!(relativeChange <= 1e-5)) {
  console.error('the volume was not kept');
  process.exit(1);
}

await writeFile(output, mrvol.writeObj(edited));
console.log(`wrote ${output}`);
mr.delete();
