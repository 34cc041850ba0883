#!/usr/bin/env node
// `npm run examples` in web/: imports and optimizes the example's Tiled map
// (examples/meadow-map.tmx, or MAP.tmx given) with the native CLI, then
// serves the checkout on http://127.0.0.1:PORT (8080, or $PORT) and prints
// the page's address. Ctrl-C stops it.
//   node examples/serve.js [MAP.tmx]
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, relative, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createServer } from 'node:http';

const webDir = join(dirname(fileURLToPath(import.meta.url)), '..');
const root = join(webDir, '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
const map = resolve(process.argv[2] ?? join(webDir, 'examples/meadow-map.tmx'));
const port = Number(process.env.PORT ?? 8080);

function die(message) {
  console.error(`examples: ${message}`);
  process.exit(1);
}
if (!existsSync(cli)) die(`no CLI at ${cli} (cmake -S . -B build && cmake --build build --target depthcull, or set DEPTHCULL_CLI)`);
if (!existsSync(join(webDir, 'dist/depthcull.wasm'))) die('no web/dist/depthcull.wasm (scripts/build-wasm)');
if (!existsSync(join(webDir, 'node_modules/pixi.js'))) die('no web/node_modules/pixi.js (npm install in web/)');
if (!existsSync(map)) die(`${map}: no such file`);
if (!relative(root, map) || relative(root, map).startsWith('..')) die(`${map}: the map must be inside the checkout (its images are served from it)`);

const gen = mkdtempSync(join(tmpdir(), 'dc-examples-'));
process.on('exit', () => rmSync(gen, { recursive: true, force: true }));
process.on('SIGINT', () => process.exit(0));
process.on('SIGTERM', () => process.exit(0));
const run = (...a) => {
  try {
    execFileSync(cli, a, { stdio: ['ignore', 'pipe', 'pipe'] });
  } catch (e) {
    die(String(e.stderr).trim().split('\n').pop());
  }
};
run('import', map, '-o', join(gen, 'map.scene.json'));
run('optimize', join(gen, 'map.scene.json'), '-o', join(gen, 'map.meshes.json'), '--no-timing');
// The page loads images from the checkout: paths as URLs from its root.
const scene = JSON.parse(readFileSync(join(gen, 'map.scene.json'), 'utf8'));
for (const img of scene.images) {
  if (!img.path) continue;
  const rel = relative(root, resolve(gen, img.path));
  if (rel.startsWith('..')) die(`${map}: image ${img.path} is outside the checkout`);
  img.path = `/${rel}`;
}
writeFileSync(join(gen, 'map.scene.json'), JSON.stringify(scene));

const { serve } = await import('../test/support/browser.js');
process.on('uncaughtException', (e) => die(e.code === 'EADDRINUSE' ? `port ${port} is in use (set PORT)` : e.message));
const { origin } = await serve(root, gen, null, port);
console.log(`examples: open ${origin}/web/examples/index.html (serving the checkout on 127.0.0.1 only; Ctrl-C stops)`);
