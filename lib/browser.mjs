// Browser (and worker) entry point of the package: loads the web build of the WASM module
// (build/wasm/mrvol-web.{mjs,wasm}) and returns the public API (lib/api.mjs).
//
// The .wasm is referenced as `new URL('../build/wasm/mrvol-web.wasm', import.meta.url)`, which
// bundlers (vite, webpack 5, rollup plugins) follow to copy the file and rewrite the URL. Hosts
// that move assets elsewhere say where it is: `wasmUrl`, `locateFile` (emscripten's hook, as
// manifold-3d takes it), or the bytes or compiled module themselves.
import createMrvolModule from '../build/wasm/mrvol-web.mjs';
import { wrapModule, MrvolError } from './api.mjs';

export { MrvolError, wrapModule };
export { DEFAULT_SCHEME, chooseGradientPath } from './api.mjs';

const WASM_FILE = 'mrvol-web.wasm';
const defaultWasmUrl = () => new URL('../build/wasm/mrvol-web.wasm', import.meta.url).href;

// Where the .wasm is: wasmUrl, else what locateFile says, else next to this file (bundled or not).
function wasmLocation({ wasmUrl, locateFile }) {
  if (wasmUrl !== undefined) return typeof wasmUrl === 'string' ? wasmUrl : wasmUrl.href;
  if (locateFile) return locateFile(WASM_FILE, '');
  return defaultWasmUrl();
}

async function compile(options) {
  if (options.wasmModule !== undefined) {
    if (!(options.wasmModule instanceof WebAssembly.Module)) throw new MrvolError('wasmModule must be a WebAssembly.Module');
    return options.wasmModule;
  }
  if (options.wasmBinary !== undefined) {
    const bytes = options.wasmBinary;
    if (!(bytes instanceof ArrayBuffer || ArrayBuffer.isView(bytes)))
      throw new MrvolError('wasmBinary must be an ArrayBuffer or a typed array');
    return WebAssembly.compile(bytes);
  }
  const url = wasmLocation(options);
  let response;
  try {
    response = await fetch(url, { credentials: 'same-origin' });
  } catch (e) {
    throw new MrvolError(`could not fetch the WASM module from ${url}: ${e.message}`);
  }
  if (!response.ok) throw new MrvolError(`could not load the WASM module from ${url} (HTTP ${response.status})`);
  // Streaming compilation needs the server to send application/wasm; otherwise compile the bytes.
  if (response.headers.get('content-type')?.startsWith('application/wasm') && WebAssembly.compileStreaming) {
    try {
      return await WebAssembly.compileStreaming(response.clone());
    } catch {
      // fall through to the bytes
    }
  }
  try {
    return await WebAssembly.compile(await response.arrayBuffer());
  } catch (e) {
    throw new MrvolError(`${url} is not a loadable WASM module: ${e.message}`);
  }
}

/**
 * Loads the WASM core and returns the API.
 * @param {{ wasmUrl?: string | URL, locateFile?: (path: string, prefix: string) => string,
 *           wasmBinary?: ArrayBuffer | ArrayBufferView, wasmModule?: WebAssembly.Module }} [options]
 */
export async function createMrvol(options = {}) {
  const wasmModule = await compile(options);
  let failed;
  const failure = new Promise((_, reject) => (failed = reject));
  const raw = await Promise.race([
    createMrvolModule({
      // emscripten calls this instead of fetching the file itself: the module is compiled above.
      instantiateWasm(imports, receiveInstance) {
        WebAssembly.instantiate(wasmModule, imports).then((instance) => receiveInstance(instance, wasmModule), failed);
        return {};
      },
    }),
    failure,
  ]);
  return wrapModule(raw);
}
