// Hostile input to the wasm package (a hunt's findings): a refused call
// changes nothing, counts and sizes are checked before anything is
// allocated for them, getters that call back cannot corrupt a frame,
// objects of an instance a trap replaced say so, handles are reused, and
// the meshes readers' insertion point checks stay near-linear.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';

import { Depthcull, DepthcullError, loadDepthcull } from '../src/index.js';
import { parseMeshesBinary } from '../src/meshes.js';
import { wasiImports } from '../src/wasi.js';

const depthcull = await loadDepthcull();
const bounds = { x: 0, y: 0, width: 64, height: 64 };
const solid = (w, h, a = 255) => ({ width: w, height: h, data: new Uint8Array(w * h * 4).fill(a) });

function throwsLine(fn, message) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof DepthcullError, `a DepthcullError, not ${e?.name}: ${e?.message}`);
    if (message instanceof RegExp) assert.match(e.message, message);
    else assert.equal(e.message, message);
    return true;
  });
}

// A sparse array: `length` entries for a few bytes of JavaScript.
function sparse(length) {
  const a = [];
  a.length = length;
  a[0] = 0;
  return a;
}

// The instance's memory size, through a frame's views of it.
function memoryOf(dc) {
  const fa = dc.createFrameAssembler();
  fa.addImage(solid(4, 4));
  const bytes = fa.assemble([{ image: 0 }], bounds).vertices.buffer.byteLength;
  fa.free();
  return bytes;
}

const tiny = () => ({
  viewport: { width: 8, height: 8 },
  images: [{ id: 'a.png', width: 2, height: 2, data: new Uint8Array(16).fill(255) }],
  elements: [{ image: 0 }],
});

test('1. a refused setStaticMeshes leaves the assembler as it was', () => {
  // Sprites on top of meshes without points, then meshes with no level left.
  const a = depthcull.createFrameAssembler();
  a.addImage(solid(4, 4));
  a.setStaticMeshes({ draws: [], insertionPoints: [], stats: { depthBits: 10, depthLevels: 1 }, depthTest: true });
  assert.equal(a.assemble([{ image: 0 }], bounds).stats.sprites, 1);
  throwsLine(() => a.setStaticMeshes({ draws: [], insertionPoints: [], stats: { depthBits: 10, depthLevels: 1000 } }),
    'setStaticMeshes: the meshes leave no depth level above them for sprites (stats depth_levels, depth_bits)');
  assert.equal(a.assemble([{ image: 0 }], bounds).stats.sprites, 1);
  // Two points, then a point the wasm refuses: the two points stay.
  const points = [{ levels: 4, firstLevel: 1, blendDraw: 0 }, { levels: 4, firstLevel: 6, blendDraw: 0 }];
  const b = depthcull.createFrameAssembler();
  b.addImage(solid(4, 4));
  b.setStaticMeshes({ draws: [], insertionPoints: points, stats: { depthBits: 10, depthLevels: 12 }, depthTest: true });
  assert.equal(b.assemble([[{ image: 0 }], []], bounds).stats.sprites, 1);
  throwsLine(() => b.setStaticMeshes({ draws: [], insertionPoints: [points[0], { levels: 4, firstLevel: -1, blendDraw: 0 }], stats: { depthBits: 10 } }),
    'setInsertionPoints: point 1: firstLevel: Value -1 not in range 0 to 2097151');
  throwsLine(() => b.setStaticMeshes({ draws: [], insertionPoints: [], stats: { depthBits: 10, depthLevels: -3 } }),
    'setInsertionPoints: point 0: firstLevel: Value -3 not in range 0 to 2097151');
  assert.equal(b.assemble([[{ image: 0 }], [{ image: 0, x: 8 }]], bounds).stats.sprites, 2);
  a.free();
  b.free();
});

test('2. reconstructScene: element arrays of the wrong length or shape name the field', () => {
  const run = (element) => depthcull.reconstructScene({ ...tiny(), elements: [{ image: 0, ...element }] });
  throwsLine(() => run({ blend: 'add', color: [1, 1, 1, 1, 0, -1] }), 'element 0: color must be [r, g, b, a]: 4 numbers, not 6');
  throwsLine(() => run({ color: [1, 1, 1] }), 'element 0: color must be [r, g, b, a]: 4 numbers, not 3');
  throwsLine(() => run({ transform: [1, 0, 0, 1, 0] }), 'element 0: transform must be [a, b, c, d, e, f]: 6 numbers, not 5');
  throwsLine(() => run({ transform: { a: 1 } }), 'element 0: transform must be [a, b, c, d, e, f]');
  throwsLine(() => run({ rect: [0, 0, 2, 2, 0] }), 'element 0: rect must be [x, y, width, height] or {x, y, width, height}: 4 numbers, not 5');
  throwsLine(() => run({ rect: [0, '0', 2, 2] }), 'element 0: rect[1]: Value 0 is not a number');
  throwsLine(() => run({ rect: { x: 0, y: 0, width: 2 } }), 'element 0: rect.height: Value undefined is not a number');
  // analyzeImage's rect form is taken too, and means the same.
  const object = run({ rect: { x: 0, y: 0, width: 2, height: 2 }, blend: 'add' });
  assert.deepEqual(object, run({ rect: [0, 0, 2, 2], blend: 'add' }));
  assert.deepEqual(object.draws.map((d) => d.blend), ['add']);
  const animated = {
    ...tiny(),
    animations: [{ frames: [{ image: 0, rect: { x: 0, y: 0, width: 1, height: 1 }, duration: 100 }, { image: 0, rect: [1, 1, 1, 1], duration: 100 }] }],
    elements: [{ image: 0, rect: [0, 0, 1, 1], animation: 0 }],
  };
  assert.equal(depthcull.reconstructScene(animated).animations[0].frames.length, 2);
  animated.animations[0].frames[1].rect = [1, 1, 1];
  throwsLine(() => depthcull.reconstructScene(animated), 'animation 0: frames[1]: rect must be [x, y, width, height] or {x, y, width, height}: 4 numbers, not 3');
});

test('3. counts are checked before anything is allocated for them', () => {
  const dc = depthcull;
  const fa = dc.createFrameAssembler();
  fa.addImage(solid(4, 4));
  const before = memoryOf(dc);
  throwsLine(() => fa.addAnimation(sparse(2 ** 27 - 1)), 'addAnimation: frames: Value 134217727 not in range 1 to 65536');
  throwsLine(() => fa.addAnimation(sparse(2 ** 28)), 'addAnimation: frames: Value 268435456 not in range 1 to 65536');
  throwsLine(() => fa.addAnimation([]), 'addAnimation: frames: Value 0 not in range 1 to 65536');
  throwsLine(() => dc.reconstructScene({ ...tiny(), insertionPoints: sparse(2 ** 28) }), 'insertionPoints.length: Value 268435456 not in range 0 to 65536');
  throwsLine(() => dc.reconstructScene({ ...tiny(), insertion_points: sparse(2 ** 28) }), 'insertion_points, insertAt: 268435456 points, more than 65536');
  throwsLine(() => dc.reconstructScene({ ...tiny(), elements: sparse(2 ** 28) }), 'elements: 268435456 elements, more than the 4194304 the wasm takes');
  throwsLine(() => dc.reconstructScene({ ...tiny(), images: sparse(2 ** 28) }), 'images: 268435456 images, more than 65536 (kMaxSceneImages)');
  throwsLine(() => dc.reconstructScene({ ...tiny(), animations: [{ frames: sparse(2 ** 28) }] }), 'animation 0: frames.length: Value 268435456 not in range 1 to 65536');
  throwsLine(() => fa.setStaticMeshes({ draws: [], insertionPoints: sparse(2 ** 28), stats: { depthBits: 10 } }),
    'setInsertionPoints: insertionPoints.length: Value 268435456 not in range 0 to 65536');
  assert.equal(memoryOf(dc), before);
  assert.equal(fa.addAnimation([0]), 0);
  fa.free();
});

test('4. reconstructScene checks an image\'s size before copying its pixels', () => {
  const before = memoryOf(depthcull);
  const data = new Uint8Array(16385 * 4096 * 4); // 268 MB, never copied
  const scene = (img) => ({ viewport: { width: 8, height: 8 }, images: [{ id: 'big', data, ...img }], elements: [] });
  throwsLine(() => depthcull.reconstructScene(scene({ width: 16385, height: 4096 })), 'big: width: Value 16385 not in range 1 to 16384');
  throwsLine(() => depthcull.reconstructScene(scene({ width: '16385', height: 4096 })), 'big: width: Value 16385 is not a number');
  throwsLine(() => depthcull.reconstructScene(scene({ width: 2.5, height: 4096 })), 'big: width: Value 2.5 is not an integer');
  throwsLine(() => depthcull.reconstructScene(scene({ width: 16384, height: 16385 })), 'big: height: Value 16385 not in range 1 to 16384');
  assert.equal(memoryOf(depthcull), before);
});

test('5. assemble: the sprite limit is kMaxDepthLevels, named, whatever came before', () => {
  const fresh = depthcull.createFrameAssembler();
  fresh.addImage(solid(4, 4));
  const used = depthcull.createFrameAssembler();
  used.addImage(solid(4, 4));
  used.assemble(Array.from({ length: 1000 }, (_, i) => ({ image: 0, x: i % 60 })), bounds);
  for (const fa of [fresh, used]) {
    throwsLine(() => fa.assemble(sparse(2 ** 21), bounds), 'assemble: 2097152 sprites, more than the 2097151 depth levels a frame has (kMaxDepthLevels)');
    // 2^20 sprites used to ask the wasm for room for twice as many, past
    // the limit: now the frame is read (and refused here for its last sprite).
    const sprite = { image: 0 };
    const many = new Array(2 ** 20).fill(sprite);
    many[many.length - 1] = { image: 0, blend: 'screen' };
    throwsLine(() => fa.assemble(many, bounds), "assemble: sprite 1048575: blend 'screen' is not one of alpha, add, multiply, opaque");
    assert.equal(fa.assemble([{ image: 0 }], bounds).stats.sprites, 1);
  }
  fresh.free();
  used.free();
});

test('6. assemble: getters that grow memory or call back cannot change the frame', () => {
  const a = depthcull.createFrameAssembler();
  a.addImage(solid(4, 4));
  a.assemble([{ image: 0, x: 1, y: 1 }], bounds);
  const growing = {
    image: 0,
    get x() {
      depthcull.analyzeImage(solid(1024, 1024, 0)); // 4 MB into linear memory
      return 30;
    },
    y: 30,
  };
  const f = a.assemble([growing], bounds);
  assert.equal(f.stats.sprites, 1);
  const xs = Array.from({ length: f.vertices.length / 9 }, (_, k) => f.vertices[9 * k]);
  assert.equal(Math.min(...xs), 30);
  // Calling the same assembler back from a getter is refused (the outer
  // call is not answered with the inner frame).
  const reentering = {
    image: 0,
    get x() {
      a.assemble([{ image: 0 }, { image: 0 }], bounds);
      return 40;
    },
  };
  throwsLine(() => a.assemble([reentering], bounds), "FrameAssembler: called from a sprite's getter while assemble() reads the sprites");
  const freeing = { image: 0, get x() { a.free(); return 0; } };
  throwsLine(() => a.assemble([freeing], bounds), "FrameAssembler: called from a sprite's getter while assemble() reads the sprites");
  assert.equal(a.assemble([{ image: 0, x: 2 }], bounds).stats.sprites, 1);
  a.free();
});

test('7. objects made before a trap say so; decoded images are bounded before any copy', async () => {
  // An instance whose dcw_analyze traps once, on demand.
  const module = await WebAssembly.compile(readFileSync(new URL('../dist/depthcull.wasm', import.meta.url)));
  let real;
  real = await WebAssembly.instantiate(module, wasiImports(() => real.exports.memory, () => {}));
  let trap = false;
  const exports = Object.defineProperty({ ...real.exports }, 'dcw_analyze', {
    get: () => (trap ? () => { throw new WebAssembly.RuntimeError('unreachable'); } : real.exports.dcw_analyze),
  });
  const dc = new Depthcull(module, { exports }, () => {});
  const old = dc.createFrameAssembler();
  old.addImage(solid(4, 4));
  old.assemble([{ image: 0, x: 2, y: 2 }], bounds);
  trap = true;
  assert.throws(() => dc.analyzeImage(solid(4, 4)), /the analysis stopped in WebAssembly/);
  const fresh = dc.createFrameAssembler();
  fresh.addImage(solid(8, 8));
  const minX = (f) => Math.min(...Array.from({ length: f.vertices.length / 9 }, (_, k) => f.vertices[9 * k]));
  assert.equal(minX(fresh.assemble([{ image: 0, x: 5, y: 5 }], bounds)), 5);
  const dead = 'FrameAssembler: made before a WebAssembly error replaced the instance; make a new one (createFrameAssembler)';
  throwsLine(() => old.assemble([{ image: 0, x: 2, y: 2 }], bounds), dead);
  old.free(); // frees nothing in the new instance
  assert.equal(fresh.assemble([{ image: 0, x: 5, y: 5 }], bounds).stats.sprites, 1);
  fresh.free();

  // kMaxDecodedBytes: nine 8192^2 images are 2304 MiB, refused at the
  // ninth before the first is copied.
  const before = memoryOf(depthcull);
  const big = { width: 8192, height: 8192, data: new Uint8Array(8192 * 8192 * 4) };
  throwsLine(() => depthcull.reconstructScene({ viewport: { width: 8, height: 8 }, images: Array.from({ length: 9 }, (_, i) => ({ id: `i${i}`, ...big })), elements: [{ image: 0 }] }),
    'i8: 8192x8192 brings the decoded images to 2304 MiB, over the limit of 2048 MiB (kMaxDecodedBytes)');
  assert.equal(memoryOf(depthcull), before);
});

test('8. handles are reused: calls that make and free objects do not grow memory', async () => {
  const dc = await loadDepthcull();
  for (let i = 0; i < 100; ++i) dc.createFrameAssembler().free();
  const before = memoryOf(dc);
  const bad = { ...tiny(), viewport: { width: 0, height: 8 } };
  for (let i = 0; i < 20000; ++i) assert.throws(() => dc.reconstructScene(bad), DepthcullError);
  for (let i = 0; i < 40000; ++i) dc.createFrameAssembler().free();
  assert.equal(memoryOf(dc), before);
});

// gen.py of the hunt: valid binary meshes with 65,536 insertion points over
// `draws` blend draws of `vertices` vertices each at level 0.
function pointsFile(draws, vertices, blendDraw) {
  const points = 65536;
  const bytes = new Uint8Array(8 + 8 + 24 + 8 + 56 + 12 + 8 + draws * (16 + vertices * 36) + 4 + points * 32);
  const d = new DataView(bytes.buffer);
  let at = 0;
  const u32 = (v) => (d.setUint32(at, v, true), (at += 4));
  bytes.set([0x44, 0x43, 0x4d, 0x45, 0x53, 0x48, 0, 0]);
  at = 8;
  u32(1);
  u32(1 | 16);
  d.setInt32(at + 16, 64, true);
  d.setInt32(at + 20, 64, true);
  at += 24;
  u32(1);
  u32(draws);
  [1, draws, 0, 1, 10, 0].forEach((v, i) => d.setBigInt64(at + 8 * i, BigInt(v), true));
  at += 56;
  u32(1);
  bytes[at++] = 0x61; // "a"
  u32(0);
  at = (at + 3) & ~3;
  u32(4);
  u32(4);
  const vertex = new Float32Array([0, 0, 1 / 256, 0, 0, 1, 1, 1, 1]);
  for (let k = 0; k < draws; ++k) {
    u32(0);
    bytes[at] = 1; // blend pass
    at += 4;
    u32(vertices);
    u32(0);
    for (let v = 0; v < vertices; ++v, at += 36) new Float32Array(bytes.buffer, at, 9).set(vertex);
  }
  u32(points);
  for (let k = 0; k < points; ++k, at += 32) {
    d.setBigUint64(at, 1n, true);
    d.setUint32(at + 24, blendDraw < 0 ? draws : blendDraw, true);
  }
  return bytes.subarray(0, at);
}

test('9. the insertion point checks are near-linear in points x draws and points x vertices', () => {
  // Were 65,536 x draws and 65,536 x vertices steps: 2.6 and 6.5 s here.
  let t = performance.now();
  assert.equal(parseMeshesBinary(pointsFile(32768, 0, 0)).insertionPoints.length, 65536);
  assert.ok(performance.now() - t < 1500, `${performance.now() - t} ms for 32768 draws`);
  t = performance.now();
  assert.equal(parseMeshesBinary(pointsFile(1, 65536, -1)).insertionPoints.length, 65536);
  assert.ok(performance.now() - t < 1500, `${performance.now() - t} ms for 65536 vertices`);
  // The same verdicts: an opaque draw after a point's blend_draw, a vertex
  // in a point's levels.
  const opaque = pointsFile(4, 0, 1);
  opaque[8 + 8 + 24 + 8 + 56 + 12 + 8 + 2 * 16 + 4] = 0; // draw 2: opaque pass
  throwsLine(() => parseMeshesBinary(opaque, { name: 'x.bin' }), 'x.bin: byte 216: insertion point 0: blend_draw 1 is not in the blend pass (draw 2 is opaque)');
  const reserved = pointsFile(1, 4, -1);
  new DataView(reserved.buffer).setBigInt64(reserved.length - 32 + 8, 1n, true); // the last point reserves level 0
  throwsLine(() => parseMeshesBinary(reserved, { name: 'x.bin' }), /^x\.bin: byte \d+: draw 0 vertex 0 has depth level 0, reserved by insertion point 65535$/);
});

test('10. reconstructScene: a viewport past kMaxImageSide is refused, not rasterized', () => {
  for (const side of [16385, 65536]) {
    const s = { ...tiny(), viewport: { width: side, height: side }, elements: [{ image: 0, transform: [side / 2, 0, 0, side / 2, 0, 0] }] };
    throwsLine(() => depthcull.reconstructScene(s, { target: 'llvmpipe' }), `viewport.width: Value ${side} not in range 1 to 16384 (kMaxImageSide)`);
  }
  throwsLine(() => depthcull.reconstructScene({ ...tiny(), viewport: { x: 2e9, width: 8, height: 8 } }), 'viewport: x and y must be within +-1e9 (kMaxCoordinate)');
  assert.ok(depthcull.reconstructScene(tiny(), { target: 'llvmpipe' }).target.predictedMs > 0);
});

test('11. assemble refuses transforms and colours scene elements may not have', () => {
  const fa = depthcull.createFrameAssembler();
  fa.addImage(solid(4, 4));
  throwsLine(() => fa.assemble([{ image: 0, x: 1e300 }], bounds), 'assemble: sprite 0: x: 1e+300 is not a finite number within +-1e9 (kMaxCoordinate)');
  throwsLine(() => fa.assemble([{ image: 0 }, { image: 0, transform: [1e39, 0, 0, 1, 0, 0] }], bounds),
    'assemble: sprite 1: transform[0]: 1e+39 is not a finite number within +-1e9 (kMaxCoordinate)');
  throwsLine(() => fa.assemble([{ image: 0, color: [5, 1, 1, 1] }], bounds), 'assemble: sprite 0: color[0]: 5 is not in 0..1');
  throwsLine(() => fa.assemble([{ image: 0, color: [1, 1, 1, -1] }], bounds), 'assemble: sprite 0: color[3]: -1 is not in 0..1');
  throwsLine(() => fa.assemble([{ image: 0, y: '3' }], bounds), 'assemble: sprite 0: y: 3 is not a finite number within +-1e9 (kMaxCoordinate)');
  const f = fa.assemble([{ image: 0, transform: [1e9, 0, 0, 1, -1e9, 0], color: [0, 0.5, 1, 1] }], bounds);
  assert.ok(Array.from(f.vertices).every(Number.isFinite));
  fa.free();
  // Scene elements: the scene reader's bound in the wasm too.
  throwsLine(() => depthcull.reconstructScene({ ...tiny(), elements: [{ image: 0, transform: [1, 0, 0, 1, 0, -2e9] }] }),
    'element 0: transform value 5 is outside +-1e9 (kMaxCoordinate)');
});
