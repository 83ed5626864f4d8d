// Browser entry point: loads the browser build of the WASM module (build/wasm/mrvol-web.{mjs,wasm},
// found next to this file's folder by URL, which bundlers such as vite follow) and returns the API.
import createMrvolModule from '../build/wasm/mrvol-web.mjs';
import { wrapModule, MrvolError } from './api.mjs';

export { wrapModule, MrvolError, DEFAULT_SCHEME, chooseGradientPath } from './api.mjs';

const defaultWasmUrl = new URL('../build/wasm/mrvol-web.wasm', import.meta.url);

/**
 * Compiles and instantiates the module, then wraps it (lib/api.mjs).
 * @param {{ wasmUrl?: string | URL }} [options] where mrvol-web.wasm is served, if elsewhere
 */
export async function createMrvol({ wasmUrl = defaultWasmUrl } = {}) {
  let compiled;
  try {
    const response = await fetch(wasmUrl);
    if (!response.ok) throw new Error(`HTTP ${response.status}`);
    compiled = await WebAssembly.compile(await response.arrayBuffer());
  } catch (e) {
    throw new MrvolError(`could not load the WASM module from ${wasmUrl} (${e.message})`);
  }
  const raw = await new Promise((resolve, reject) => {
    createMrvolModule({
      // emscripten 3.1.6's own fetch path has no branch for module workers: it is handed the module.
      instantiateWasm(imports, receiveInstance) {
        WebAssembly.instantiate(compiled, imports).then((instance) => receiveInstance(instance, compiled), reject);
        return {};
      },
    }).then(resolve, reject);
  });
  return wrapModule(raw);
}
