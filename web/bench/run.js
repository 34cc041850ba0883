#!/usr/bin/env node
// `npm run bench` in web/: Table 2 in the browser. Each scene (the bundled
// example and the corpus Tiled maps) is imported and optimized with the
// native CLI, then drawn in headless Chromium by a PixiJS app as plain
// sprites and with a DepthCulledLayer (bench/bench-page.js): draw calls and
// triangles counted on the GL context, ms per frame (median, the frame
// finished by a 1-pixel readPixels), GPU ms where the browser exposes
// EXT_disjoint_timer_query_webgl2. Fragments shaded cannot be counted in
// WebGL 2 (its occlusion queries say only whether any sample passed), so
// that column is the native CLI's (`depthcull bench`: GL_SAMPLES_PASSED on
// the same scene and meshes, overpaint vs optimized) and says so.
// Prints the table and writes it to ../bench/results/browser-pixi.md.
//   node bench/run.js [--frames N] [--sprites N (500; 0: none)] [--out FILE] [--no-write] [SCENE.json|MAP.tmx[@X,Y,W,H] ...]
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { cpus, homedir, tmpdir } from 'node:os';
import { basename, dirname, join, relative, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

import { browserMissing, launch, openPage, serve } from '../test/support/browser.js';

const webDir = join(dirname(fileURLToPath(import.meta.url)), '..');
const root = join(webDir, '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
const corpus = join(homedir(), '.cache/depthcull/corpus/tiled/usr/share/doc/tiled/examples');

function die(message) {
  console.error(`bench: ${message}`);
  process.exit(1);
}

const args = process.argv.slice(2);
let frames = 60, sprites = 500, out = join(root, 'bench/results/browser-pixi.md'), write = true;
const scenes = [];
for (let i = 0; i < args.length; ++i) {
  const a = args[i];
  if (a === '--frames') {
    frames = Number(args[++i]);
    if (!Number.isInteger(frames) || frames < 1 || frames > 100000) die(`--frames: Value ${args[i]} not in range 1 to 100000`);
  } else if (a === '--sprites') {
    sprites = Number(args[++i]);
    if (!Number.isInteger(sprites) || sprites < 0 || sprites > 100000) die(`--sprites: Value ${args[i]} not in range 0 to 100000`);
  } else if (a === '--out') out = resolve(args[++i] ?? die('--out needs a file'));
  else if (a === '--no-write') write = false;
  else if (a.startsWith('-')) die(`unknown option ${a}`);
  else {
    const [file, viewport] = a.split('@');
    if (!existsSync(file)) die(`${file}: no such file`);
    scenes.push({ name: basename(file), file: resolve(file), viewport });
  }
}
if (!scenes.length) {
  scenes.push({ name: 'examples/meadow.json', file: join(root, 'examples/meadow.json') });
  for (const [file, viewport] of [['desert.tmx', '0,0,640,480'], ['rpg/island.tmx', '0,0,640,480'], ['isometric_grass_and_water.tmx', '-400,0,800,600'], ['perspective_walls.tmx', '0,0,640,480'], ['sewers.tmx', '0,0,640,480']])
    if (existsSync(join(corpus, file))) scenes.push({ name: `corpus ${file}`, file: join(corpus, file), viewport });
}
const missing = (await browserMissing(webDir)) ?? (existsSync(cli) ? null : `no CLI at ${cli} (cmake --build build --target depthcull)`);
if (missing) die(missing);

const gen = mkdtempSync(join(tmpdir(), 'dc-bench-'));
const run = (...a) => execFileSync(cli, a, { stdio: ['ignore', 'pipe', 'pipe'], maxBuffer: 1 << 26 }).toString();
const corpusBase = join(homedir(), '.cache/depthcull/corpus');
const { server, origin } = await serve(root, gen, corpusBase);
const browser = await launch();
const rows = [];
let renderer = '', timerQuery = false, userAgent = '', page;
try {
  page = (await openPage(browser, `${origin}/web/bench/bench.html`)).page;
  for (const [k, s] of scenes.entries()) {
    // A Tiled map is imported (cut to its viewport); a scene is used as is.
    let scene = s.file;
    if (!s.file.endsWith('.json')) {
      scene = join(gen, `${k}.imported.scene.json`); // import writes the images' absolute paths
      run('import', s.file, '-o', scene, ...(s.viewport ? ['--viewport', s.viewport] : []));
    }
    {
      const meshes = join(gen, `${k}.meshes.json`);
      run('optimize', scene, '-o', meshes, '--no-timing');
      const noOpaque = join(gen, `${k}.no-opaque.meshes.json`);
      run('optimize', scene, '-o', noOpaque, '--no-timing', '--no-opaque');
      const native = JSON.parse(run('bench', scene, '--frames', '0', '--json', '-q', '--modes', 'overpaint,optimized')).scenes[0];
      const od = Object.fromEntries(native.modes.map((m) => [m.mode, m.overdraw]));
      // The page reads the scene by URL: image paths as served (the checkout at /, the corpus at /corpus/).
      const doc = JSON.parse(readFileSync(scene, 'utf8'));
      for (const img of doc.images) {
        if (!img.path) continue;
        const abs = resolve(dirname(scene), img.path);
        if (!relative(root, abs).startsWith('..')) img.path = `/${relative(root, abs)}`;
        else if (!relative(corpusBase, abs).startsWith('..')) img.path = `/corpus/${relative(corpusBase, abs)}`;
        else die(`${s.file}: image ${img.path} is neither in the checkout nor in ${corpusBase}: the bench page cannot load it`);
      }
      writeFileSync(join(gen, `${k}.scene.json`), JSON.stringify(doc));
      const r = await page.evaluate((a) => window.bench.run(a), { sceneUrl: `${origin}/gen/${k}.scene.json`, meshesUrl: `${origin}/gen/${k}.meshes.json`, noOpaqueUrl: `${origin}/gen/${k}.no-opaque.meshes.json`, frames });
      ({ renderer, timerQuery, userAgent } = r);
      rows.push({ name: s.name, size: `${r.width}x${r.height}`, elements: r.elements, plain: { ...r.results.plain, od: od.overpaint }, noOpaque: { ...r.results.noOpaque, od: null }, layer: { ...r.results.layer, od: od.optimized } });
      console.error(`bench: ${s.name} done`);
    }
  }
  // Moving sprites (not a scene file): plain Pixi against DepthCulledSpriteContainer.
  const art = ['tree', 'rock', 'bush', 'flower', 'ring', 'moons', 'glow', 'shadow'].map((n) => `${origin}/examples/art/${n}.png`);
  if (sprites > 0) {
    const r = await page.evaluate((a) => window.bench.sprites(a), { images: art, count: sprites, frames });
    rows.push({ name: `${sprites} moving sprites (examples/art)`, size: `${r.width}x${r.height}`, elements: r.elements, plain: { ...r.results.plain, od: null }, layer: { ...r.results.layer, od: null }, layerName: 'DepthCulledSpriteContainer' });
    console.error('bench: moving sprites done');
  }
} finally {
  await browser.close();
  server.close();
  rmSync(gen, { recursive: true, force: true });
}

const f2 = (x) => (x == null ? 'n/a' : x.toFixed(2));
const lines = [
  '| Scene | Viewport | Elements | Mode | Draws | Triangles | Fragments shaded / px (native) | ms / frame | GPU ms |',
  '|---|---|---:|---|---:|---:|---:|---:|---:|',
];
for (const r of rows)
  for (const [mode, m] of [['plain Pixi sprites', r.plain], ['layer, no opaque pass', r.noOpaque], [r.layerName ?? 'DepthCulledLayer', r.layer]])
    if (m)
    lines.push(`| ${r.name} | ${r.size} | ${r.elements} | ${mode} | ${m.draws} | ${m.triangles} | ${f2(m.od)} | ${f2(m.ms)} | ${f2(m.gpuMs)} |`);
const text = [
  '# Table 2 in the browser: plain PixiJS sprites against depthcull\'s DepthCulledLayer',
  '',
  `Made by \`cd web && npm run bench\` (web/bench/run.js, ${frames} timed frames per mode after 5 warm-up, median).`,
  `Browser: ${userAgent}`,
  `WebGL renderer: ${renderer}`,
  '',
  ...lines,
  '',
  'Draws and triangles: every draw call made on the GL context in one frame (Pixi\'s batches, or the layer\'s).',
  'The moving sprites row: sprites of examples/art wandering, moved every frame; the container re-assembles its meshes each frame.',
  'Fragments shaded / px: not countable in WebGL 2 (occlusion queries only say whether any sample passed);',
  'this column is the native CLI\'s `depthcull bench` (GL_SAMPLES_PASSED over viewport pixels) on the same',
  'scene, overpaint for plain sprites and optimized for the layer (n/a: not measured natively).',
  '"layer, no opaque pass": the same DepthCulledLayer and shader drawing `optimize --no-opaque` meshes (boundary',
  'polygons back to front, no depth culling): it separates what the shader changes from what culling changes.',
  'Pixi\'s batch shader picks its texture with an if-chain over up to 16 samplers (generateTextureBatchBitGl),',
  'which a software renderer such as llvmpipe runs masked for every fragment; we take that to be why plain',
  'Pixi costs several times the layer here even with one draw (not measured apart).',
  `ms / frame: wall time of app.renderer.render plus a 1-pixel readPixels that waits for the frame. GPU ms: ${timerQuery ? 'EXT_disjoint_timer_query_webgl2 (on a software renderer not a GPU time: read ms / frame)' : 'n/a, this browser has no EXT_disjoint_timer_query_webgl2'}.`,
  `Machine: ${cpus().length} cores, ${cpus()[0]?.model ?? 'unknown CPU'}; timings on a shared machine vary by tens of percent from run to run.`,
  '',
].join('\n');
console.log(text);
if (write) {
  mkdirSync(dirname(out), { recursive: true });
  writeFileSync(out, text);
  console.error(`bench: wrote ${relative(process.cwd(), out)}`);
}
