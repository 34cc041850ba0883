// The wasm analysis against the native CLI (`depthcull analyze`): the same
// polygons, coordinate for coordinate as IEEE doubles (the CLI writes
// round-trip precision, so its JSON parses back to the very bits), and the
// same stats, on the bundled images with several option sets.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, readdirSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join, relative } from 'node:path';

import { loadDepthcull } from '../src/index.js';
import { readPng } from './support/png.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');

const images = [
  ...readdirSync(join(root, 'examples/art')).filter((f) => f.endsWith('.png')).sort().map((f) => `examples/art/${f}`),
  'examples/atlas/sheet.png',
  'tests/data/atlas/packed/array-0.png',
  'tests/data/tiled/tiles.png',
  'tests/data/tiled/tall.png',
];
// Sub-rectangles too: every cell of a sprite sheet.
const grids = ['examples/atlas/sheet.png:grid=16,16', 'tests/data/tiled/tiles.png:grid=4,4'];

// [CLI flags, the same as analyzeImage options]
const optionSets = [
  [[], {}],
  [['--max-vertices', '4', '--no-split', '--filter', 'linear'], { maxVertices: 4, split: false, filter: 'linear' }],
  [['--opaque', 'paper', '--max-opaque', '8', '--min-coverage', '1', '--min-opaque-area', '1'],
    { opaque: 'paper', maxOpaque: 8, minCoverage: 1, minOpaqueArea: 1 }],
  [['--opaque', 'grow', '--max-vertices', '16', '--max-opaque', '0', '--min-coverage', '0.5'],
    { opaque: 'grow', maxVertices: 16, maxOpaque: 0, minCoverage: 0.5 }],
  [['--filter', 'linear', '--opaque', 'fast', '--min-opaque-area', '16'], { filter: 'linear', minOpaqueArea: 16 }],
];

const depthcull = await loadDepthcull();
const pixels = new Map();
const load = (path) => {
  if (!pixels.has(path)) pixels.set(path, readPng(join(root, path)));
  return pixels.get(path);
};

for (const [flags, options] of optionSets) {
  test(`wasm analysis equals the CLI's: ${flags.join(' ') || 'defaults'}`, { skip: !existsSync(cli) && `no ${cli} (build it, or set DEPTHCULL_CLI)` }, () => {
    const out = execFileSync(cli, ['analyze', '--no-cache', '--no-timing', '-q', '-j', '1', ...flags, ...images, ...grids], {
      cwd: root, encoding: 'utf8', maxBuffer: 64 << 20,
    });
    const expected = JSON.parse(out).images;
    assert.equal(expected.length, images.length + 4 + 9);
    for (const e of expected) {
      const [x, y, width, height] = e.rect;
      const got = depthcull.analyzeImage(load(e.path), { ...options, rect: { x, y, width, height }, name: e.path });
      const where = `${relative(root, join(root, e.path))} rect ${e.rect}`;
      assert.deepStrictEqual(got.boundary, e.boundary, `boundary polygons of ${where}`);
      assert.deepStrictEqual(got.opaque, e.opaque, `opaque polygons of ${where}`);
      const { seconds, excess_area_ratio, boundary_polygons, opaque_polygons, ...stats } = e.stats;
      assert.deepStrictEqual(got.stats, stats, `stats of ${where}`);
      assert.equal(got.stats.nontransparent_texels ? got.stats.boundary_area / got.stats.nontransparent_texels : 0, excess_area_ratio);
      assert.equal(got.boundary.length, boundary_polygons);
      assert.equal(got.opaque.length, opaque_polygons);
    }
  });
}
