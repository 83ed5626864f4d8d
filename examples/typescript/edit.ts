// A TypeScript consumer of mrvol's types (type-checked with `tsc --strict --noEmit`): the core API
// (mrvol) and the remesher (mrvol/remesh). Functions only, no I/O: they take and return OBJ text.
import { createMrvol, MrvolError } from 'mrvol';
import type { EditReport, Mesh, MeshInfo, Mrvol, MultiresMesh, VolumeEditor } from 'mrvol';
import { remesh } from 'mrvol/remesh';
import type { RemeshResult } from 'mrvol/remesh';

export interface EditResult {
  obj: string;
  report: EditReport;
  info: MeshInfo;
}

/** Moves one vertex of the level-e cage of a semi-regular OBJ by `offset`, keeping the volume. */
export async function moveCageVertex(objText: string, vertex: number, offset: [number, number, number],
                                     level = 0): Promise<EditResult> {
  const mrvol: Mrvol = await createMrvol();
  const mesh: Mesh = mrvol.readObj(objText);
  const mr: MultiresMesh = mrvol.openMesh(mesh);
  try {
    const editor: VolumeEditor = mr.createEditor({ level, scheme: 'loop' });
    const report = editor.moveVertices([{ vertex, offset }], { tolerance: 1e-6 });
    if (!report.converged) throw new MrvolError(`no convergence after ${report.iterations} iterations`);
    const obj = mrvol.writeObj({ positions: editor.positions(), faces: mr.faces() });
    return { obj, report, info: mr.info() };
  } finally {
    mr.delete();
  }
}

/**
 * Remeshes any closed manifold OBJ into a semi-regular one with `levels` levels; `stages` collects
 * what remesh() reported doing.
 */
export async function remeshObj(objText: string, levels: number, stages: string[] = []):
    Promise<{ obj: string; result: RemeshResult }> {
  // locateFile, as a host that serves the .wasm itself would pass it (here: where it already is).
  const mrvol = await createMrvol({ locateFile: (path, prefix) => prefix + path });
  const result = await remesh(mrvol, mrvol.readObj(objText), {
    levels,
    onProgress: (fraction, stage) => stages.push(`${Math.round(100 * fraction)}% ${stage}`),
  });
  return { obj: mrvol.writeObj(result.mesh), result };
}

/** The messages of mrvol's errors, anything else rethrown. */
export function describeError(e: unknown): string {
  if (e instanceof MrvolError) return e.message;
  throw e;
}
