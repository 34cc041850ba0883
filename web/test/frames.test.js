// Moving sprites through the wasm (src/frames.js, dcw_frame_*): frames of
// include/depthcull/frame.h's FrameAssembler, alone and at the insertion
// points of static meshes; the same input gives the same frame, frames of
// the same size reuse every buffer, and bad input is one line.
import { test } from 'node:test';
import assert from 'node:assert/strict';

import { DepthcullError, loadDepthcull } from '../src/index.js';
import { parseMeshesJson } from '../src/meshes.js';

const depthcull = await loadDepthcull();

// A w x h picture, opaque inside a transparent border of `border` texels.
function picture(w, h, border) {
  const data = new Uint8Array(w * h * 4);
  for (let y = 0; y < h; ++y)
    for (let x = 0; x < w; ++x) {
      const inside = x >= border && y >= border && x < w - border && y < h - border;
      data.set([200, 100, 50, inside ? 255 : 0], 4 * (y * w + x));
    }
  return { width: w, height: h, data };
}

const bounds = { x: 0, y: 0, width: 256, height: 256 };

test('frames: a solid sprite gets an opaque draw, a bordered one a blend draw; draws name the texture', () => {
  const fa = depthcull.createFrameAssembler();
  const solid = fa.addImage(picture(16, 16, 0), { texture: 2 });
  const bordered = fa.addImage(picture(16, 16, 3), { texture: 5, minOpaqueArea: 4 });
  const f = fa.assemble([{ image: solid, x: 10, y: 20 }, { image: bordered, x: 100, y: 100 }], bounds);
  assert.equal(f.stats.sprites, 2);
  assert.ok(f.opaqueDraws >= 1);
  const textures = new Set();
  for (let d = 0; d < f.drawCount; ++d) textures.add(f.draws[5 * d]);
  assert.deepEqual([...textures].sort(), [2, 5]);
  assert.equal(f.stats.drawCalls, f.drawCount);
  // Every index names a vertex; the solid sprite's vertices lie on its square.
  const vertices = f.vertices.length / 9;
  for (const i of f.indices) assert.ok(i < vertices);
  let triangles = 0;
  for (let d = 0; d < f.drawCount; ++d) triangles += f.draws[5 * d + 4] / 3;
  assert.equal(triangles, f.stats.triangles);
  // Fully dynamic: one point, its blend draws after the opaque ones.
  assert.equal(f.pointCount, 1);
  assert.equal(f.points[1], f.opaqueDraws);
  assert.equal(f.points[2], f.drawCount);
  fa.free();
});

test('frames: the same sprites give the same frame; frames of one size reuse every buffer (no allocation)', () => {
  const fa = depthcull.createFrameAssembler();
  const img = fa.addImage(picture(16, 16, 2), { texture: 0, minOpaqueArea: 4 });
  const sprites = Array.from({ length: 50 }, (_, k) => ({ image: img, x: (k * 37) % 240, y: (k * 53) % 240 }));
  const first = fa.assemble(sprites, bounds);
  const copy = { v: Array.from(first.vertices), i: Array.from(first.indices), d: Array.from(first.draws) };
  const views = [first.vertices, first.indices, first.draws];
  const memory = first.vertices.buffer;
  for (let frame = 0; frame < 60; ++frame) {
    // Moving: each frame shifted, then back to the first positions.
    const moved = sprites.map((s) => ({ ...s, x: s.x + (frame % 7), y: s.y + (frame % 5) }));
    fa.assemble(moved, bounds);
  }
  const again = fa.assemble(sprites, bounds);
  assert.deepEqual(Array.from(again.vertices), copy.v);
  assert.deepEqual(Array.from(again.indices), copy.i);
  assert.deepEqual(Array.from(again.draws), copy.d);
  // Same memory, same addresses: nothing was allocated or moved.
  assert.equal(again.vertices.buffer, memory);
  assert.deepEqual([again.vertices, again.indices, again.draws].map((v) => v.byteOffset), views.map((v) => v.byteOffset));
  fa.free();
});

// Static meshes with one insertion point reserving level 1 (depth_bits 10,
// D = 256): a static opaque square at level 0 behind, a blend one at level
// 2 in front (draw 1, where the point's blend draws go before).
function meshesWithPoint(levels = 2) {
  const square = (z) => [0, 0, z, 0, 0, 1, 1, 1, 1, 64, 0, z, 1, 0, 1, 1, 1, 1, 0, 64, z, 0, 1, 1, 1, 1, 1];
  return parseMeshesJson({
    viewport: { x: 0, y: 0, width: 256, height: 256 },
    depth_test: true,
    images: [{ id: 'a', path: 'a.png', width: 2, height: 2 }],
    draws: [
      { image: 'a', pass: 'opaque', blend: 'opaque', vertices: square(2 / 256), indices: [0, 1, 2] },
      { image: 'a', pass: 'blend', blend: 'alpha', vertices: square((2 * (levels + 1) + 2) / 256), indices: [0, 1, 2] },
    ],
    stats: { elements: 2, draw_calls: 2, triangles: 2, depth_levels: levels + 2, depth_bits: 10, graph_edges: 0, seconds: 0 },
    insertion_points: [{ element: 1, levels, first_level: 1, blend_draw: 1 }],
  });
}

test('frames at an insertion point: the sprites take its reserved levels, their blend draws go before the named static draw', () => {
  const fa = depthcull.createFrameAssembler();
  const img = fa.addImage(picture(16, 16, 2), { texture: 0, minOpaqueArea: 4 });
  fa.setStaticMeshes(meshesWithPoint());
  const f = fa.assemble([[{ image: img, x: 8, y: 8 }, { image: img, x: 12, y: 12 }]], bounds);
  assert.equal(f.pointCount, 1);
  assert.equal(f.points[0], 1); // static draw 1
  // Levels 1 and 2 draw at z (2k+1)/D and (2k+2)/D: 3/256 .. 6/256.
  const used = new Set();
  for (const i of f.indices) used.add(f.vertices[9 * i + 2] * 256);
  for (const z of used) assert.ok(z >= 3 && z <= 6, `z ${z}/256 outside levels 1..2`);
  assert.ok(used.size >= 2);
  assert.throws(() => fa.assemble([[0, 1, 2].map((k) => ({ image: img, x: k, y: k }))], bounds), {
    name: 'DepthcullError',
    message: "assemble: more sprites than depth levels (kMaxDepthLevels, or an insertion point's reserved levels)",
  });
  assert.throws(() => fa.assemble([[], []], bounds), { message: 'assemble: 2 sprite lists but the meshes have 1 insertion points' });
  fa.free();
});

const bad = [
  ['unknown image', [{ image: 7 }], 'assemble: a sprite names an unknown image or animation, or has a non-finite transform or colour'],
  ['fractional image', [{ image: 0.5 }], 'assemble: sprite 0: image: Value 0.5 is not an integer'],
  ['NaN transform', [{ image: 0, transform: [1, 0, 0, 1, NaN, 0] }], 'assemble: sprite 0: transform[4]: NaN is not a finite number within +-1e9 (kMaxCoordinate)'],
  ['blend', [{ image: 0, blend: 'screen' }], "assemble: sprite 0: blend 'screen' is not one of alpha, add, multiply, opaque"],
  ['not a list', { image: 0 }, 'assemble: expected an array of sprites'],
];
for (const [label, sprites, message] of bad) {
  test(`frames, bad input: ${label}`, () => {
    const fa = depthcull.createFrameAssembler();
    fa.addImage(picture(4, 4, 0));
    assert.throws(() => fa.assemble(sprites, bounds), (e) => e instanceof DepthcullError && e.message === message && !e.message.includes('\n'));
    // The assembler still works after an error.
    assert.equal(fa.assemble([{ image: 0 }], bounds).stats.sprites, 1);
    fa.free();
  });
}

test('frames: bad images and options are the analysis\'s one-line errors', () => {
  const fa = depthcull.createFrameAssembler();
  assert.throws(() => fa.addImage(picture(4, 4, 0), { rect: { x: 2, y: 0, width: 3, height: 3 }, name: 'hero.png' }), {
    message: 'hero.png: rectangle 2,0,3,3 is outside the 4x4 image',
  });
  assert.throws(() => fa.addImage(picture(4, 4, 0), { texture: -1 }), { message: 'texture: Value -1 not in range 0 to 2147483647' });
  assert.throws(() => fa.addAnimation([0]), { message: 'addAnimation: frame 0: image: Value 0 not in range 0 to -1' });
  assert.throws(() => depthcull.createFrameAssembler({ filter: 'cubic' }), { message: "filter: 'cubic' is not one of nearest, linear" });
  fa.free();
  assert.throws(() => fa.assemble([], bounds), { message: 'FrameAssembler: freed' });
});
