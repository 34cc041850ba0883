// Reading the binary meshes form in JavaScript (src/meshes.js's
// parseMeshesBinary): what the CLI writes with --binary reads back equal to
// its JSON, insertion points (flags bit 4) read as the JSON's, and bad files
// give one line worded as src/io/mesh_binary_reader.cpp words it, at the
// byte the C++ reader names.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

import { DepthcullError } from '../src/index.js';
import { parseMeshes, parseMeshesBinary, parseMeshesJson } from '../src/meshes.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');

const Z = 2 / 256; // depth level 0 of depth_bits 10

// A little writer of docs/mesh-format.md's binary layout, for the cases.
function encode(m) {
  const parts = [];
  const view = (n, fill) => {
    const dv = new DataView(new ArrayBuffer(n));
    fill(dv);
    parts.push(new Uint8Array(dv.buffer));
  };
  const u32 = (v) => view(4, (d) => d.setUint32(0, v, true));
  const str = (s) => {
    const b = new TextEncoder().encode(s);
    u32(b.length);
    parts.push(b);
  };
  parts.push(new Uint8Array([0x44, 0x43, 0x4d, 0x45, 0x53, 0x48, 0, 0]));
  u32(m.version ?? 1);
  u32(m.flags);
  view(24, (d) => {
    d.setFloat64(0, m.viewport[0], true);
    d.setFloat64(8, m.viewport[1], true);
    d.setInt32(16, m.viewport[2], true);
    d.setInt32(20, m.viewport[3], true);
  });
  u32(m.images.length);
  u32(m.drawCount ?? m.draws.length);
  view(56, (d) => {
    m.stats.forEach((v, i) => d.setBigInt64(8 * i, BigInt(v), true));
    d.setFloat64(48, m.seconds ?? 0, true);
  });
  for (const img of m.images) {
    str(img.id);
    str(img.path);
    const len = parts.reduce((n, p) => n + p.length, 0);
    if (len % 4) parts.push(new Uint8Array(4 - (len % 4)));
    view(8, (d) => {
      d.setInt32(0, img.width, true);
      d.setInt32(4, img.height, true);
    });
    if (m.flags & 2) u32(img.key ?? 0);
  }
  for (const dr of m.draws) {
    view(16, (d) => {
      d.setUint32(0, dr.image, true);
      d.setUint8(4, dr.pass);
      d.setUint8(5, dr.blend);
      d.setUint32(8, dr.vertices.length / 9, true);
      d.setUint32(12, dr.indices.length, true);
    });
    parts.push(new Uint8Array(new Float32Array(dr.vertices).buffer));
    parts.push(new Uint8Array(new Uint32Array(dr.indices).buffer));
  }
  if (m.points) {
    u32(m.points.length);
    for (const p of m.points)
      view(32, (d) => {
        d.setBigUint64(0, BigInt(p[0]), true);
        d.setBigInt64(8, BigInt(p[1]), true);
        d.setBigInt64(16, BigInt(p[2]), true);
        d.setUint32(24, p[3], true);
        d.setUint32(28, p[4] ?? 0, true);
      });
  }
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}

// Two draws (an opaque square at level 0, a blend one at level 2) and an
// insertion point between them reserving level 1: element 1 of 2, its
// sprites' blend draws before draw 1.
function valid() {
  const square = (z) => [0, 0, z, 0, 0, 1, 1, 1, 1, 2, 0, z, 1, 0, 1, 1, 1, 1, 0, 2, z, 0, 1, 1, 1, 1, 1];
  return {
    flags: 1 | 16,
    viewport: [0, 0, 4, 4],
    images: [{ id: 'a', path: 'a.png', width: 2, height: 2 }],
    draws: [
      { image: 0, pass: 0, blend: 3, vertices: square(Z), indices: [0, 1, 2] },
      { image: 0, pass: 1, blend: 0, vertices: square(6 / 256), indices: [0, 1, 2] },
    ],
    // elements, draw_calls, triangles, depth_levels, depth_bits, graph_edges
    stats: [2, 2, 2, 3, 10, 0],
    points: [[1, 1, 1, 1]],
  };
}

function message(bytes) {
  try {
    parseMeshes(bytes, { name: 'bad.meshes.bin' });
  } catch (e) {
    assert.ok(e instanceof DepthcullError, `${e.name}: ${e.message}`);
    assert.ok(!e.message.includes('\n'));
    return e.message;
  }
  assert.fail('no error');
}

test('binary: insertion points read back, as the JSON form gives them', () => {
  const m = parseMeshesBinary(encode(valid()), { name: 'ok.bin' });
  assert.deepEqual(m.insertionPoints, [{ element: 1, levels: 1, firstLevel: 1, blendDraw: 1 }]);
  assert.equal(m.draws.length, 2);
  assert.equal(m.draws[1].blend, 'alpha');
  assert.equal(m.draws[0].vertices[2], Math.fround(Z));
  const json = parseMeshesJson({
    viewport: { x: 0, y: 0, width: 4, height: 4 },
    depth_test: true,
    images: [{ id: 'a', path: 'a.png', width: 2, height: 2 }],
    draws: m.draws.map((d) => ({ image: 'a', pass: d.pass, blend: d.blend, vertices: Array.from(d.vertices), indices: Array.from(d.indices) })),
    stats: { elements: 2, draw_calls: 2, triangles: 2, depth_levels: 3, depth_bits: 10, graph_edges: 0, seconds: 0 },
    insertion_points: [{ element: 1, levels: 1, first_level: 1, blend_draw: 1 }],
  });
  assert.deepEqual(json.insertionPoints, m.insertionPoints);
  assert.deepEqual(json.draws, m.draws);
});

const cases = [
  ['short', () => new Uint8Array([0x44, 0x43, 0x4d, 0x45, 0x53, 0x48, 0, 0, 1]), 'bad.meshes.bin: byte 8: the file ends inside the header'],
  ['version 2', (m) => (m.version = 2), 'bad.meshes.bin: byte 8: format version 2 is not supported (expected 1)'],
  ['unknown flag', (m) => (m.flags |= 32), 'bad.meshes.bin: byte 12: unknown flags 49 (bit 0 depth_test, bit 1 colour keys, bit 2 linear filtering, bit 3 animations and bit 4 insertion points are defined)'],
  ['NaN viewport', (m) => (m.viewport[1] = NaN), 'bad.meshes.bin: byte 24: viewport y is not a finite number'],
  ['negative width', (m) => (m.viewport[2] = -1), 'bad.meshes.bin: byte 32: viewport width -1 is outside 0..2147483647'],
  ['negative stats', (m) => (m.stats[2] = -1), 'bad.meshes.bin: byte 64: a negative stats count'],
  ['too many draws for the bytes', (m) => (m.drawCount = 1000), 'bad.meshes.bin: byte 40: 1 images and 1000 draws do not fit in the 332 bytes left'],
  ['image side', (m) => (m.images[0].width = 20000), 'bad.meshes.bin: byte 120: image width 20000 is outside 0..16384'],
  ['colour key bits', (m) => ((m.flags |= 2), (m.images[0].key = 1 << 26)), 'bad.meshes.bin: byte 128: colour key 67108864 has unknown bits'],
  ['colour keys flag without keys', (m) => (m.flags |= 2), 'bad.meshes.bin: byte 12: flags bit 1 (colour keys) is set but no image has a colour key or fill'],
  ['draw image', (m) => (m.draws[0].image = 1), 'bad.meshes.bin: byte 128: draw names image 1 of 1'],
  ['pass', (m) => (m.draws[0].pass = 2), 'bad.meshes.bin: byte 132: unknown pass 2 (0 opaque, 1 blend)'],
  ['blend', (m) => (m.draws[0].blend = 4), 'bad.meshes.bin: byte 133: unknown blend 4 (0 alpha, 1 add, 2 multiply, 3 opaque)'],
  ['not triangles', (m) => m.draws[0].indices.push(0), 'bad.meshes.bin: byte 140: index count 4 is not a multiple of 3 (triangles)'],
  ['z above 1', (m) => (m.draws[0].vertices[11] = 1.5), 'bad.meshes.bin: byte 188: vertex 1 value 2 is a depth (z) outside [0, 1]'],
  ['index', (m) => (m.draws[0].indices[2] = 3), 'bad.meshes.bin: byte 260: index 3 is not below the draw\'s vertex count 3'],
  ['depth levels', (m) => ((m.flags = 1), (m.points = null), (m.stats[3] = 1)), "bad.meshes.bin: stats depth_levels 1 is lower than the 3 levels its draws' z values use"],
  ['points flag, no points', (m) => (m.points = []), /^bad\.meshes\.bin: byte \d+: flags bit 4 \(insertion points\) is set but the insertion point count is 0$/],
  ['point reserved', (m) => (m.points[0][4] = 1), /^bad\.meshes\.bin: byte \d+: insertion point reserved field is not 0$/],
  ['point past elements', (m) => (m.points[0][0] = 3), /^bad\.meshes\.bin: byte \d+: insertion point 0: element 3 is past the scene's 2 elements \(stats elements\)$/],
  ['point on a static level', (m) => ((m.points[0][2] = 0), (m.points[0][3] = 1)), /^bad\.meshes\.bin: byte \d+: draw 0 vertex 0 has depth level 0, reserved by insertion point 0$/],
  ['point blend draw opaque', (m) => (m.points[0][3] = 0), /^bad\.meshes\.bin: byte \d+: insertion point 0: blend_draw 0 is not in the blend pass \(draw 0 is opaque\)$/],
  ['points out of order', (m) => m.points.push([0, 0, 3, 2]), /^bad\.meshes\.bin: byte \d+: insertion point 1: element 0 is before the previous point's \(points go in element order\)$/],
  ['points past the bytes', (m) => m.points.push(...Array(3).fill([2, 0, 3, 2])), null],
  ['bytes after', null, /^bad\.meshes\.bin: byte \d+: 1 bytes after the insertion points$/],
];

for (const [label, change, expected] of cases) {
  test(`bad binary meshes: ${label}`, () => {
    let bytes;
    if (label === 'short') bytes = change();
    else {
      const m = valid();
      if (change) change(m);
      bytes = encode(m);
      if (label === 'bytes after') bytes = Uint8Array.of(...bytes, 0);
      if (label === 'points past the bytes') bytes = bytes.subarray(0, bytes.length - 1);
    }
    const got = message(bytes);
    if (expected === null) assert.match(got, /^bad\.meshes\.bin: byte \d+: 4 insertion points do not fit in the 127 bytes left$/);
    else if (expected instanceof RegExp) assert.match(got, expected);
    else assert.equal(got, expected);
  });
}

test('binary: not read past the file at any length (every prefix a one-line error)', () => {
  const bytes = encode(valid());
  for (let n = 0; n < bytes.length; ++n) {
    const m = message(bytes.subarray(0, n));
    // Shorter than the magic reads as (bad) JSON, as the CLI's read_meshes does.
    if (n >= 8) assert.match(m, /^bad\.meshes\.bin: byte \d+: /);
  }
});

test('binary: the bundled example as the CLI writes it (--binary) equals its JSON', { skip: !existsSync(cli) && `no CLI at ${cli}` }, () => {
  const dir = mkdtempSync(join(tmpdir(), 'dc-meshes-bin-'));
  try {
    const json = join(dir, 'meadow.meshes.json');
    const bin = join(dir, 'meadow.meshes.bin');
    execFileSync(cli, ['optimize', join(root, 'examples/meadow.json'), '-o', json, '--binary', bin, '--no-timing'], { stdio: 'pipe' });
    const a = parseMeshesJson(readFileSync(json, 'utf8'), { name: json });
    const b = parseMeshes(readFileSync(bin), { name: bin });
    assert.ok(b.draws.length > 0);
    assert.deepEqual(b, a);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
