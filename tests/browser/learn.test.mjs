// The teaching views and the paper's demos (web/learn/): each view opens from its URL, renders
// (a non-blank canvas), responds to its controls, and shows numbers from the core. Screenshots of
// every view go to test-results/learn-*.png. One server and one browser for the file.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { readFileSync } from 'node:fs';
import { openApp, settle, root, RESULTS_DIR } from './harness.mjs';

let browser, page;

async function open(route) {
  await page.goto(`${browser.url}#${route}`);
  await page.waitForFunction((r) => window.mrvolLearn?.route() === r && window.mrvolLearn.ready(), route, { timeout: 30_000 });
  await settle(page);
}

const state = () => page.evaluate(() => window.mrvolLearn.state());

async function shot(name) {
  await settle(page);
  await page.screenshot({ path: join(RESULTS_DIR, `learn-${name}.png`) });
}

/** Fraction of sampled canvas pixels that differ from the background colour. */
async function inkFraction() {
  await settle(page);
  return page.evaluate(() => {
    const canvas = document.querySelector('.learn-stage canvas');
    const probe = document.createElement('canvas');
    probe.width = 200;
    probe.height = 120;
    const g = probe.getContext('2d');
    g.drawImage(canvas, 0, 0, 200, 120);
    const data = g.getImageData(0, 0, 200, 120).data;
    let ink = 0;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - 0xf4) + Math.abs(data[i + 1] - 0xf5) + Math.abs(data[i + 2] - 0xf7) > 24) ink++;
    return ink / (data.length / 4);
  });
}

describe('teaching views', { timeout: 120_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ goto: false })));
  after(() => browser?.close());

  test('#learn/levels: every level of the spiky ball, details, three schemes side by side', async () => {
    await open('learn/levels');
    let s = await state();
    assert.equal(s.model, 'spiky-ball');
    assert.equal(s.levels, 3);
    assert.ok(await inkFraction() > 0.05, 'the canvas shows the mesh');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /section 2/);
    // Level 3 is the fine mesh: its approximation keeps every detail and the fine volume.
    await page.fill('[data-testid="levels-level"]', '3');
    await page.dispatchEvent('[data-testid="levels-level"]', 'input');
    s = await state();
    assert.equal(s.level, 3);
    assert.ok(Math.abs(s.volumes.loop[3] - s.fineVolume) < 1e-9 * s.fineVolume);
    // Zeroing the spikes' details leaves the round ball: the level-0 approximation is near the unit sphere's volume.
    assert.ok(Math.abs(s.volumes.loop[0] - 4 * Math.PI / 3) < 0.05, `volume at level 0 ${s.volumes.loop[0]}`);
    await page.click('[data-testid="bank-1"]');
    assert.equal((await state()).level, 1);
    assert.equal(await page.textContent('[data-testid="levels-cage-size"]'), '42');
    await shot('levels');
    await page.selectOption('[data-testid="levels-details"]', 'colour');
    await page.check('[data-testid="levels-compare"]');
    s = await state();
    assert.deepEqual(s.panels, ['loop: level 1', 'butterfly: level 1', 'linear: level 1']);
    assert.equal(s.volumes.butterfly.length, 4);
    assert.ok(await inkFraction() > 0.02);
    await shot('levels-compare');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/ball: the squashed ball loses volume without preservation and keeps it with', async () => {
    await open('demo/ball');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 6.*section 5/s);
    await page.click('[data-testid="demo-play"]'); // pause: the test drives the clock
    const before = await state();
    await page.evaluate(() => window.mrvolLearn.act('run', 150, 1 / 60)); // 2.5 s: the first impact
    const s = await state();
    assert.ok(s.steps >= before.steps + 150, `steps ${s.steps}`);
    assert.equal(s.failures, 0);
    assert.ok(s.minRatio < 0.9, `the free volume drops at the impact (min ratio ${s.minRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved volume within 1e-5 (worst ${s.maxError})`);
    assert.ok(await inkFraction() > 0.05);
    const chartInk = await page.evaluate(() => document.querySelector('[data-testid="volume-chart"]').width > 100);
    assert.ok(chartInk);
    await page.evaluate(() => window.mrvolLearn.act('runUntilSquashed', 0.25, 1 / 120));
    const squashed = await state();
    assert.ok(squashed.free < 0.8 * squashed.reference, 'stopped during an impact');
    assert.ok(Math.abs(squashed.preserved - squashed.reference) <= 1.01e-5 * squashed.reference);
    await shot('ball');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/skinning: a skeleton drives the cage; linear blend skinning loses volume, the correction keeps it', async () => {
    await open('demo/skinning');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 8.*section 5/s);
    await page.click('[data-testid="demo-play"]');
    let s = await state();
    assert.equal(s.vertices, 674);
    assert.equal(s.cageSize, 44);
    await page.evaluate(() => window.mrvolLearn.act('run', 75, 1 / 30)); // 2.5 s of animation
    s = await state();
    assert.equal(s.failures, 0);
    assert.ok(s.minRatio < 0.97, `skinning alone changes the volume (min ratio ${s.minRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved within 1e-5 (worst ${s.maxError})`);
    assert.ok(await inkFraction() > 0.03);
    await shot('skinning');
    assert.deepEqual(page.problems, []);
  });

  test('#learn/tensor: theta^l for l = n..0 read from the live tensors, blocks by depth and coarse count', async () => {
    await open('learn/tensor');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 4.*section 3\.1/s);
    assert.equal(await page.getAttribute('[data-testid="tensor-outwards-link"]', 'href'), '#learn/lifting', 'Figure 5 is played there');
    let s = await state();
    assert.equal(s.n, 2);
    assert.equal(s.N, 66);
    assert.deepEqual(s.levels.map((x) => x.level), [2, 1, 0]);
    for (const level of s.levels) {
      assert.equal(level.stored, level.nnzStored, 'every stored entry is listed by theta.entries()');
      assert.equal(6 * level.stored, level.nnzFull, 'alternating: six orderings per stored entry');
    }
    assert.deepEqual(s.levels[0].classCounts.slice(0, 3), [0, 0, 0], 'at the fine level every index is coarse');
    assert.ok(s.levels[2].classCounts[0] > 0 && s.levels[2].stored > s.levels[0].stored, 'theta^0 fills in, with detail-only entries');
    assert.equal(await page.locator('canvas[data-testid^="tensor-slab-"]').count(), 9);
    await shot('tensor');
    await page.selectOption('[data-testid="tensor-scheme"]', 'linear');
    await page.waitForFunction(() => window.mrvolLearn.state()?.scheme === 'linear');
    s = await state();
    assert.equal(6 * s.levels[2].stored, s.levels[2].nnzFull);
    assert.deepEqual(page.problems, []);
  });

  test('#demo/bunny: pulling two ears grows the free mesh, the preserved one keeps its volume; level e changes', async () => {
    await open('demo/bunny');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 7.*section 5/s);
    await page.click('[data-testid="demo-play"]');
    let s = await state();
    assert.equal(s.ears.length, 2);
    await page.evaluate(() => window.mrvolLearn.act('run', 60, 1 / 30)); // 2 s: pulled out
    s = await state();
    assert.equal(s.failures, 0);
    assert.ok(s.maxRatio > 1.01, `the ears add volume (max ratio ${s.maxRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved within 1e-5 (worst ${s.maxError})`);
    await shot('bunny');
    await page.selectOption('[data-testid="bunny-level"]', '1');
    s = await state();
    assert.equal(s.level, 1);
    assert.ok(await inkFraction() > 0.03);
    assert.deepEqual(page.problems, []);
  });

  test('#learn/levels and #learn/lifting show the editor\'s model, with its edits, from the stored session', async () => {
    // The session the editor keeps (web/session.js): an opened file and its edited positions.
    const text = readFileSync(join(root, 'public/models/blob.obj'), 'utf8');
    const positions = Float64Array.from(text.split('\n').filter((l) => l.startsWith('v ')).flatMap((l) => l.split(/\s+/).slice(1, 4).map((x) => 1.1 * Number(x))));
    const session = { version: 1, model: { kind: 'file', name: 'my-blob.obj', text }, settings: {}, fingerprint: null,
                      positions: Buffer.from(positions.buffer).toString('base64'), reference: null, saved: Date.now() };
    await page.goto(`${browser.url}#learn/tensor`);
    await page.evaluate((json) => localStorage.setItem('mrvol.session.v1', json), JSON.stringify(session));
    try {
      await open('learn/levels');
      const s = await state();
      assert.equal(s.model, 'my-blob.obj');
      assert.equal(s.levels, 4);
      assert.match(await page.textContent('[data-testid="levels-model"]'), /editor: my-blob\.obj/);
      assert.ok(Math.abs(s.fineVolume - 1.331 * 5.7481791) < 1e-5 * s.fineVolume, `the edited (scaled) blob: ${s.fineVolume}`);
      // The samples stay a choice away.
      await page.selectOption('[data-testid="levels-model"]', 'spiky-ball');
      await page.waitForFunction(() => window.mrvolLearn.state()?.model === 'spiky-ball');
      // The lifting view plays the editor's model too.
      await open('learn/lifting');
      const lifting = await state();
      assert.equal(lifting.model, 'my-blob.obj');
      assert.deepEqual(lifting.phases, ['U', 'P_o', 'N', 'P_e']);
      assert.deepEqual(page.problems, []);
    } finally {
      await page.evaluate(() => localStorage.removeItem('mrvol.session.v1'));
      await open('learn/tensor');  // leaves the views that showed the editor's model
    }
  });

  test('#learn/lifting: one level played phase by phase around a vertex, synthesis and analysis as its reverse', async () => {
    await open('learn/lifting');
    const text = await page.textContent('[data-testid="learn-text"]');
    assert.match(text, /Figure 3.*section 2/s);
    assert.doesNotMatch(text, /does not offer|not have yet/);
    let s = await state();
    assert.equal(s.level, 1);
    assert.equal(s.vertex, 0);
    assert.equal(s.odd, false);
    assert.deepEqual(s.phases, ['U', 'P_o', 'N', 'P_e']);
    assert.equal(s.phase, 0);
    assert.equal(s.written, 0);
    assert.equal(s.touched, 1, 'before the first phase the unit coefficient is on the picked vertex only');
    // Step through the four phases of the even base vertex 0 (valence 5).
    const phases = [];
    for (let k = 1; k <= 4; k++) {
      await page.click('[data-testid="lifting-step"]');
      s = await state();
      assert.equal(s.phase, k);
      assert.equal(s.phaseName, ['U', 'P_o', 'N', 'P_e'][k - 1]);
      assert.equal(await page.getAttribute('[data-testid="lifting-written"]', 'data-value'), String(s.written), 'the readout says it');
      for (const w of s.weights) assert.ok(s.writtenVertices.includes(w.target), 'every weight belongs to a written vertex');
      phases.push(s);
    }
    const [U, Po, Nm, Pe] = phases;
    assert.deepEqual(U.writtenVertices, [0], 'U writes the even vertex from its odd neighbours');
    assert.ok(U.read >= 5 && U.weights.every((w) => w.source !== null));
    assert.equal(U.touched, 1, 'U reads only details: the even unit coefficient is not spread');
    assert.equal(Po.written, 5, 'P_o writes the five odd neighbours');
    assert.ok(Po.readVertices.includes(0) && Po.read >= 3);
    assert.ok(Po.touched > 1, 'P_o spreads the coefficient to the odd ring');
    const eta = 3 / 8 + Math.cos(2 * Math.PI / 5) / 4;
    assert.deepEqual(Nm.writtenVertices, [0]);
    assert.equal(Nm.read, 0, 'N scales, it reads nothing');
    assert.ok(Math.abs(Nm.weights[0].weight - 8 / 5 * eta * eta) < 1e-12, `N's factor ${Nm.weights[0].weight}`);
    assert.equal(Pe.written, 1);
    assert.equal(Pe.read, 5, 'P_e reads the odd neighbours');
    assert.ok(Pe.weights.every((w) => Math.abs(w.weight - (1 - 8 / 5 * eta * eta) / 5) < 1e-12), 'mu each');
    assert.ok(new Set(phases.map((p) => `${p.written}/${p.read}`)).size >= 3, 'the counts change from phase to phase');
    for (let k = 1; k < 4; k++) assert.notDeepEqual(phases[k].weights, phases[k - 1].weights);
    assert.ok(Pe.reached.some((r) => r.vertex === 0) && Pe.touched > Po.touched, 'P_e spreads it to the even neighbours');
    await page.click('[data-testid="lifting-step"]'); // past the last phase: nothing
    assert.equal((await state()).phase, 4);
    await shot('lifting');
    // Analysis: the inverse phases in reverse order, with the weights negated and the factor inverted.
    await page.selectOption('[data-testid="lifting-mode"]', 'analysis');
    s = await state();
    assert.equal(s.mode, 'analysis');
    assert.equal(s.phase, 0);
    assert.deepEqual(s.phases, ['P_e⁻¹', 'N⁻¹', 'P_o⁻¹', 'U⁻¹']);
    await page.click('[data-testid="lifting-step"]');
    s = await state();
    assert.equal(s.phaseName, 'P_e⁻¹');
    assert.deepEqual(s.weights.map((w) => ({ ...w, weight: -w.weight })), Pe.weights);
    await page.click('[data-testid="lifting-step"]');
    s = await state();
    assert.ok(Math.abs(s.weights[0].weight * Nm.weights[0].weight - 1) < 1e-12, 'N⁻¹ divides by the factor');
    // Transposed (Figure 5): the same masks outwards, in reverse order; P_e at the picked even vertex
    // now pushes it to its odd neighbours with the same weights.
    await page.evaluate(() => window.mrvolLearn.act('setPhase', 4));
    const analysisEnd = await state();
    await page.selectOption('[data-testid="lifting-mode"]', 'transposed');
    s = await state();
    assert.deepEqual(s.phases, ['P_eᵀ', 'Nᵀ', 'P_oᵀ', 'Uᵀ']);
    await page.click('[data-testid="lifting-step"]');
    s = await state();
    assert.deepEqual(s.readVertices, [0], 'P_eᵀ: the picked vertex pushes');
    assert.deepEqual([...s.writtenVertices].sort((a, b) => a - b), [...Pe.readVertices].sort((a, b) => a - b), 'to what P_e reads');
    assert.deepEqual(s.weights.map((w) => w.weight), Pe.weights.map((w) => w.weight));
    assert.ok(s.touched > 1, 'the unit covector spreads outwards');
    await page.evaluate(() => window.mrvolLearn.act('setPhase', 4));
    s = await state();
    // The adjoint of synthesis: the covector at 0 after all phases is row 0 of [S C]: its value at 0
    // is what the unit coefficient at 0 synthesizes to at 0.
    const atZero = (st) => st.reached.find((r) => r.vertex === 0)?.value;
    assert.ok(Math.abs(atZero(s) - atZero(Pe)) < 1e-12, `row 0 of [S C] at 0: ${atZero(s)} vs ${atZero(Pe)}`);
    assert.notDeepEqual(s.reached, analysisEnd.reached, 'transposed is not the inverse');
    await shot('lifting-transposed');
    await page.selectOption('[data-testid="lifting-mode"]', 'analysis');
    await page.click('[data-testid="lifting-reset"]');
    assert.equal((await state()).phase, 0);
    // Play runs the phases by itself.
    await page.click('[data-testid="lifting-play"]');
    await page.waitForFunction(() => window.mrvolLearn.state().phase === 4 && !window.mrvolLearn.state().playing, null, { timeout: 15_000 });
    s = await state();
    assert.ok(s.touched > 1, `analysis of c^1_0 reaches several coefficients (${s.touched})`);
    // An odd vertex, by clicking it on the canvas.
    await page.selectOption('[data-testid="lifting-mode"]', 'synthesis');
    await page.click('[data-testid="lifting-next-odd"]');
    s = await state();
    assert.equal(s.odd, true);
    const oddVertex = s.vertex;
    await page.click('[data-testid="lifting-next-even"]');
    assert.equal((await state()).odd, false);
    await page.evaluate((v) => window.mrvolLearn.act('pick', v), oddVertex); // the camera faces it
    await page.evaluate(() => window.mrvolLearn.act('pick', 0, false)); // another one picked, the camera stays
    assert.equal((await state()).vertex, 0);
    const [x, y] = await page.evaluate((v) => window.mrvolLearn.act('screenOf', v), oddVertex);
    await settle(page);
    await page.mouse.click(x, y);
    s = await state();
    assert.equal(s.vertex, oddVertex, 'a click picks the vertex under the pointer');
    assert.equal(s.phase, 0, 'a new vertex starts before the first phase');
    // A click where a vertex lies behind the surface (none in front within 16 px) picks no hidden vertex.
    const all = await page.evaluate(() => window.mrvolLearn.act('screenOfAll'));
    const depths = all.map(([, , , z]) => z).sort((a, b) => a - b), median = depths[depths.length >> 1];
    const hidden = all.filter(([, x, y, z]) => z > median && !all.some(([, x2, y2, z2]) => z2 < z && Math.hypot(x2 - x, y2 - y) < 16))
      .sort((a, b) => b[3] - a[3]);
    assert.ok(hidden.length > 0, `a vertex on the far side (of ${all.length})`);
    const [back, bx, by] = hidden[0];
    await page.mouse.click(bx, by);
    assert.notEqual((await state()).vertex, back, `vertex ${back}, behind the surface, is not picked through it`);
    // A detail: U writes the two ends of its edge, reading the odd vertex among others.
    await page.click('[data-testid="lifting-step"]');
    s = await state();
    assert.equal(s.written, 2, `U writes the ends of the odd vertex's edge: ${JSON.stringify(s.writtenVertices)}`);
    assert.ok(s.readVertices.includes(oddVertex));
    assert.ok(s.touched > 1, 'the detail spreads to the ends in U');
    await page.evaluate(() => window.mrvolLearn.act('setPhase', 4));
    s = await state();
    assert.ok(s.reached.some((r) => r.vertex === oddVertex), 'the odd vertex itself after P_o');
    assert.ok(s.touched > 3);
    // Butterfly: two phases.
    await page.selectOption('[data-testid="lifting-scheme"]', 'butterfly');
    s = await state();
    assert.deepEqual(s.phases, ['U', 'P']);
    assert.deepEqual(page.problems, []);
  });

  test('#learn/lifting speaks of the scheme it plays: title, text, phase glossary, phase readout and buttons', async () => {
    // What names each scheme, and what only another scheme's text says (its phases and masks).
    const NAME = { loop: /Loop/, butterfly: /Butterfly/, linear: /linear/, 'catmull-clark': /Catmull-Clark/ };
    const ONLY = {
      loop: [/8\/5/, /\bPo\b/, /predict odd/, /Figure 3/],
      butterfly: [/Butterfly/, /−1\/16/],
      linear: [/Lounsbery/, /midpoint/],
      'catmull-clark': [/face point/, /edge point/, /Pf\b/, /vertex rule/],
    };
    const glossaryKey = (name) => name.replace(/^([NP])_3\d+$/, '$1_3k').replace('_', '');
    await open('learn/lifting');
    for (const [model, scheme] of [['spiky-ball', 'loop'], ['spiky-ball', 'butterfly'], ['spiky-ball', 'linear'], ['quad-critter', 'catmull-clark']]) {
      if ((await state()).model !== model) {
        await page.selectOption('[data-testid="lifting-model"]', model);
        await page.waitForFunction((m) => window.mrvolLearn.state()?.model === m, model);
      }
      if ((await state()).scheme !== scheme) await page.selectOption('[data-testid="lifting-scheme"]', scheme);
      const s = await state();
      assert.equal(s.scheme, scheme);
      const title = await page.textContent('[data-testid="learn-text"] h2');
      assert.match(title, NAME[scheme], `${scheme}: the title names it`);
      const text = await page.textContent('[data-testid="learn-text"]');
      for (const [other, marks] of Object.entries(ONLY))
        if (other !== scheme)
          for (const mark of marks) assert.doesNotMatch(text, mark, `${scheme}: the text says nothing of ${other} (${mark})`);
      // One glossary line per phase played (the valence-3 layers share one), in order.
      const terms = await page.locator('[data-testid="lifting-glossary"] dt').allTextContents();
      assert.deepEqual(terms, [...new Set(s.phases.map(glossaryKey))], `${scheme}: the glossary lists its phases`);
      const lines = await page.locator('[data-testid="lifting-glossary"] dd').allTextContents();
      // The phase readout says what the glossary says, phase by phase.
      for (let k = 1; k <= s.phaseCount; k++) {
        await page.evaluate((p) => window.mrvolLearn.act('setPhase', p), k);
        const line = lines[terms.indexOf(glossaryKey(s.phases[k - 1]))];
        assert.ok((await page.textContent('[data-testid="lifting-phase"]')).endsWith(line), `${scheme}: phase ${k} reads "${line}"`);
      }
      const buttons = [await page.textContent('[data-testid="lifting-next-even"]'), await page.textContent('[data-testid="lifting-next-odd"]')];
      assert.deepEqual(buttons, scheme === 'catmull-clark' ? ['next old vertex', 'next new point'] : ['next even', 'next odd']);
      await shot(`lifting-words-${scheme}`);
    }
    assert.deepEqual(page.problems, []);
  });

  test('navigation: the bar switches views, a learn URL in the editor opens it, the editor link goes back', async () => {
    await open('learn/tensor');
    await page.click('[data-testid="nav-demo-skinning"]');
    await page.waitForFunction(() => window.mrvolLearn.route() === 'demo/skinning' && window.mrvolLearn.ready());
    assert.equal(await page.locator('.learn-stage canvas').count(), 1, 'the previous view is gone');
    await page.goto(`${browser.url}#learn/nothing`);
    await page.waitForFunction(() => window.mrvolLearn?.ready());
    assert.match(await page.textContent('[data-testid="learn-text"]'), /no view 'learn\/nothing'/);
    await page.click('.learn-editor-link');
    await page.waitForFunction(() => window.mrvolDebug?.ready() === true, null, { timeout: 30_000 });
    assert.equal(await page.isVisible('[data-testid="readouts"]'), true, 'the editor is back');
    await page.evaluate(() => { location.hash = '#learn/levels'; });
    await page.waitForFunction(() => window.mrvolLearn?.route() === 'learn/levels' && window.mrvolLearn.ready(), null, { timeout: 30_000 });
    assert.equal(await page.isVisible('[data-testid="readouts"]'), false, 'the editor is hidden');
    assert.deepEqual(page.problems, []);
  });
});
