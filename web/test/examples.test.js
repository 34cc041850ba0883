// `npm run examples` (examples/serve.js) serves a page that loads in
// headless Chromium without errors and draws the map and the moving sprites
// depth-culled, and as plain sprites when the checkbox says so.
// Skips, saying why, without chromium, web/node_modules, the wasm or the CLI.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

import { browserMissing, launch } from './support/browser.js';

const webDir = join(dirname(fileURLToPath(import.meta.url)), '..');
const cli = process.env.DEPTHCULL_CLI ?? join(webDir, '..', 'build', 'depthcull');
const missing = (await browserMissing(webDir)) ?? (existsSync(join(webDir, 'dist/depthcull.wasm')) ? null : 'no web/dist/depthcull.wasm') ?? (existsSync(cli) ? null : `no CLI at ${cli}`);
if (missing) console.log(`# example page test skipped: ${missing}`);

let child, url, browser;

before(async () => {
  if (missing) return;
  child = spawn(process.execPath, [join(webDir, 'examples/serve.js')], { env: { ...process.env, PORT: '0' }, stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  child.stderr.on('data', (d) => (err += d));
  url = await new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/open (http:\/\/\S+)/);
      if (m) resolve(m[1]);
    });
    child.on('exit', (code) => reject(new Error(`examples/serve.js exited ${code}: ${err.trim()}`)));
  });
  browser = await launch();
});

after(async () => {
  await browser?.close();
  child?.kill();
});

test('the example page draws the map and the sprites, culled and plain', { skip: missing ?? false }, async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => m.type() === 'error' && !/favicon/.test(m.location()?.url ?? '') && errors.push(`${m.text()} (${m.location()?.url})`));
  await page.goto(url);
  await page.waitForFunction('window.depthcullExampleReady === true', { timeout: 60000 });
  await page.waitForFunction(() => /fps/.test(document.getElementById('stats').textContent), { timeout: 30000 });
  const culled = await page.$eval('#stats', (e) => e.textContent);
  assert.match(culled, /^map: [1-9]\d* draws, \d+ triangles; sprites: [1-9]\d* draws, [1-9]\d*\/60 in the opaque pass/);
  await page.click('#culled');
  await page.waitForFunction(() => /^plain Pixi/.test(document.getElementById('stats').textContent), { timeout: 30000 });
  console.log(`# example: ${culled}`);
  assert.deepEqual(errors, []);
});
