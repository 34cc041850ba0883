// Bad input: a DepthcullError with one line naming what is wrong, worded as
// the CLI words it; never a crash, a raw TypeError or a half result.
import { test } from 'node:test';
import assert from 'node:assert/strict';

import { DepthcullError, loadDepthcull } from '../src/index.js';

const depthcull = await loadDepthcull();

// A 4x3 image: an opaque 2x3 column in the middle.
function column() {
  const data = new Uint8Array(4 * 3 * 4);
  for (let y = 0; y < 3; ++y) for (const x of [1, 2]) data[(y * 4 + x) * 4 + 3] = 255;
  return { width: 4, height: 3, data };
}

function throwsLine(fn, message) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof DepthcullError, `a DepthcullError, not ${e?.name}: ${e?.message}`);
    assert.equal(e.message, message);
    assert.ok(!e.message.includes('\n'));
    return true;
  });
}

test('a small image gives its exact polygons', () => {
  const r = depthcull.analyzeImage(column(), { minOpaqueArea: 1 });
  assert.deepStrictEqual(r.boundary, [[[1, 0], [3, 0], [3, 3], [1, 3]]]);
  assert.equal(r.stats.nontransparent_texels, 6);
  assert.equal(r.stats.opaque_texels, 6);
  assert.deepStrictEqual(r.rect, { x: 0, y: 0, width: 4, height: 3 });
  // Fully opaque: the opaque polygon keeps half a texel inside (the paper's push, docs/opaque.md).
  const full = depthcull.analyzeImage({ width: 4, height: 3, data: new Uint8Array(48).fill(255) }, { minOpaqueArea: 1 });
  assert.deepStrictEqual(full.boundary, [[[0, 0], [4, 0], [4, 3], [0, 3]]]);
  assert.deepStrictEqual(full.opaque, [[[0.5, 0.5], [3.5, 0.5], [3.5, 2.5], [0.5, 2.5]]]);
  // ImageData's own array type works the same.
  const clamped = { ...column(), data: new Uint8ClampedArray(column().data) };
  assert.deepStrictEqual(depthcull.analyzeImage(clamped, { minOpaqueArea: 1 }), r);
});

test('a fully transparent image has no polygons', () => {
  const r = depthcull.analyzeImage({ width: 2, height: 2, data: new Uint8Array(16) });
  assert.deepStrictEqual([r.boundary, r.opaque], [[], []]);
});

test('options out of range are refused as the CLI refuses them', () => {
  const image = column();
  throwsLine(() => depthcull.analyzeImage(image, { maxVertices: 2 }), 'maxVertices: Value 2 not in range 4 to 1000');
  throwsLine(() => depthcull.analyzeImage(image, { maxVertices: 4.5 }), 'maxVertices: Value 4.5 is not an integer');
  throwsLine(() => depthcull.analyzeImage(image, { maxOpaque: 65 }), 'maxOpaque: Value 65 not in range 0 to 64');
  throwsLine(() => depthcull.analyzeImage(image, { minCoverage: 1.5 }), 'minCoverage: Value 1.5 not in range 0 to 1');
  throwsLine(() => depthcull.analyzeImage(image, { minCoverage: NaN }), 'minCoverage: Value NaN not in range 0 to 1');
  throwsLine(() => depthcull.analyzeImage(image, { minOpaqueArea: 0 }), 'minOpaqueArea: Value 0 not in range 1 to 1073741824');
  throwsLine(() => depthcull.analyzeImage(image, { opaque: 'foo' }), "opaque: 'foo' is not one of fast, grow, paper");
  throwsLine(() => depthcull.analyzeImage(image, { filter: 'cubic' }), "filter: 'cubic' is not one of nearest, linear");
  throwsLine(() => depthcull.analyzeImage(image, { maxVertices: '10' }), 'maxVertices: Value 10 is not a number');
  throwsLine(() => depthcull.analyzeImage(image, { maxVerts: 10 }),
    "analyzeImage: unknown option 'maxVerts' (known: maxVertices, split, filter, opaque, maxOpaque, minCoverage, minOpaqueArea, rect, name)");
});

test('a rectangle outside the image names the image and both sizes', () => {
  throwsLine(() => depthcull.analyzeImage(column(), { rect: { x: 2, y: 0, width: 3, height: 3 }, name: 'hero.png' }),
    'hero.png: rectangle 2,0,3,3 is outside the 4x3 image');
  throwsLine(() => depthcull.analyzeImage(column(), { rect: { x: 0, y: 0, width: 0, height: 3 } }),
    'image: rectangle 0,0,0,3 is outside the 4x3 image');
  throwsLine(() => depthcull.analyzeImage(column(), { rect: 5 }), 'image: rect must be {x, y, width, height}');
});

test('bad images are refused before anything is copied', () => {
  throwsLine(() => depthcull.analyzeImage(null), 'image: not an image (expected {width, height, data})');
  throwsLine(() => depthcull.analyzeImage({ width: 4, height: 3, data: [0, 0, 0, 0] }),
    'image: data must be a Uint8Array or Uint8ClampedArray of RGBA8 texels');
  throwsLine(() => depthcull.analyzeImage({ width: 4, height: 3, data: new Uint8Array(47) }),
    'image: data has 47 bytes, a 4x3 RGBA8 image has 48');
  throwsLine(() => depthcull.analyzeImage({ width: 0, height: 3, data: new Uint8Array(0) }),
    'image: width: Value 0 not in range 1 to 16384');
  throwsLine(() => depthcull.analyzeImage({ width: 20000, height: 1, data: new Uint8Array(80000) }),
    'image: width: Value 20000 not in range 1 to 16384');
  throwsLine(() => depthcull.analyzeImage({ width: 16384, height: 16385, data: new Uint8Array(0) }),
    'image: height: Value 16385 not in range 1 to 16384');
  throwsLine(() => depthcull.analyzeImage({ width: 2.5, height: 3, data: new Uint8Array(30) }),
    'image: width: Value 2.5 is not an integer');
});

test('the instance keeps working after errors', () => {
  for (let i = 0; i < 100; ++i) assert.throws(() => depthcull.analyzeImage(column(), { maxVertices: 1 }));
  assert.equal(depthcull.analyzeImage(column()).boundary.length, 1);
});

test('a missing wasm file is a one-line error naming it', async () => {
  await assert.rejects(loadDepthcull({ wasm: new URL('file:///nonexistent/depthcull.wasm') }),
    (e) => e instanceof DepthcullError && /^\/nonexistent\/depthcull\.wasm: cannot read depthcull\.wasm \(ENOENT; run scripts\/build-wasm\)$/.test(e.message));
});
