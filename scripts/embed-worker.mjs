// Writes a pool worker's script (emscripten's *.worker.js) as the text of a JS module, for
// lib/browser.mjs to start the threaded module's pool from a blob: URL of the page's own origin.
// Served as a file, the script was inlined by bundlers as a data: URL (an opaque origin that may
// not import the module under COEP) or transformed by their dev servers into a module (its dynamic
// import rewritten with a static one): as a string it is neither.
//
//   node scripts/embed-worker.mjs IN.worker.js OUT.mjs
import { readFileSync, writeFileSync } from 'node:fs';
import { basename } from 'node:path';

const [input, output] = process.argv.slice(2);
if (!input || !output) {
  console.error('usage: node scripts/embed-worker.mjs IN.worker.js OUT.mjs');
  process.exit(2);
}
const text = readFileSync(input, 'utf8');
writeFileSync(output, `// ${basename(input)} as text (made by scripts/embed-worker.mjs at the build; do not edit).\n` +
                      `export default ${JSON.stringify(text)};\n`);
