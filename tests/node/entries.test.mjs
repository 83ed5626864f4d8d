// The package's entry points against what it declares and ships: every value the types declare is
// exported at run time by the entry they are the types of, and no more (lib/index.d.ts for
// lib/browser.mjs; lib/node.d.ts, index.d.ts's and readObjFile, for lib/node.mjs), and the Node
// builds' .wasm are the web builds' bytes (the package holds only the web builds' and Node reads them).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';

const lib = new URL('../../lib/', import.meta.url);
const build = new URL('../../build/wasm/', import.meta.url);

/** The value exports (functions, classes, consts) a .d.ts declares, sorted. */
function declaredValues(file) {
  const text = readFileSync(new URL(file, lib), 'utf8');
  return [...text.matchAll(/^export (?:declare )?(?:function|class|const|let) (\w+)/gm)].map((m) => m[1]);
}

test("lib/browser.mjs exports exactly index.d.ts's values; lib/node.mjs those and node.d.ts's readObjFile", async () => {
  const shared = declaredValues('index.d.ts');
  assert.ok(shared.includes('createMrvol') && shared.includes('canUseThreads'), shared.join(' '));
  const browser = await import(new URL('browser.mjs', lib).href);
  assert.deepEqual(Object.keys(browser).sort(), [...new Set(shared)].sort());
  const node = await import(new URL('node.mjs', lib).href);
  assert.deepEqual(Object.keys(node).sort(), [...new Set([...shared, ...declaredValues('node.d.ts')])].sort());
  assert.ok(!shared.includes('readObjFile'), 'readObjFile is Node only: not in the browser entry\'s types');
  assert.equal(node.canUseThreads(), true);
  assert.equal(node.DEFAULT_SCHEME, browser.DEFAULT_SCHEME);
});

test('the Node builds run the web builds\' .wasm: the same bytes', () => {
  for (const [nodeFile, webFile] of [['mrvol-node.wasm', 'mrvol-web.wasm'], ['mrvol-node-mt.wasm', 'mrvol-web-mt.wasm']])
    assert.ok(readFileSync(new URL(nodeFile, build)).equals(readFileSync(new URL(webFile, build))), `${nodeFile} = ${webFile}`);
});
