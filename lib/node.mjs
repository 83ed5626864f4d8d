// Node entry point: loads the Node build of the WASM module (build/wasm, made by `npm test` or
// `npm start`) and returns the public API.
import { readFile } from 'node:fs/promises';
import { wrapModule, MrvolError } from './api.mjs';

export { MrvolError };
export { remesh, repair } from './remesh.mjs';

const buildDir = new URL('../build/wasm/', import.meta.url);

/** @returns {Promise<ReturnType<typeof wrapModule>>} */
export async function createMrvol() {
  let factory, wasmBinary;
  try {
    ({ default: factory } = await import(new URL('mrvol-node.mjs', buildDir).href));
    wasmBinary = await readFile(new URL('mrvol-node.wasm', buildDir));
  } catch (e) {
    throw new MrvolError(`the WASM module is not built (${e.message}); run 'npm test' or 'node scripts/setup.mjs'`);
  }
  // emscripten 3.1.6 would fetch() the .wasm under Node too: hand it the bytes.
  const module = await factory({ wasmBinary });
  return wrapModule(module);
}
