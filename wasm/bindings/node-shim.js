// Linked with --extern-pre-js into the Node build only: emscripten 3.1.6's ES module output uses
// CommonJS names under Node.
import { createRequire } from 'node:module';
import { dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
const require = createRequire(import.meta.url);
const __dirname = dirname(fileURLToPath(import.meta.url));
