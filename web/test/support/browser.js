// Headless Chromium for the browser tests and the bench: a local HTTP
// server on 127.0.0.1 serving the repository (the web package, the
// examples) and a folder of generated files under /gen/, and puppeteer-core
// driving Debian's chromium with WebGL 2 on llvmpipe (exact rasterization;
// SwiftShader, the fallback, snaps vertices at 1/16 px).
import { createServer } from 'node:http';
import { existsSync, readFileSync, statSync } from 'node:fs';
import { extname, join, normalize, sep } from 'node:path';

export const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';

const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json', '.png': 'image/png', '.wasm': 'application/wasm', '.bin': 'application/octet-stream' };

// Why the browser tests cannot run here, or null.
export async function browserMissing(webDir) {
  if (!existsSync(chromiumPath)) return `no chromium at ${chromiumPath} (apt-get install chromium)`;
  if (!existsSync(join(webDir, 'node_modules', 'puppeteer-core')) || !existsSync(join(webDir, 'node_modules', 'pixi.js')))
    return 'web/node_modules has no puppeteer-core or pixi.js (npm install --no-package-lock in web/)';
  return null;
}

// Serves `root` at / and `gen` at /gen/ (and `corpus` at /corpus/);
// paths outside them are 404. `port`: 0 for any free one.
export function serve(root, gen, corpus, port = 0) {
  const server = createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    let path = decodeURIComponent(url.pathname);
    let base = root;
    if (path.startsWith('/gen/')) {
      base = gen;
      path = path.slice(4);
    } else if (corpus && path.startsWith('/corpus/')) {
      base = corpus;
      path = path.slice(7);
    }
    const file = normalize(join(base, path));
    if (!(file + sep).startsWith(normalize(base + sep)) || !existsSync(file) || !statSync(file).isFile()) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream', 'cache-control': 'no-store' });
    res.end(readFileSync(file));
  });
  return new Promise((resolve) => server.listen(port, '127.0.0.1', () => resolve({ server, origin: `http://127.0.0.1:${server.address().port}` })));
}

export async function launch() {
  const { default: puppeteer } = await import('puppeteer-core');
  return puppeteer.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--headless=new', '--no-sandbox', '--use-gl=angle', '--use-angle=gl-egl', '--ignore-gpu-blocklist', '--enable-gpu'],
  });
}

export async function openPage(browser, url) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => m.type() === 'error' && !/favicon|404/.test(m.text() + (m.location()?.url ?? '')) && errors.push(m.text()));
  await page.goto(url);
  await page.waitForFunction('window.depthcullReady === true', { timeout: 30000 }).catch((e) => {
    throw new Error(`page did not load: ${errors.join('; ') || e.message}`);
  });
  return { page, errors };
}
