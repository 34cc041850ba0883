// reconstructScene takes what `depthcull optimize` takes for a scene: a
// scene JSON with colour-keyed images (Tiled's trans), fill images (a
// map's backgroundcolor), animated tiles, images sharing a file, insertion
// points (insertion_points, --insert-at, --insertion-levels), and --target
// with a built-in profile or a calibrated profile file. Its meshes equal
// the CLI's float for float and index for index, on a scene made here and
// on corpus Tiled maps (sewers: a colour key; island: animated tiles and
// an object layer), imported with `depthcull import`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { homedir, tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, isAbsolute, join } from 'node:path';

import { DepthcullError, loadDepthcull } from '../src/index.js';
import { parseMeshesJson } from '../src/meshes.js';
import { encodePng, readPng } from './support/png.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');
const noCli = !existsSync(cli) && `no CLI at ${cli}`;
const depthcull = await loadDepthcull();
const profileFile = join(root, 'bench/results/calibration-llvmpipe.json');

// ---- A scene made here: every kind of input at once.

function image(width, height, texel) {
  const data = new Uint8Array(width * height * 4);
  for (let y = 0; y < height; ++y) for (let x = 0; x < width; ++x) data.set(texel(x, y), (y * width + x) * 4);
  return { width, height, data };
}

// tiles.png: two opaque 8x8 tiles, then a 16x16 sprite with transparent
// corners and a translucent ring.
const tiles = image(32, 16, (x, y) => {
  if (x < 16) return y < 8 ? [40 + 10 * (x % 8), 120, 60, 255] : [90, 60 + 9 * (y % 8), 30, 255];
  const d = Math.hypot(x - 24 + 0.5, y - 8 + 0.5);
  return d < 5 ? [230, 200, 40, 255] : d < 7 ? [200, 90, 30, 128] : [0, 0, 0, 0];
});
// keyed.png (RGB): a diamond on the key colour ff00ff.
const keyed = image(16, 16, (x, y) => (Math.abs(x - 7.5) + Math.abs(y - 7.5) < 7 ? [20 + 10 * x, 200, 20 + 10 * y, 255] : [255, 0, 255, 255]));
// anim.png: two 8x8 frames; frame 1 shows texels frame 0 does not.
const anim = image(16, 8, (x, y) => {
  const f = x >= 8 ? 1 : 0, u = x % 8;
  if (f === 0) return u >= 2 && u < 6 && y >= 2 && y < 6 ? [250, 250, 250, 255] : [0, 0, 0, 0];
  return u >= 1 && u < 7 && y >= 1 && y < 5 ? [250, 120, 120, 255] : y === 6 ? [120, 120, 250, 100] : [0, 0, 0, 0];
});

function madeScene() {
  const elements = [{ image: 'sky', transform: [6, 0, 0, 4, 0, 0] }];
  // A backdrop of opaque tiles (opaque merging with a target).
  for (let y = 32; y < 64; y += 8) for (let x = 0; x < 96; x += 8) elements.push({ image: 'tiles', rect: [(x / 8) % 2 ? 8 : 0, (y / 8) % 2 ? 8 : 0, 8, 8], transform: [1, 0, 0, 1, x, y] });
  elements.push(
    { image: 'keyed', transform: [1, 0, 0, 1, 4, 4] },
    { image: 'keyed', transform: [2, 0, 0, 2, 20, 24] },
    { image: 'anim', rect: [0, 0, 8, 8], animation: 0, transform: [1, 0, 0, 1, 40, 10] },
    { image: 'anim', rect: [0, 0, 8, 8], animation: 0, transform: [2, 0, 0, 2, 56, 30] },
    { image: 'tiles', rect: [16, 0, 16, 16], transform: [1, 0, 0, 1, 30, 36], color: [1, 0.8, 0.6, 0.7] },
    { image: 'tiles2', rect: [16, 0, 16, 16], transform: [1, 0, 0, 1, 50, 40] },
    { image: 'tiles', rect: [16, 0, 16, 16], transform: [1, 0, 0, 1, 70, 20], blend: 'add' },
    { image: 'tiles', rect: [16, 0, 16, 16], transform: [1.5, 0, 0, 1.5, 10, 40], blend: 'multiply' },
    { image: 'keyed', transform: [0, 1, -1, 0, 90, 2] },
  );
  return {
    viewport: { x: 0, y: 0, width: 96, height: 64 },
    images: [
      { id: 'sky', fill: '336699' },
      { id: 'tiles', path: 'tiles.png' },
      { id: 'keyed', path: 'keyed.png', trans: 'ff00ff' },
      { id: 'anim', path: 'anim.png' },
      { id: 'tiles2', path: 'tiles.png' }, // the same file: shared analyses and meshes
    ],
    animations: [{ frames: [{ image: 'anim', rect: [0, 0, 8, 8], duration: 100 }, { image: 'anim', rect: [8, 0, 8, 8], duration: 150 }] }],
    elements,
    insertion_points: [25, elements.length],
  };
}

// The scene JSON's images with their pixels, as a page would decode them.
function withPixels(doc, dir) {
  return { ...doc, images: doc.images.map((img) => (img.fill ? img : { ...img, ...readPng(isAbsolute(img.path) ? img.path : join(dir, img.path)) })) };
}

function compare(wasm, native, label) {
  const { seconds, ...nativeStats } = native.stats;
  void seconds;
  assert.deepEqual(wasm.stats, nativeStats, `${label}: stats`);
  assert.equal(wasm.depthTest, native.depthTest, `${label}: depth test`);
  assert.deepEqual(wasm.images.map((i) => [i.id, i.trans, i.fill]), native.images.map((i) => [i.id, i.trans, i.fill]), `${label}: images`);
  assert.equal(wasm.draws.length, native.draws.length, `${label}: draws`);
  wasm.draws.forEach((d, i) => {
    const n = native.draws[i];
    assert.deepEqual([d.image, d.pass, d.blend], [n.image, n.pass, n.blend], `${label}: draw ${i}`);
    assert.deepEqual(d.vertices, n.vertices, `${label}: draw ${i} vertices`);
    assert.deepEqual(d.indices, n.indices, `${label}: draw ${i} indices`);
  });
  assert.deepEqual(wasm.insertionPoints, native.insertionPoints, `${label}: insertion points`);
  assert.deepEqual(wasm.animations, native.animations, `${label}: animations`);
  assert.deepEqual(wasm.animated, native.animated, `${label}: animated runs`);
}

function optimize(scene, dir, args) {
  const out = join(dir, 'out.meshes.json');
  execFileSync(cli, ['optimize', scene, '-o', out, '--no-timing', '--no-cache', '-q', ...args], { stdio: 'pipe' });
  return parseMeshesJson(readFileSync(out, 'utf8'), { name: out });
}

// [label, CLI options, reconstructScene options]
const cases = [
  ['defaults', [], {}],
  ['--insertion-levels 16', ['--insertion-levels', '16'], { insertionLevels: 16 }],
  ['--insert-at 5', ['--insert-at', '5'], { insertAt: [5] }],
  ['--no-opaque', ['--no-opaque'], { opaquePolygons: false }],
  ['--max-vertices 6 --opaque grow', ['--max-vertices', '6', '--opaque', 'grow'], { maxVertices: 6, opaque: 'grow' }],
  ['--target ipad1 --insertion-levels 8', ['--target', 'ipad1', '--insertion-levels', '8'], { target: 'ipad1', insertionLevels: 8 }],
  ['--target llvmpipe', ['--target', 'llvmpipe'], { target: 'llvmpipe' }],
  ['--target calibration-llvmpipe.json --insertion-levels 4', ['--target', profileFile, '--insertion-levels', '4'], { target: readFileSync(profileFile, 'utf8'), insertionLevels: 4 }],
];

// The wasm has no Clipper: with a target it plans without clipping hidden
// parts, as the CLI does with --no-clip-hidden; it is compared with
// that. Where the CLI's own plan clipped nothing, its default output is the
// same (said in the log, with the scenes where it is not).
function nativeFor(scene, dir, args, options, label) {
  if (!options.target) return optimize(scene, dir, args);
  const noClip = optimize(scene, dir, [...args, '--no-clip-hidden']);
  const clipped = optimize(scene, dir, args);
  const same = JSON.stringify(clipped, (k, v) => (ArrayBuffer.isView(v) ? Array.from(v) : v)) === JSON.stringify(noClip, (k, v) => (ArrayBuffer.isView(v) ? Array.from(v) : v));
  console.log(`# ${label}: the CLI's default output ${same ? 'is the same (no hidden part clipped)' : 'clips hidden parts (Clipper): compared with --no-clip-hidden'}`);
  return noClip;
}

for (const [label, args, options] of cases) {
  test(`reconstructScene equals depthcull optimize on a scene with a fill, a colour key, animations, a shared file and insertion points: ${label}`, { skip: noCli }, () => {
    const dir = mkdtempSync(join(tmpdir(), 'dc-scenes-'));
    try {
      writeFileSync(join(dir, 'tiles.png'), encodePng(tiles));
      writeFileSync(join(dir, 'keyed.png'), encodePng(keyed, { rgb: true }));
      writeFileSync(join(dir, 'anim.png'), encodePng(anim));
      const doc = madeScene();
      writeFileSync(join(dir, 'scene.json'), JSON.stringify(doc));
      const native = nativeFor(join(dir, 'scene.json'), dir, args, options, label);
      const wasm = depthcull.reconstructScene(withPixels(doc, dir), options);
      compare(wasm, native, label);
      // What the scene exercises shows in the output.
      assert.ok(wasm.draws.some((d) => wasm.images[d.image].fill), 'a draw of the fill');
      assert.ok(wasm.animated.length > 0, 'animated runs');
      if (options.insertionLevels || options.insertAt) assert.ok(wasm.insertionPoints.length > 0);
      if (options.target) assert.ok(wasm.target.predictedMs > 0);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });
}

// ---- Corpus Tiled maps (scripts/fetch-corpus), imported by the CLI.
const corpus = join(homedir(), '.cache/depthcull/corpus/tiled/usr/share/doc/tiled/examples');
const maps = [
  ['sewers (colour key)', 'sewers.tmx', '0,0,640,480'],
  ['island (animated tiles, an object layer)', 'rpg/island.tmx', '0,0,640,480'],
];
for (const [label, file, viewport] of maps) {
  for (const [option, args, options] of [
    ['--insertion-levels 32', ['--insertion-levels', '32'], { insertionLevels: 32 }],
    ['--target ipad1', ['--target', 'ipad1'], { target: 'ipad1' }],
    ['--target calibration-llvmpipe.json', ['--target', profileFile], { target: JSON.parse(readFileSync(profileFile, 'utf8')) }],
  ]) {
    test(`reconstructScene equals depthcull optimize: corpus ${label} ${option}`, { skip: noCli || (!existsSync(join(corpus, file)) && 'no corpus (scripts/fetch-corpus)') }, () => {
      const dir = mkdtempSync(join(tmpdir(), 'dc-scenes-'));
      try {
        const scene = join(dir, 'map.scene.json');
        execFileSync(cli, ['import', join(corpus, file), '-o', scene, '--viewport', viewport], { stdio: 'pipe' });
        const doc = JSON.parse(readFileSync(scene, 'utf8'));
        const native = nativeFor(scene, dir, args, options, `${label} ${option}`);
        const wasm = depthcull.reconstructScene(withPixels(doc, dir), options);
        compare(wasm, native, `${label} ${option}`);
        if (file.includes('island')) assert.ok(wasm.animated.length > 0 && (wasm.insertionPoints.length > 0) === Boolean(options.insertionLevels));
        else assert.ok(wasm.images.some((i) => i.trans));
      } finally {
        rmSync(dir, { recursive: true, force: true });
      }
    });
  }
}

// ---- Bad input: one line, worded as the CLI words it.
const small = () => ({
  viewport: { width: 8, height: 8 },
  images: [{ id: 'a.png', path: 'a.png', width: 2, height: 2, data: new Uint8Array(16).fill(255) }, { id: 'bg', fill: '102030' }],
  animations: [{ frames: [{ image: 'a.png', rect: [0, 0, 1, 1] }, { image: 'a.png', rect: [1, 1, 1, 1] }] }],
  elements: [{ image: 'bg' }, { image: 'a.png', rect: [0, 0, 1, 1], animation: 0 }],
});
const calibrated = () => JSON.parse(readFileSync(profileFile, 'utf8'));
const bad = [
  ['unknown image id', (s) => (s.elements[1].image = 'b.png'), 'element 1: unknown image id "b.png"'],
  ['colour key', (s) => (s.images[0].trans = 'magenta'), "a.png: trans: colour key 'magenta' is not RRGGBB hex"],
  ['fill', (s) => (s.images[1].fill = '12345'), "bg: fill: colour key '12345' is not RRGGBB hex"],
  ['animation frames of two sizes', (s) => (s.animations[0].frames[1].rect = [0, 0, 2, 2]), 'animation 0: frames differ in size'],
  ['animation frame image', (s) => (s.animations[0].frames[1].rect = [2, 1, 1, 1]), 'animation 0: frame 1 rect is outside image "a.png"'],
  ['animated element not on frame 0', (s) => (s.elements[1].rect = [1, 1, 1, 1]), "element 1: an animated element shows its animation's first frame (image and rect)"],
  ['unknown animation', (s) => (s.elements[1].animation = 1), 'element 1: animation: Value 1 not in range -1 to 0'],
  ['profile term missing', (s, o) => (o.target = (({ fragment_blend_ns, ...p }) => (void fragment_blend_ns, p))(calibrated())), 'target: "fragment_blend_ns" missing (every term of the model is required)'],
  ['profile term negative', (s, o) => (o.target = { ...calibrated(), triangle_us: -1 }), 'target: "triangle_us": -1 is not a finite number >= 0'],
  ['profile unknown key', (s, o) => (o.target = { ...calibrated(), gpu: 'x' }), 'target: "gpu": unknown key'],
  ['profile version', (s, o) => (o.target = { ...calibrated(), depthcull_profile: 2 }), 'target: "depthcull_profile": expected 1 (the profile format version)'],
  ['profile text', (s, o) => (o.target = '{"depthcull_profile": 1,'), /^target: not valid JSON/],
  ['insertion levels', (s, o) => Object.assign(o, { insertAt: [1], insertionLevels: 1.5 }), 'insertionPoints[0].levels: Value 1.5 is not an integer'],
  ['insert at', (s, o) => (o.insertAt = [3]), 'insertionPoints[0].element: Value 3 not in range 0 to 2'],
];
for (const [label, change, message] of bad) {
  test(`reconstructScene, bad scene input: ${label}`, () => {
    const s = small();
    const o = {};
    change(s, o);
    assert.throws(() => depthcull.reconstructScene(s, o), (e) => e instanceof DepthcullError && (message instanceof RegExp ? message.test(e.message) : e.message === message));
    // The instance still works, with every kind of input.
    const m = depthcull.reconstructScene(small(), { target: calibrated(), insertAt: [1] });
    assert.ok(m.draws.length > 0 && m.animated.length > 0 && m.insertionPoints.length === 1);
  });
}
