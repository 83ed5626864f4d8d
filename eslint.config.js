// ESLint (flat config): the recommended rules over every JS folder, with the globals of where each
// file runs. `npm run lint`; scripts/test.mjs runs it as one test.
import js from '@eslint/js';
import globals from 'globals';

export default [
  { ignores: ['build/', 'dist/', 'node_modules/', 'public/', 'tests/fuzz/corpus/', 'wasm/bindings/node-shim.js'] },
  js.configs.recommended,
  {
    languageOptions: { ecmaVersion: 'latest', sourceType: 'module' },
    linterOptions: { reportUnusedDisableDirectives: 'error' },
    rules: {
      // `catch {}` and `catch (e) { ... }` without using e are deliberate where they appear.
      'no-unused-vars': ['error', { args: 'after-used', argsIgnorePattern: '^_', caughtErrors: 'none' }],
      'no-empty': ['error', { allowEmptyCatch: true }],
    },
  },
  // The library runs in Node, browsers and workers alike.
  { files: ['lib/**'], languageOptions: { globals: globals['shared-node-browser'] } },
  // The three.js component runs in pages (DOM, pointer events).
  { files: ['lib/three/**'], languageOptions: { globals: globals.browser } },
  // Node: the command line, scripts, benchmarks, tests, the Node example, config files.
  {
    files: ['bin/**', 'scripts/**', 'bench/**', 'tests/**', 'examples/node/**', '*.config.js', '*.config.mjs'],
    languageOptions: { globals: globals.node },
  },
  // The web app: page modules and module workers.
  { files: ['web/**', 'examples/web/**'], languageOptions: { globals: globals.browser } },
  { files: ['web/**/*worker*.js'], languageOptions: { globals: { ...globals.browser, ...globals.worker } } },
  // Browser tests and the web benchmark hand functions to page.evaluate(): they run in the page.
  {
    files: ['tests/browser/**', 'bench/web.mjs', 'bench/web-open-profile.mjs', 'bench/theta-handoff-trace.mjs', 'bench/web-big-trace.mjs', 'bench/memory-copy.mjs', 'tests/package/**'],
    languageOptions: { globals: { ...globals.node, ...globals.browser } },
  },
  // Tests look for control characters (NUL bytes, terminal escapes) on purpose.
  { files: ['tests/**'], rules: { 'no-control-regex': 'off' } },
];
