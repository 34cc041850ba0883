// In headless Chromium: moving Pixi sprites drawn by a plain Container and
// by a DepthCulledSpriteContainer (src/pixi-sprites.js; polygons analysed in
// the page by the wasm core) give the same pixels, frame by frame, but on
// texel edges (test/browser/compare.js). Skips, saying why, without
// chromium, web/node_modules or web/dist/depthcull.wasm.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { copyFileSync, existsSync, mkdtempSync, rmSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

import { browserMissing, launch, openPage, serve } from './support/browser.js';

const webDir = join(dirname(fileURLToPath(import.meta.url)), '..');
const root = join(webDir, '..');
const missing = (await browserMissing(webDir)) ?? (existsSync(join(webDir, 'dist/depthcull.wasm')) ? null : 'no web/dist/depthcull.wasm (scripts/build-wasm)');
if (missing) console.log(`# sprite container tests skipped: ${missing}`);

let gen, server, origin, browser, page, pageErrors;

before(async () => {
  if (missing) return;
  gen = mkdtempSync(join(tmpdir(), 'dc-sprites-'));
  ({ server, origin } = await serve(root, gen));
  browser = await launch();
  ({ page, errors: pageErrors } = await openPage(browser, `${origin}/web/test/browser/sprites.html`));
});

after(async () => {
  await browser?.close();
  server?.close();
  if (gen) rmSync(gen, { recursive: true, force: true });
});

const art = ['tree', 'rock', 'bush', 'flower', 'glow', 'ring', 'moons', 'shadow'];

test('moving sprites: a plain Pixi Container and DepthCulledSpriteContainer draw the same pixels', { skip: missing ?? false }, async () => {
  const images = Object.fromEntries(art.map((n) => [n, `${origin}/examples/art/${n}.png`]));
  for (const seed of [1, 2]) {
    const r = await page.evaluate((a) => window.spritesTest.identity(a), { images, count: 40, frames: 5, seed });
    const s = r.frames[r.frames.length - 1];
    console.log(`# sprites seed ${seed}: 5 frames of ${s.sprites} sprites (${s.opaqueSprites} in the opaque pass), last frame ${s.draws} draws ${s.triangles} triangles; at most ${r.differ} pixels differ, ${r.offEdges} off texel edges (${r.glRenderer})`);
    assert.equal(r.offEdges, 0, r.examples.join('; '));
    assert.ok(s.opaqueSprites > 0 && s.draws > 0);
  }
  assert.deepEqual(pageErrors, []);
});

test('atlas sprites: a plain Container and the layer with the polygons `depthcull atlas` wrote draw the same pixels', { skip: missing ?? false }, async (t) => {
  const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
  if (!existsSync(cli)) return t.skip(`no CLI at ${cli}`);
  // Next to the page image (the atlas names it relatively): written in gen/ with a copy of the page.
  execFileSync(cli, ['atlas', join(root, 'examples/atlas/sheet.json'), '-o', join(gen, 'sheet-polygons.json'), '--no-cache'], { stdio: 'pipe' });
  copyFileSync(join(root, 'examples/atlas/sheet.png'), join(gen, 'sheet.png'));
  const r = await page.evaluate((a) => window.spritesTest.atlas(a), { atlasUrl: `${origin}/gen/sheet-polygons.json` });
  console.log(`# atlas sprites: ${r.frames} frames x 4, polygons of ${r.set} frames, ${r.stats.draws} draws ${r.stats.triangles} triangles (rectangles: ${r.frames * 8}); ${r.differ} bytes differ`);
  assert.ok(r.stats.triangles > r.frames * 8, 'the atlas polygons were not used');
  assert.ok(r.set >= r.frames && r.frames >= 3);
  assert.equal(r.stats.opaqueSprites, 0);
  assert.equal(r.differ, 0);
  assert.deepEqual(pageErrors, []);
});
