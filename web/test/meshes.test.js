// Reading meshes files in JavaScript (src/meshes.js): a file the CLI wrote
// reads back with its numbers as float32, and bad files give one line
// worded as src/io/mesh_json_reader.cpp words it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

import { DepthcullError } from '../src/index.js';
import { parseMeshes, parseMeshesJson } from '../src/meshes.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const cli = process.env.DEPTHCULL_CLI ?? join(root, 'build', 'depthcull');

// Depth level 0 of depth_bits 10 (D = 256) draws at 1/D and 2/D.
const Z = 2 / 256;

// The smallest valid file, changed by each case.
function valid() {
  return {
    viewport: { x: 0, y: 0, width: 4, height: 4 },
    depth_test: true,
    filter: 'nearest',
    images: [{ id: 'a', path: 'a.png', width: 2, height: 2 }],
    draws: [{ image: 'a', pass: 'blend', blend: 'alpha', vertices: [0, 0, Z, 0, 0, 1, 1, 1, 1, 2, 0, Z, 1, 0, 1, 1, 1, 1, 0, 2, Z, 0, 1, 1, 1, 1, 1], indices: [0, 1, 2] }],
    stats: { elements: 1, draw_calls: 1, triangles: 1, depth_levels: 1, depth_bits: 10, graph_edges: 0, seconds: 0 },
  };
}

function message(doc) {
  try {
    parseMeshes(typeof doc === 'string' ? doc : JSON.stringify(doc), { name: 'bad.meshes.json' });
  } catch (e) {
    assert.ok(e instanceof DepthcullError, `${e.name}: ${e.message}`);
    assert.ok(!e.message.includes('\n'));
    return e.message;
  }
  assert.fail('no error');
}

const cases = [
  ['not JSON', '{"viewport": ', /^bad\.meshes\.json: byte 13: not valid JSON \(/],
  ['an array', '[]', 'bad.meshes.json: top level: expected a JSON object with "images" and "draws"'],
  ['no viewport', (d) => delete d.viewport, 'bad.meshes.json: top level: missing "viewport"'],
  ['depth_test a number', (d) => (d.depth_test = 1), 'bad.meshes.json: depth_test: must be true or false'],
  ['filter', (d) => (d.filter = 'cubic'), 'bad.meshes.json: filter: must be "nearest" or "linear"'],
  ['negative width', (d) => (d.images[0].width = -1), 'bad.meshes.json: images[0].width: must be an integer in 0..16384'],
  ['unknown image', (d) => (d.draws[0].image = 'b'), 'bad.meshes.json: draws[0].image: unknown image id "b"'],
  ['unknown pass', (d) => (d.draws[0].pass = 'late'), 'bad.meshes.json: draws[0].pass: unknown pass "late" (expected opaque or blend)'],
  ['unknown blend', (d) => (d.draws[0].blend = 'screen'), 'bad.meshes.json: draws[0].blend: unknown blend "screen" (expected alpha, add, multiply or opaque)'],
  ['8 floats', (d) => d.draws[0].vertices.pop(), 'bad.meshes.json: draws[0].vertices: has 26 numbers, not 9 per vertex'],
  ['z above 1', (d) => (d.draws[0].vertices[11] = 1.5), 'bad.meshes.json: draws[0].vertices[11]: is a depth (z) outside [0, 1]'],
  ['a string vertex', (d) => (d.draws[0].vertices[4] = '0'), 'bad.meshes.json: draws[0].vertices[4]: must be a number'],
  ['beyond float', (d) => (d.draws[0].vertices[0] = 1e39), 'bad.meshes.json: draws[0].vertices[0]: is outside the range of a float'],
  ['index out of range', (d) => (d.draws[0].indices[2] = 3), 'bad.meshes.json: draws[0].indices[2]: must be an integer in 0..2'],
  ['not triangles', (d) => d.draws[0].indices.push(0), 'bad.meshes.json: draws[0].indices: has 4 indices, not a multiple of 3 (triangles)'],
  ['negative seconds', (d) => (d.stats.seconds = -1), 'bad.meshes.json: stats.seconds: must not be negative'],
  ['depth levels below the draws', (d) => (d.stats.depth_levels = 0), 'bad.meshes.json: stats depth_levels 0 is lower than the 1 levels its draws\' z values use'],
  ['depth levels past the mapping', (d) => (d.stats.depth_levels = 200), 'bad.meshes.json: stats depth_levels 200 is more than the depth mapping resolves (128 levels for depth_bits 10; kMaxDepthLevels)'],
  ['insertion point not an object', (d) => (d.insertion_points = [1]), 'bad.meshes.json: insertion_points[0]: must be an object'],
  ['insertion point past the elements', (d) => (d.insertion_points = [{ element: 2, levels: 1, first_level: 1, blend_draw: 1 }]), "bad.meshes.json: insertion_points[0].element: element 2 is past the scene's 1 elements (stats elements)"],
  ['insertion point levels outside', (d) => (d.insertion_points = [{ element: 1, levels: 2, first_level: 1, blend_draw: 1 }]), 'bad.meshes.json: insertion_points[0].first_level: levels 1 + 2 are not inside the 2 depth levels of stats depth_levels'],
  ['insertion point on a static level', (d) => (d.insertion_points = [{ element: 0, levels: 1, first_level: 0, blend_draw: 0 }]), 'bad.meshes.json: insertion_points: draw 0 vertex 0 has depth level 0, reserved by insertion point 0'],
  ['insertion point blend draw', (d) => (d.insertion_points = [{ element: 1, levels: 1, first_level: 1, blend_draw: 2 }]), 'bad.meshes.json: insertion_points[0].blend_draw: blend_draw 2 is past the 1 draws'],
  ['insertion point missing key', (d) => (d.insertion_points = [{ element: 1, levels: 1, first_level: 1 }]), 'bad.meshes.json: insertion_points[0]: missing "blend_draw"'],
  ['animated draw', (d) => (d.animated = [{ draw: 1, first_vertex: 0, vertex_count: 1, animation: 0 }]), 'bad.meshes.json: animated[0].draw: must be an integer in 0..0'],
];

for (const [label, change, expected] of cases) {
  test(`bad meshes: ${label}`, () => {
    let text = change;
    if (typeof change === 'function') {
      const d = valid();
      if (label.startsWith('insertion point')) d.stats.depth_levels = 2;
      change(d);
      text = JSON.stringify(d);
    }
    const m = message(text);
    if (expected instanceof RegExp) assert.match(m, expected);
    else assert.equal(m, expected);
  });
}


test('the bundled example as the CLI writes it: draws and stats read back', { skip: !existsSync(cli) && `no CLI at ${cli}` }, () => {
  const dir = mkdtempSync(join(tmpdir(), 'dc-meshes-'));
  try {
    const out = join(dir, 'meadow.meshes.json');
    execFileSync(cli, ['optimize', join(root, 'examples/meadow.json'), '-o', out, '--no-timing'], { stdio: 'pipe' });
    const text = readFileSync(out, 'utf8');
    const doc = JSON.parse(text);
    const m = parseMeshesJson(text, { name: out });
    assert.equal(m.draws.length, doc.draws.length);
    let triangles = 0;
    m.draws.forEach((d, i) => {
      assert.deepEqual(Array.from(d.vertices), doc.draws[i].vertices.map(Math.fround));
      assert.deepEqual(Array.from(d.indices), doc.draws[i].indices);
      triangles += d.indices.length / 3;
    });
    assert.equal(triangles, m.stats.triangles);
    assert.deepEqual(m.viewport, doc.viewport);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
