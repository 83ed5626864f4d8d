// Nothing the user made is lost to the usual ways of working (real IndexedDB, real tabs of one
// browser profile): a sample or file opened again brings its stored edits back (rather than its
// fresh copy writing over them), an edit made just before another model is opened is stored, a
// share link opens beside the model's own stored edits, two tabs editing one model keep their edits
// apart, a reload opens the tab's own model, storage cleared under the page is written again, the
// message's × stops the remesh running under it, and the keys: Ctrl+Z from a select, Ctrl+O, Ctrl+S.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, visibleHandles, dragHandle, settle, root } from './harness.mjs';

const debug = (page, name) => page.evaluate((n) => window.mrvolDebug[n](), name);
const undoSteps = async (page) => (await debug(page, 'historySize')).undo;
const recent = (page) => page.$$eval('[data-testid="recent-item"]', (items) => items.map((b) => b.textContent));
const notice = (page) => page.locator('[data-testid="notice"]').textContent();

async function dragFirst(page, dx = 30, dy = -20) {
  const { index } = (await visibleHandles(page))[0];
  await dragHandle(page, index, dx, dy, { steps: 3 });
  await settle(page);
}

async function openSample(page, name) {
  await page.locator('[data-testid="model-select"]').selectOption(name);
  await page.waitForFunction((n) => window.mrvolDebug.modelName() === n && window.mrvolDebug.ready(), name);
}

/**
 * Waits until the store holds the current model with `steps` undo steps, saved after `since` (ms
 * since the epoch: another tab's record of the same model may have those steps already); the save
 * is debounced and written in a worker. Returns the record's time.
 * (Polled from here: page.waitForFunction takes an async predicate's promise for a truthy value and
 * returns at once.)
 */
async function stored(page, steps, since = 0, timeout = 30_000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const { saved, undo } = await page.evaluate(async () => {
      const id = window.mrvolDebug.storedSessionId?.();
      const record = id ? await window.mrvolDebug.storedSession(id) : null;
      return { saved: record?.saved ?? 0, undo: record?.history?.steps?.undo?.length ?? -1 };
    });
    if (undo === steps && saved > since) return saved;
    if (Date.now() > deadline) throw new Error(`the store holds ${undo} undo steps (saved at ${saved}), not ${steps} saved after ${since}`);
    await page.waitForTimeout(200);
  }
}

describe('nothing lost: stored edits, tabs, share links, storage, remesh, keys', { timeout: 600_000 }, () => {
  let server, browser;
  before(async () => {
    server = await startTestServer();
    browser = await launchBrowser(server.url, { viewport: { width: 1280, height: 800 } });
  });
  after(async () => {
    await browser?.close();
    await server?.close();
  });

  test('a sample opened again has its edits back; an edit made just before another model opens is stored', async () => {
    const page = await browser.newPage();
    await page.goto(`${server.url}?model=spiky-ball`);
    await waitReady(page);
    await dragFirst(page);
    await stored(page, 1);
    await openSample(page, 'torus');
    await openSample(page, 'spiky-ball');
    assert.equal(await undoSteps(page), 1, 'the edit and its undo step are back');
    assert.match(await notice(page), /^Your edits of spiky-ball are back \(1 step of undo history\); "reset \(forget edits\)" starts over\. open a fresh copy instead$/);
    // a second edit, and another model at once (its save still waiting): stored all the same
    await dragFirst(page, -25, 15);
    await openSample(page, 'torus');
    await openSample(page, 'spiky-ball');
    assert.equal(await undoSteps(page), 2, 'the edit made just before switching is kept');
    // "open a fresh copy instead": the sample as it comes, in a record of its own; its own edits stay
    const edited = await debug(page, 'cagePositions');
    await page.locator('[data-testid="open-fresh-copy"]').click();
    await page.waitForFunction(() => window.mrvolDebug.ready() && window.mrvolDebug.historySize().undo === 0 &&
                                     /#fresh copy/.test(window.mrvolDebug.storedSessionId()));
    assert.notDeepEqual(await debug(page, 'cagePositions'), edited, 'the shape as the sample comes');
    assert.equal(new URL(page.url()).searchParams.get('model'), null, 'a reload does not take the copy for the sample');
    await dragFirst(page, 15, 15);
    await stored(page, 1);
    await page.waitForFunction(() => [...document.querySelectorAll('[data-testid="recent-item"]')].some((b) => /^spiky-ball \(fresh copy, /.test(b.textContent)));
    await openSample(page, 'torus');
    await openSample(page, 'spiky-ball');
    assert.equal(await undoSteps(page), 2, 'the sample\'s own edits as they were');
    assert.ok((await debug(page, 'cagePositions')).every((x, i) => Math.abs(x - edited[i]) < 1e-9 * (1 + Math.abs(x))));
    assert.deepEqual(page.problems, []);
    await page.close();
  });

  test('a file dropped again has its edits back; an edit made just before it is dropped again too', async () => {
    const page = await browser.newPage();
    await page.goto(`${server.url}?model=torus`);
    await waitReady(page);
    const blob = readFileSync(join(root, 'public/models/blob.obj'));
    const drop = async () => {
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'my-blob.obj', mimeType: 'text/plain', buffer: blob });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'my-blob.obj' && window.mrvolDebug.ready());
    };
    // (the name was already the current one: opened again once the notice, cleared here, says so)
    const dropAgain = async (steps) => {
      await page.evaluate(() => { document.querySelector('[data-testid="notice"]').textContent = ''; });
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'my-blob.obj', mimeType: 'text/plain', buffer: blob });
      await page.waitForFunction(() => /^Your edits of my-blob\.obj are back/.test(document.querySelector('[data-testid="notice"]').textContent) &&
                                       window.mrvolDebug.ready());
      assert.equal(await undoSteps(page), steps);
      assert.match(await notice(page), new RegExp(`^Your edits of my-blob\\.obj are back \\(${steps} steps? of undo history\\)`));
    };
    const sameShape = (a, b) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) < 1e-9 * (1 + Math.abs(x)));
    await drop();
    assert.equal(await undoSteps(page), 0);
    await dragFirst(page);
    await stored(page, 1);
    const cage = await debug(page, 'cagePositions');
    await dropAgain(1);
    assert.ok(sameShape(await debug(page, 'cagePositions'), cage), 'the edited shape is back');
    // more edits, each with the file dropped again at once (its save still waiting): back all the same,
    // and the fresh copy's first save did not write over them; the last with the store's worker busy
    // (as while it writes a big file), so the edit's save is answered only after the file is read again
    const storeWorker = page.workers().find((w) => /store-worker/.test(w.url()));
    assert.ok(storeWorker, page.workers().map((w) => w.url()).join(' | '));
    for (let steps = 2; steps <= 4; steps++) {
      const { index } = (await visibleHandles(page))[0];
      await dragHandle(page, index, steps % 2 ? 25 : -25, 15, { steps: 3 });
      const edited = await debug(page, 'cagePositions');
      if (steps === 4) await storeWorker.evaluate(() => { setTimeout(() => { for (const end = Date.now() + 1500; Date.now() < end;); }); });
      await dropAgain(steps);
      assert.ok(sameShape(await debug(page, 'cagePositions'), edited), `the shape of edit ${steps} is back`);
    }
    await stored(page, 4);
    assert.deepEqual(page.problems, []);
    await page.close();
  });

  test('a share link opens beside the model\'s own stored edits: both in recent models', async () => {
    const page = await browser.newPage();
    await page.goto(`${server.url}?model=spiky-ball`);
    await waitReady(page);
    const own = await undoSteps(page);
    assert.ok(own >= 2, 'spiky-ball\'s edits from the first test');
    await dragFirst(page, 10, 30);
    await stored(page, own + 1);
    await page.locator('[data-testid="share-link"]').click();
    await page.waitForFunction(() => document.querySelector('[data-testid="share-url"]').value.includes('edits='));
    const url = await page.locator('[data-testid="share-url"]').inputValue();
    await page.locator('#share-close').click();
    await page.close();

    const shared = await browser.newPage();
    await shared.goto(url);
    await waitReady(shared);
    await dragFirst(shared, -40, 0); // an edit of the shared copy: saved in its own record
    await stored(shared, 1);
    await shared.waitForFunction(() => [...document.querySelectorAll('[data-testid="recent-item"]')].some((b) => /spiky-ball \(shared link\)/.test(b.textContent)));
    await openSample(shared, 'torus');
    await openSample(shared, 'spiky-ball');
    assert.equal(await undoSteps(shared), own + 1, 'the sample\'s own edits are as they were');
    const items = await recent(shared);
    assert.ok(items.some((t) => /^spiky-ball \(shared link\)/.test(t)) && items.some((t) => /^spiky-ball( ·)?$/.test(t)), items.join(' | '));
    await shared.close();
  });

  test('two tabs editing one model keep their edits apart; a reload opens the tab\'s own', async () => {
    const a = await browser.newPage();
    await a.goto(`${server.url}?model=blob`);
    await waitReady(a);
    const b = await browser.newPage();
    await b.goto(`${server.url}?model=blob`);
    await waitReady(b);
    await dragFirst(a, 30, 0);
    const savedByA = await stored(a, 1);
    await dragFirst(b, 0, 30);
    await stored(b, 1, savedByA);
    // a's next save: b wrote blob's record since, so a's edits go to a record of their own
    await dragFirst(a, -30, 0);
    await a.waitForFunction(() => /blob was saved from another tab too: this tab's edits are kept apart/.test(document.querySelector('[data-testid="notice"]').textContent));
    await stored(a, 2);
    const aCage = await debug(a, 'cagePositions');
    await a.reload();
    await a.waitForFunction(() => window.mrvolDebug.modelName() === 'blob' && window.mrvolDebug.ready());
    assert.equal(await undoSteps(a), 2, 'tab a reopens its own edits');
    const again = await debug(a, 'cagePositions');
    assert.ok(again.every((x, i) => Math.abs(x - aCage[i]) < 1e-9 * (1 + Math.abs(x))));
    await b.reload();
    await b.waitForFunction(() => window.mrvolDebug.modelName() === 'blob' && window.mrvolDebug.ready());
    assert.equal(await undoSteps(b), 1, 'tab b reopens its own edit');
    assert.deepEqual([...a.problems, ...b.problems], []);
    await a.close();
    await b.close();
  });

  test('the site\'s storage cleared under the page: the next save opens the database again', async () => {
    const page = await browser.newPage();
    const opened = Date.now();
    await page.goto(`${server.url}?model=torus`);
    await waitReady(page);
    await stored(page, await undoSteps(page), opened); // the opening's own save written first
    const cdp = await browser.context.newCDPSession(page);
    await cdp.send('Storage.clearDataForOrigin', { origin: new URL(server.url).origin, storageTypes: 'indexeddb' });
    await dragFirst(page);
    await stored(page, 1);
    assert.equal(await page.locator('[data-testid="storage-problem"]').textContent(), '');
    await page.close();
  });

  test('the message\'s × stops the remesh running under it', async () => {
    const page = await browser.newPage();
    await page.goto(`${server.url}?model=torus`);
    await waitReady(page);
    // a file that opens but is not semi-regular (a 25 x 11 torus grid: odd, so no 1-to-4 split): remeshed by itself, in a worker
    const grid = [], nu = 25, nv = 11;
    for (let i = 0; i < nu; i++) for (let j = 0; j < nv; j++) {
      const u = 2 * Math.PI * i / nu, v = 2 * Math.PI * j / nv;
      grid.push(`v ${(2 + Math.cos(v)) * Math.cos(u)} ${(2 + Math.cos(v)) * Math.sin(u)} ${Math.sin(v)}`);
    }
    const id = (i, j) => ((i + nu) % nu) * nv + ((j + nv) % nv) + 1;
    for (let i = 0; i < nu; i++) for (let j = 0; j < nv; j++) grid.push(`f ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)}`, `f ${id(i, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}`);
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'grid.obj', mimeType: 'text/plain', buffer: Buffer.from(grid.join('\n')) });
    await page.locator('[data-testid="remesh-offer"]').waitFor({ state: 'visible' });
    await page.locator('#error-close').click();
    assert.equal(await notice(page), 'Remeshing cancelled.');
    await page.waitForTimeout(4000); // long enough for the remesh of this small grid to have finished
    assert.equal(await debug(page, 'modelName'), 'torus', 'no result replaced the model');
    await page.close();
  });

  test('keys: Ctrl+Z with a select focused undoes, Ctrl+O opens the file picker, Ctrl+S saves the project', async () => {
    const page = await browser.newPage();
    await page.goto(`${server.url}?model=torus`);
    await waitReady(page);
    const before = await undoSteps(page);
    await dragFirst(page);
    assert.equal(await undoSteps(page), before + 1);
    await page.focus('[data-testid="scheme"]');
    await page.keyboard.press('Control+z');
    assert.equal(await undoSteps(page), before, 'undone from the select');
    const [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.keyboard.press('Control+o')]);
    assert.equal(chooser.isMultiple(), true);
    await page.focus('#view canvas');
    const [download] = await Promise.all([page.waitForEvent('download'), page.keyboard.press('Control+s')]);
    assert.match(download.suggestedFilename(), /^torus\.mrvol\.json$/);
    assert.deepEqual(page.problems, []);
    await page.close();
  });
});
