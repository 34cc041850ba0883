// Reconstruction and --target in the wasm (Depthcull.reconstructScene):
// the bundled example's meshes equal, float for float and index for index,
// what `depthcull optimize` writes under the same options, --target
// included; bad scenes are one-line errors.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

import { DepthcullError, loadDepthcull } from '../src/index.js';
import { parseMeshesJson } from '../src/meshes.js';
import { readPng } from './support/png.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
const depthcull = await loadDepthcull();

const scenePath = join(root, 'examples/meadow.json');
const doc = JSON.parse(readFileSync(scenePath, 'utf8'));
const ids = doc.images.map((i) => i.id);
const scene = {
  viewport: doc.viewport,
  images: doc.images.map((i) => ({ id: i.id, ...readPng(join(dirname(scenePath), i.path)) })),
  elements: doc.elements.map((e) => ({ ...e, image: ids.indexOf(e.image) })),
};

// [label, CLI options, reconstructScene options]
const cases = [
  ['defaults', [], {}],
  ['--no-opaque', ['--no-opaque'], { opaquePolygons: false }],
  ['--max-vertices 6 --opaque grow', ['--max-vertices', '6', '--opaque', 'grow'], { maxVertices: 6, opaque: 'grow' }],
  ['--target llvmpipe', ['--target', 'llvmpipe'], { target: 'llvmpipe' }],
  ['--target ipad1', ['--target', 'ipad1'], { target: 'ipad1' }],
];
// A calibrated profile (a file `depthcull calibrate` wrote): on the meadow
// the CLI's plan clips hidden parts there, which the wasm cannot (no
// Clipper), so it is compared with the CLI's --no-clip-hidden.
const profileFile = join(root, 'bench/results/calibration-llvmpipe.json');
cases.push(['--target calibration-llvmpipe.json --no-clip-hidden', ['--target', profileFile, '--no-clip-hidden'], { target: JSON.parse(readFileSync(profileFile, 'utf8')) }]);

for (const [label, args, options] of cases) {
  test(`reconstructScene equals depthcull optimize: meadow ${label}`, { skip: !existsSync(cli) && `no CLI at ${cli}` }, () => {
    const dir = mkdtempSync(join(tmpdir(), 'dc-reconstruct-'));
    try {
      const out = join(dir, 'meadow.meshes.json');
      execFileSync(cli, ['optimize', scenePath, '-o', out, '--no-timing', '--no-cache', ...args], { stdio: 'pipe' });
      const native = parseMeshesJson(readFileSync(out, 'utf8'), { name: out });
      const wasm = depthcull.reconstructScene(scene, options);
      const { seconds, ...nativeStats } = native.stats;
      void seconds;
      assert.deepEqual(wasm.stats, nativeStats);
      assert.equal(wasm.depthTest, native.depthTest);
      assert.equal(wasm.draws.length, native.draws.length);
      wasm.draws.forEach((d, i) => {
        const n = native.draws[i];
        assert.equal(wasm.images[d.image].id, native.images[n.image].id, `draw ${i} image`);
        assert.equal(d.pass, n.pass);
        assert.equal(d.blend, n.blend);
        assert.deepEqual(d.vertices, n.vertices, `draw ${i} vertices`);
        assert.deepEqual(d.indices, n.indices, `draw ${i} indices`);
      });
      if (options.target) assert.ok(wasm.target.predictedMs > 0 && wasm.target.predictedMs <= wasm.target.meshesOnlyMs + 1e-9);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });
}

const small = () => ({
  viewport: { width: 8, height: 8 },
  images: [{ id: 'a.png', width: 2, height: 2, data: new Uint8Array(16).fill(255) }],
  elements: [{ image: 0 }],
});
const bad = [
  ['unknown image', (s) => (s.elements[0].image = 1), 'element 0: image: Value 1 not in range 0 to 0'],
  ['rect outside', (s) => (s.elements[0].rect = [1, 0, 2, 2]), 'element 0: rect 1,0,2,2 is outside the 2x2 image'],
  ['NaN transform', (s) => (s.elements[0].transform = [1, 0, 0, 1, NaN, 0]), 'element 0: transform value 4 is not a finite number'],
  ['colour above 1', (s) => (s.elements[0].color = [1, 2, 1, 1]), 'element 0: colour value 1 is outside 0..1'],
  ['short pixels', (s) => (s.images[0].data = new Uint8Array(15)), 'a.png: data has 15 bytes, a 2x2 RGBA8 image has 16'],
  ['viewport', (s) => (s.viewport.width = 0), 'viewport.width: Value 0 not in range 1 to 16384 (kMaxImageSide)'],
  ['target', (s, o) => (o.target = 'gameboy'), "target: 'gameboy' is not a built-in profile (llvmpipe, ipad1; or pass a profile from depthcull calibrate)"],
  ['option', (s, o) => (o.maxVertices = 2), 'maxVertices: Value 2 not in range 4 to 1000'],
  [
    'more elements than a target weighs',
    (s, o) => ((s.elements = new Array(262145).fill({ image: 0 })), (o.target = 'llvmpipe')),
    'target: 262145 elements, more than the 262144 a target weighs (kMaxTargetElements); reconstruct without a target, or only the elements in view',
  ],
];
for (const [label, change, message] of bad) {
  test(`reconstructScene, bad input: ${label}`, () => {
    const s = small();
    const o = {};
    change(s, o);
    assert.throws(() => depthcull.reconstructScene(s, o), (e) => e instanceof DepthcullError && e.message === message);
    // The instance still works.
    assert.equal(depthcull.reconstructScene(small()).draws.length > 0, true);
  });
}

test('reconstructScene with an insertion point: the point as optimize --insert-at states it, valid for the meshes reader', () => {
  const m = depthcull.reconstructScene({ ...scene, insertionPoints: [{ element: 230, levels: 64 }] });
  assert.equal(m.insertionPoints.length, 1);
  const p = m.insertionPoints[0];
  assert.equal(p.element, 230);
  assert.equal(p.levels, 64);
  assert.ok(p.firstLevel > 0 && p.firstLevel + p.levels <= m.stats.depthLevels);
  // Written as a meshes JSON, it passes the reader's insertion point checks.
  const json = {
    viewport: m.viewport,
    depth_test: m.depthTest,
    images: m.images.map((img) => ({ id: img.id, path: `${img.id}.png`, width: img.width, height: img.height })),
    draws: m.draws.map((d) => ({ image: m.images[d.image].id, pass: d.pass, blend: d.blend, vertices: Array.from(d.vertices), indices: Array.from(d.indices) })),
    stats: { elements: m.stats.elements, draw_calls: m.stats.drawCalls, triangles: m.stats.triangles, depth_levels: m.stats.depthLevels, depth_bits: m.stats.depthBits, graph_edges: m.stats.graphEdges, seconds: 0 },
    insertion_points: [{ element: p.element, levels: p.levels, first_level: p.firstLevel, blend_draw: p.blendDraw }],
  };
  assert.deepEqual(parseMeshesJson(json).insertionPoints, m.insertionPoints);
  assert.throws(() => depthcull.reconstructScene({ ...scene, insertionPoints: [{ element: 500, levels: 1 }] }), {
    message: 'insertionPoints[0].element: Value 500 not in range 0 to 459',
  });
});
