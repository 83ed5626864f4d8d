// The Node entry's types (lib/node.mjs): everything of the browser entry's (index.d.ts), and
// readObjFile, which reads from disk.
import type { Mrvol, ObjMesh } from './index.js';

export * from './index.js';

/**
 * Reads an OBJ file from disk in chunks straight into the WASM reader (Node never holds the whole
 * file). Returns what readObj gives; onProgress(fraction) after each chunk.
 */
export function readObjFile(mrvol: Mrvol, path: string,
                            options?: { chunkBytes?: number; onProgress?: (fraction: number) => void }): Promise<ObjMesh>;
