// In headless Chromium: PixiJS v8 drawing a scene as plain sprites and as a
// DepthCulledLayer (the meshes `depthcull optimize` wrote) gives the same
// pixels, with other Pixi objects behind and in front of the layer. The
// only pixels allowed to differ are those whose centre lies exactly on a
// texel edge of an element (test/browser/harness.js's compare, as
// render::count_off_texel_edges in C++): there the last bits of the
// interpolated u, v pick the texel on either side.
// Skips, saying why, without chromium or web/node_modules.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { homedir, tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join, relative } from 'node:path';

import { browserMissing, launch, openPage, serve } from './support/browser.js';

const webDir = join(dirname(fileURLToPath(import.meta.url)), '..');
const root = join(webDir, '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
const missing = (await browserMissing(webDir)) ?? (existsSync(cli) ? null : `no CLI at ${cli}`);
if (missing) console.log(`# browser tests skipped: ${missing}`);

// Corpus maps (scripts/fetch-corpus), when present: imported, cut to a
// camera, optimized. Maps whose scenes need what plain Pixi sprites cannot
// show (atlas frames) are left out.
const corpus = join(homedir(), '.cache/depthcull/corpus/tiled/usr/share/doc/tiled/examples');
const corpusMaps = [
  ['desert', 'desert.tmx', '0,0,640,480'],
  ['island', 'rpg/island.tmx', '0,0,640,480'],
  ['isometric', 'isometric_grass_and_water.tmx', '-400,0,800,600'],
].filter(([, file]) => existsSync(join(corpus, file)));

let gen, server, origin, browser, page, pageErrors;

before(async () => {
  if (missing) return;
  gen = mkdtempSync(join(tmpdir(), 'dc-browser-'));
  ({ server, origin } = await serve(root, gen, corpus));
  browser = await launch();
  ({ page, errors: pageErrors } = await openPage(browser, `${origin}/web/test/browser/page.html`));
});

after(async () => {
  await browser?.close();
  server?.close();
  if (gen) rmSync(gen, { recursive: true, force: true });
});

function optimize(scene, name, extra = []) {
  const out = join(gen, `${name}.meshes.json`);
  execFileSync(cli, ['optimize', scene, '-o', out, '--no-timing', ...extra], { stdio: 'pipe' });
  return out;
}

// URL of a file under the repository or the generated folder.
function urlOf(file) {
  const rel = relative(gen, file);
  return rel.startsWith('..') ? `${origin}/${relative(root, file)}` : `${origin}/gen/${rel}`;
}

async function identity(label, scene, meshes) {
  const r = await page.evaluate((a) => window.depthcullTest.identity(a), { sceneUrl: urlOf(scene), meshesUrl: urlOf(meshes), frames: 2 });
  console.log(`# ${label}: ${r.width}x${r.height}, ${r.elements} elements, layer ${r.stats.draws} draws ${r.stats.triangles} triangles; ${r.differ} pixels differ, ${r.offEdges} off texel edges (${r.glRenderer})`);
  assert.equal(r.offEdges, 0, `${label}: ${r.offEdges} pixels differ off texel edges: ${r.examples.join('; ')}`);
  assert.ok(r.stats.draws > 0);
  assert.deepEqual(pageErrors, []);
}

test('WebGL 2 runs on llvmpipe or SwiftShader', { skip: missing ?? false }, async () => {
  const renderer = await page.evaluate(() => window.depthcullTest.rendererString());
  assert.ok(renderer, 'no WebGL 2 context');
  console.log(`# WebGL renderer: ${renderer}`);
});

// Pixel (542, 69) differs (its centre is 3.0e-5 texels from a texel edge of
// a turned "moons" element, within float32 position rounding: harness.js's
// onTexelEdge).
test('meadow: Pixi sprites and DepthCulledLayer draw the same pixels', { skip: missing ?? false }, async () => {
  const scene = join(root, 'examples/meadow.json');
  await identity('meadow', scene, optimize(scene, 'meadow'));
});

// Issue 25: with --target llvmpipe the desert's ground of opaque tiles is
// drawn without a depth buffer (the meshes' depth_test false: the opaque
// pass back to front, no depth test); the island's plan is whichever the
// cost model predicts faster.
const targeted = new Map([['desert', true], ['island', false]]);
for (const [name, file, viewport] of corpusMaps) {
  for (const target of targeted.has(name) ? [false, true] : [false]) {
    const depthless = target && targeted.get(name);
    const label = target ? `${name} --target llvmpipe${depthless ? ' (no depth buffer)' : ''}` : name;
    test(`corpus ${label}: Pixi sprites and DepthCulledLayer draw the same pixels`, { skip: missing ?? false }, async () => {
      const scene = join(gen, `${name}.scene.json`);
      // Written next to the map's images: the scene's paths are relative to it.
      execFileSync(cli, ['import', join(corpus, file), '-o', scene, '--viewport', viewport], { stdio: 'pipe' });
      const meshes = optimize(scene, target ? `${name}-llvmpipe` : name, target ? ['--target', 'llvmpipe'] : []);
      if (depthless) assert.equal(JSON.parse(readFileSync(meshes, 'utf8')).depth_test, false, 'drawn without a depth buffer');
      // The page's copy names the images by URL.
      const doc = JSON.parse(readFileSync(scene, 'utf8'));
      for (const img of doc.images) if (img.path) img.path = `/corpus/${relative(corpus, img.path.startsWith('/') ? img.path : join(dirname(join(corpus, file)), img.path))}`;
      const pageScene = join(gen, `${name}.page.json`);
      writeFileSync(pageScene, JSON.stringify(doc));
      await identity(label, pageScene, meshes);
    });
  }
}

// Moving sprites (FrameAssembler in the wasm, DepthCulledLayer.movingSprites)
// on top of each scene, 60 frames, each compared with plain Pixi sprites.
async function identityMoving(label, scene, meshes, atElement, styled = false) {
  const r = await page.evaluate((a) => window.depthcullTest.identityMoving(a), { sceneUrl: urlOf(scene), meshesUrl: meshes && urlOf(meshes), frames: 60, count: 24, atElement, styled });
  console.log(`# ${label} + ${styled ? 'tinted, translucent and additive ' : ''}moving sprites${atElement === undefined ? '' : ` at an insertion point before element ${atElement}`}: ${r.frames} frames of ${r.sprites} sprites (${r.pictures} pictures), layer up to ${r.stats.draws} draws ${r.stats.triangles} triangles; at most ${r.differ} pixels differ, ${r.offEdges} off texel edges`);
  assert.equal(r.offEdges, 0, `${label}: ${r.offEdges} pixels differ off texel edges: ${r.examples.join('; ')}`);
  assert.deepEqual(pageErrors, []);
}

test('meadow: moving sprites for 60 frames, Pixi sprites and DepthCulledLayer draw the same pixels', { skip: missing ?? false }, async () => {
  const scene = join(root, 'examples/meadow.json');
  const meshes = join(gen, 'meadow.meshes.json');
  if (!existsSync(meshes)) optimize(scene, 'meadow');
  await identityMoving('meadow', scene, meshes);
});

// The sprites between the layers: meshes reconstructed in the wasm with an
// insertion point before element 230 of 459 (static elements before it
// behind the sprites, those after it in front).
test('meadow: moving sprites at an insertion point for 60 frames (wasm reconstruction), Pixi sprites and DepthCulledLayer draw the same pixels', { skip: missing ?? false }, async () => {
  await identityMoving('meadow', join(root, 'examples/meadow.json'), null, 230);
});

// A corpus map's scene JSON as `depthcull import` wrote it (the island:
// animated tiles, an object layer) reconstructed in the browser's wasm
// with the sprites at its object layer's insertion point.
test('corpus island: moving sprites at its object layer for 60 frames (wasm reconstruction of the scene JSON in the browser), Pixi sprites and DepthCulledLayer draw the same pixels', { skip: missing ?? (!corpusMaps.some(([n]) => n === 'island') && 'no corpus island') }, async () => {
  const scene = join(gen, 'island.page.json');
  if (!existsSync(scene)) return assert.fail(`island: the static test above makes ${scene}`);
  const doc = JSON.parse(readFileSync(scene, 'utf8'));
  assert.ok(doc.animations?.length > 0 && doc.insertion_points?.length > 0, 'island has animated tiles and an object layer');
  await identityMoving('island', scene, null, doc.insertion_points[0], true);
});

// Tinted, translucent and additive sprites (tints and alphas that are not
// exact bytes): Pixi quantises a sprite's tint and alpha to 8 bits, so the
// layer must feed the frame's colours to its shader as the same bytes.
test('meadow: tinted, translucent and additive moving sprites at an insertion point for 60 frames, Pixi sprites and DepthCulledLayer draw the same pixels', { skip: missing ?? false }, async () => {
  await identityMoving('meadow', join(root, 'examples/meadow.json'), null, 230, true);
});

for (const [name, file, viewport] of corpusMaps) {
  test(`corpus ${name}: moving sprites for 60 frames, Pixi sprites and DepthCulledLayer draw the same pixels`, { skip: missing ?? false }, async () => {
    const scene = join(gen, `${name}.page.json`);
    const meshes = join(gen, `${name}.meshes.json`);
    if (!existsSync(scene) || !existsSync(meshes)) return assert.fail(`${name}: the static test above makes ${scene}`);
    void viewport;
    void file;
    await identityMoving(name, scene, meshes);
  });
}

// The figure issue 24 asks for: the time to analyse an atlas page in the
// browser (a packed corpus page, scripts/fetch-corpus), and the .wasm size.
const atlasDir = join(homedir(), '.cache/depthcull/corpus/packed-atlases');
test('analysing an atlas page in the browser: time and .wasm size', { skip: missing ?? (!existsSync(join(atlasDir, 'hash-0.json')) && 'no packed-atlases corpus') }, async () => {
  for (const f of ['hash-0.png', 'hash-0.json']) writeFileSync(join(gen, f), readFileSync(join(atlasDir, f)));
  const r = await page.evaluate((a) => window.depthcullTest.analyzeAtlas(a), { pngUrl: `${origin}/gen/hash-0.png`, jsonUrl: `${origin}/gen/hash-0.json` });
  console.log(`# atlas page hash-0.png ${r.width}x${r.height}: ${r.frames} frames analysed in ${r.ms.toFixed(1)} ms (median of 5; whole page as one image ${r.wholeMs.toFixed(1)} ms); depthcull.wasm ${r.wasmBytes} bytes, loaded in ${r.loadMs.toFixed(0)} ms`);
  assert.equal(r.frames, 18);
  assert.ok(r.vertices > 0);
});

test('MeshRenderer restores every GL state it changes', { skip: missing ?? false }, async () => {
  const scene = join(root, 'examples/meadow.json');
  const meshes = join(gen, 'meadow.meshes.json');
  if (!existsSync(meshes)) optimize(scene, 'meadow');
  const r = await page.evaluate((a) => window.depthcullTest.stateRestored(a), { meshesUrl: urlOf(meshes) });
  assert.deepEqual(r.changed, []);
  assert.equal(r.error, 0);
  assert.ok(r.stats.draws > 0 && r.stats.triangles > 0);
});

test('a bad meshes file in the browser: one line naming the file and the place', { skip: missing ?? false }, async () => {
  const m = await page.evaluate(() => window.depthcullTest.meshesError('{"viewport": {"x": 0, "y": 0, "width": 4, "height": 4}, "depth_test": "yes"}'));
  assert.equal(m, 'DepthcullError: bad.meshes.json: depth_test: must be true or false');
});
