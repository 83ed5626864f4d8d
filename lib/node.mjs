// Node entry point: loads the Node build of the WASM module (build/wasm, made by `npm test`,
// `npm start` or `npm pack`) and returns the public API.
import { readFile } from 'node:fs/promises';
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
