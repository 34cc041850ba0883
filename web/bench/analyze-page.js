// Times the wasm analysis of one atlas page: every frame of a TexturePacker
// JSON (hash or array form) on its page, or the whole image when no JSON is
// given. Prints the rects as `depthcull analyze` inputs too, so the native
// time of the same work is one command away (see web/README.md).
//   node bench/analyze-page.js PAGE.png [ATLAS.json] [--repeat N]
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';

import { loadDepthcull } from '../src/index.js';
import { readPng } from '../test/support/png.js';

const args = process.argv.slice(2);
const repeatAt = args.indexOf('--repeat');
const repeat = repeatAt >= 0 ? Number(args.splice(repeatAt, 2)[1]) : 5;
const [pagePath, atlasPath] = args;
if (!pagePath) {
  console.error('usage: node bench/analyze-page.js PAGE.png [ATLAS.json] [--repeat N]');
  process.exit(2);
}
const page = readPng(pagePath);
let rects = [{ x: 0, y: 0, width: page.width, height: page.height }];
if (atlasPath) {
  const atlas = JSON.parse(readFileSync(atlasPath, 'utf8'));
  const frames = Array.isArray(atlas.frames) ? atlas.frames : Object.values(atlas.frames);
  // A rotated frame lies on the page with its width and height swapped.
  rects = frames.map(({ frame: f, rotated }) => ({ x: f.x, y: f.y, width: rotated ? f.h : f.w, height: rotated ? f.w : f.h }));
}
const depthcull = await loadDepthcull();
const times = [];
for (let r = 0; r < repeat; ++r) {
  const start = performance.now();
  for (const rect of rects) depthcull.analyzeImage(page, { rect, name: pagePath });
  times.push(performance.now() - start);
}
times.sort((a, b) => a - b);
console.log(`${pagePath}: ${page.width}x${page.height}, ${rects.length} rects, wasm analysis ` +
  `${times[times.length >> 1].toFixed(1)} ms (median of ${repeat}; fastest ${times[0].toFixed(1)} ms), Node ${process.version}`);
if (process.env.PRINT_RECTS) console.log(rects.map((r) => `${pagePath}:${r.x},${r.y},${r.width},${r.height}`).join(' '));
