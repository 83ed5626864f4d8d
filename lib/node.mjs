// Node entry point: loads the Node build of the WASM module (build/wasm, made by `npm test`,
// `npm start` or `npm pack`) and returns the public API.
import { open, readFile } from 'node:fs/promises';
import { wrapModule, MrvolError } from './api.mjs';

export { MrvolError, wrapModule };

const buildDir = new URL('../build/wasm/', import.meta.url);

// The .wasm bytes: given, or read from wasmUrl / locateFile's answer / the build folder.
async function wasmBytes({ wasmBinary, wasmUrl, locateFile }) {
  if (wasmBinary !== undefined) {
    if (!(wasmBinary instanceof ArrayBuffer || ArrayBuffer.isView(wasmBinary)))
      throw new MrvolError('wasmBinary must be an ArrayBuffer or a typed array');
    return wasmBinary;
  }
  const where = wasmUrl ?? (locateFile ? locateFile('mrvol-node.wasm', buildDir.href) : new URL('mrvol-node.wasm', buildDir));
  const path = typeof where !== 'string' ? new URL(where.href) : where.startsWith('file:') ? new URL(where) : where;
  try {
    return await readFile(path);
  } catch (e) {
    throw new MrvolError(`cannot read the WASM module ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}` +
                         (wasmUrl ?? locateFile ? '' : "; in a checkout, run 'npm test' or 'node scripts/setup.mjs'"));
  }
}

/**
 * Loads the WASM core and returns the API.
 * @param {{ wasmBinary?: ArrayBuffer | ArrayBufferView, wasmUrl?: string | URL,
 *           locateFile?: (path: string, prefix: string) => string }} [options]
 *   where the .wasm is when not in build/wasm beside lib/ (a path or file: URL), or its bytes
 * @returns {Promise<ReturnType<typeof wrapModule>>}
 */
export async function createMrvol(options = {}) {
  let factory;
  try {
    ({ default: factory } = await import(new URL('mrvol-node.mjs', buildDir).href));
  } catch (e) {
    throw new MrvolError(`the WASM module is not built (${e.message}); run 'npm test' or 'node scripts/setup.mjs'`);
  }
  // emscripten 3.1.6 would fetch() the .wasm under Node too: hand it the bytes.
  const module = await factory({ wasmBinary: await wasmBytes(options) });
  return wrapModule(module);
}

/**
 * Reads an OBJ file from disk in chunks straight into the WASM reader (mrvol.createObjReader):
 * Node never holds the whole file, the WASM heap never holds its text. Returns what
 * mrvol.readObj gives. onProgress(fraction) after each chunk; chunkBytes: the read size.
 * File errors throw MrvolError("cannot read PATH: ..."); bad OBJ lines MrvolError("line L: ...").
 */
export async function readObjFile(mrvol, path, { chunkBytes = 16 << 20, onProgress } = {}) {
  let file;
  try {
    file = await open(path, 'r');
  } catch (e) {
    throw new MrvolError(`cannot read ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  }
  let reader;
  try {
    const size = (await file.stat()).size;
    reader = mrvol.createObjReader({ size });
    const buffer = new Uint8Array(Math.max(1, Math.min(chunkBytes, size)));
    for (let at = 0; ;) {
      let bytesRead;
      try {
        ({ bytesRead } = await file.read(buffer, 0, buffer.length, at));
      } catch (e) {
        throw new MrvolError(`cannot read ${path}: ${e.message}`);
      }
      if (bytesRead === 0) break;
      reader.push(buffer.subarray(0, bytesRead));
      at += bytesRead;
      onProgress?.(size > 0 ? Math.min(1, at / size) : 1);
    }
    const mesh = reader.finish();
    reader = null;
    return mesh;
  } finally {
    reader?.cancel();
    await file.close();
  }
}
