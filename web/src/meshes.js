// Reads the meshes `depthcull optimize` writes (docs/mesh-format.md), JSON
// or binary, into typed arrays a renderer uploads as they are. Errors are one
// line worded as the CLI's readers word them (src/io/mesh_json_reader.cpp,
// src/io/mesh_binary_reader.cpp): "NAME: draws[3].indices[7]: must be an
// integer in 0..11", so a web developer sees what `depthcull` would say.
import { DepthcullError } from './index.js';

// include/depthcull/io.h: the readers' limits, checked before allocating.
export const limits = Object.freeze({
  maxImages: 2 ** 16,
  maxDraws: 2 ** 24,
  maxVertices: 2 ** 25, // all draws together
  maxIndices: 3 * 2 ** 25, // all draws together
  maxStringBytes: 2 ** 16,
  maxImageSide: 16384,
  maxAnimations: 2 ** 20,
  maxAnimationFrames: 2 ** 16,
});

const VERTEX_FLOATS = 9;
const FLT_MAX = 3.4028234663852886e38;
const INT32_MAX = 2147483647;
const BLENDS = ['alpha', 'add', 'multiply', 'opaque'];

function fail(name, where, what) {
  throw new DepthcullError(`${name}: ${where}: ${what}`);
}

function at(where, key) {
  if (typeof key === 'number') return `${where}[${key}]`;
  return where ? `${where}.${key}` : key;
}

function isObject(v) {
  return v !== null && typeof v === 'object' && !Array.isArray(v);
}

function field(name, obj, where, key) {
  if (!Object.prototype.hasOwnProperty.call(obj, key)) fail(name, where || 'top level', `missing "${key}"`);
  return obj[key];
}

function object(name, v, where) {
  if (!isObject(v)) fail(name, where, 'must be an object');
  return v;
}

function array(name, v, where, max) {
  if (!Array.isArray(v)) fail(name, where, 'must be an array');
  if (v.length > max) fail(name, where, `has more than ${max} entries`);
  return v;
}

function number(name, v, where) {
  if (typeof v !== 'number') fail(name, where, 'must be a number');
  if (!Number.isFinite(v)) fail(name, where, 'must be finite');
  return v;
}

// JSON.parse cannot tell 1 from 1.0 (the C++ reader refuses 1.0 here): a
// whole number is accepted in either spelling.
function integer(name, v, where, max) {
  if (typeof v === 'number' && Number.isInteger(v) && v >= 0 && v <= max) return v;
  fail(name, where, `must be an integer in 0..${max}`);
}

function string(name, v, where) {
  if (typeof v !== 'string') fail(name, where, 'must be a string');
  // UTF-8 bytes, as the C++ limit counts them; a UTF-16 length is at most that.
  if (v.length > limits.maxStringBytes || new TextEncoder().encode(v).length > limits.maxStringBytes)
    fail(name, where, `is longer than ${limits.maxStringBytes} bytes`);
  return v;
}

function colourKey(name, v, where) {
  const s = string(name, v, where);
  if (!/^#?[0-9a-fA-F]{6}$/.test(s)) fail(name, where, `"${s}" is not a colour "rrggbb"`);
  return s.replace('#', '').toLowerCase();
}

// Paths in the file are relative to the meshes file's directory (URL or
// path prefix); absolute ones are kept.
function resolvePath(baseUrl, path) {
  if (!path || !baseUrl) return path;
  try {
    return new URL(path, baseUrl).href;
  } catch {
    return path;
  }
}

function readImage(name, v, where, baseUrl) {
  object(name, v, where);
  const img = {
    id: string(name, field(name, v, where, 'id'), at(where, 'id')),
    path: string(name, field(name, v, where, 'path'), at(where, 'path')),
    width: integer(name, field(name, v, where, 'width'), at(where, 'width'), limits.maxImageSide),
    height: integer(name, field(name, v, where, 'height'), at(where, 'height'), limits.maxImageSide),
  };
  img.url = resolvePath(baseUrl, img.path);
  if ('trans' in v) img.trans = colourKey(name, v.trans, at(where, 'trans'));
  if ('fill' in v) {
    img.fill = colourKey(name, v.fill, at(where, 'fill'));
    img.path = '';
    img.url = '';
  }
  return img;
}

function vertexProblem(k, f) {
  if (!Number.isFinite(f)) return 'is not a finite number';
  if (k % VERTEX_FLOATS === 2 && !(f >= 0 && f <= 1)) return 'is a depth (z) outside [0, 1]';
  return null;
}

function readDraw(name, v, where, ids, totals) {
  object(name, v, where);
  const id = string(name, field(name, v, where, 'image'), at(where, 'image'));
  if (!ids.has(id)) fail(name, at(where, 'image'), `unknown image id "${id}"`);
  const pass = string(name, field(name, v, where, 'pass'), at(where, 'pass'));
  if (pass !== 'opaque' && pass !== 'blend') fail(name, at(where, 'pass'), `unknown pass "${pass}" (expected opaque or blend)`);
  const blend = string(name, field(name, v, where, 'blend'), at(where, 'blend'));
  if (!BLENDS.includes(blend)) fail(name, at(where, 'blend'), `unknown blend "${blend}" (expected alpha, add, multiply or opaque)`);

  const vw = at(where, 'vertices');
  const vs = array(name, field(name, v, where, 'vertices'), vw, limits.maxVertices * VERTEX_FLOATS);
  if (vs.length % VERTEX_FLOATS) fail(name, vw, `has ${vs.length} numbers, not 9 per vertex`);
  const count = vs.length / VERTEX_FLOATS;
  if (count > limits.maxVertices - totals.vertices) fail(name, vw, `more than ${limits.maxVertices} vertices in all draws`);
  totals.vertices += count;
  const vertices = new Float32Array(vs.length);
  for (let k = 0; k < vs.length; ++k) {
    const d = number(name, vs[k], at(vw, k));
    if (Math.abs(d) > FLT_MAX) fail(name, at(vw, k), 'is outside the range of a float');
    vertices[k] = d;
    const problem = vertexProblem(k, vertices[k]);
    if (problem) fail(name, at(vw, k), problem);
  }

  const iw = at(where, 'indices');
  const is = array(name, field(name, v, where, 'indices'), iw, limits.maxIndices);
  if (is.length % 3) fail(name, iw, `has ${is.length} indices, not a multiple of 3 (triangles)`);
  if (is.length > limits.maxIndices - totals.indices) fail(name, iw, `more than ${limits.maxIndices} indices in all draws`);
  totals.indices += is.length;
  const indices = new Uint32Array(is.length);
  for (let k = 0; k < is.length; ++k) {
    if (count === 0) fail(name, at(iw, k), 'an index into a draw without vertices');
    indices[k] = integer(name, is[k], at(iw, k), count - 1);
  }
  return { image: ids.get(id), pass, blend, vertices, indices };
}

function readAnimations(name, doc, out) {
  if ('animations' in doc) {
    const animations = array(name, doc.animations, 'animations', limits.maxAnimations);
    for (let i = 0; i < animations.length; ++i) {
      const where = at('animations', i);
      object(name, animations[i], where);
      const fws = at(where, 'frames');
      const frames = array(name, field(name, animations[i], where, 'frames'), fws, limits.maxAnimationFrames);
      if (frames.length === 0) fail(name, fws, 'has no frames');
      const anim = { frames: [] };
      for (let k = 0; k < frames.length; ++k) {
        const fw = at(fws, k);
        object(name, frames[k], fw);
        if (out.images.length === 0) fail(name, at(fw, 'image'), 'names an image but there are none');
        const image = integer(name, field(name, frames[k], fw, 'image'), at(fw, 'image'), out.images.length - 1);
        const rect = field(name, frames[k], fw, 'rect');
        if (!Array.isArray(rect) || rect.length !== 4) fail(name, at(fw, 'rect'), 'must be [x, y, w, h]');
        const r = rect.map((x, j) => integer(name, x, at(at(fw, 'rect'), j), limits.maxImageSide));
        if (r[2] === 0 || r[3] === 0) fail(name, at(fw, 'rect'), 'is empty');
        if (k > 0 && (r[2] !== anim.frames[0].rect[2] || r[3] !== anim.frames[0].rect[3]))
          fail(name, at(fw, 'rect'), "is not the size of frame 0's");
        const duration = integer(name, field(name, frames[k], fw, 'duration'), at(fw, 'duration'), INT32_MAX);
        anim.frames.push({ image, rect: r, duration });
      }
      out.animations.push(anim);
    }
  }
  if ('animated' in doc) {
    const runs = array(name, doc.animated, 'animated', limits.maxVertices);
    for (let i = 0; i < runs.length; ++i) {
      const where = at('animated', i);
      object(name, runs[i], where);
      if (out.draws.length === 0) fail(name, at(where, 'draw'), 'names a draw but there are none');
      const draw = integer(name, field(name, runs[i], where, 'draw'), at(where, 'draw'), out.draws.length - 1);
      const vertices = out.draws[draw].vertices.length / VERTEX_FLOATS;
      if (vertices === 0) fail(name, at(where, 'draw'), 'names a draw without vertices');
      const first = integer(name, field(name, runs[i], where, 'first_vertex'), at(where, 'first_vertex'), vertices - 1);
      const count = integer(name, field(name, runs[i], where, 'vertex_count'), at(where, 'vertex_count'), vertices - first);
      if (count === 0) fail(name, at(where, 'vertex_count'), 'must not be 0');
      if (out.animations.length === 0) fail(name, at(where, 'animation'), 'names an animation but there are none');
      const animation = integer(name, field(name, runs[i], where, 'animation'), at(where, 'animation'), out.animations.length - 1);
      if (out.animated.length && draw < out.animated[out.animated.length - 1].draw) fail(name, at(where, 'draw'), 'runs are not in draw order');
      out.animated.push({ draw, firstVertex: first, vertexCount: count, animation });
    }
  }
}

function readStats(name, v) {
  object(name, v, 'stats');
  const stats = {};
  const keys = { elements: 'elements', draw_calls: 'drawCalls', triangles: 'triangles', depth_levels: 'depthLevels', depth_bits: 'depthBits', graph_edges: 'graphEdges' };
  for (const [key, js] of Object.entries(keys)) if (key in v) stats[js] = integer(name, v[key], at('stats', key), Number.MAX_SAFE_INTEGER);
  if ('seconds' in v) {
    stats.seconds = number(name, v.seconds, 'stats.seconds');
    if (stats.seconds < 0) fail(name, 'stats.seconds', 'must not be negative');
  }
  return stats;
}

/**
 * The meshes JSON text (or its parsed value) as
 * `{viewport, depthTest, filter, images, draws, stats, animations, animated}`;
 * `draws[i].vertices` a Float32Array of 9 floats per vertex,
 * `draws[i].indices` a Uint32Array, `draws[i].image` an index into `images`.
 * `name` starts every error message (the file's name or URL); `baseUrl`
 * resolves the image paths (`images[i].url`).
 */
export function parseMeshesJson(text, { name = 'meshes', baseUrl } = {}) {
  let doc = text;
  if (typeof text === 'string') {
    try {
      doc = JSON.parse(text);
    } catch (e) {
      // V8 says where ("at position N", in UTF-16 units) except at the end.
      const m = /position (\d+)/.exec(e.message);
      const end = /end of JSON input/.test(e.message) ? text.length : null;
      const at16 = m ? Number(m[1]) : end;
      const where = at16 !== null ? `byte ${new TextEncoder().encode(text.slice(0, at16)).length}: ` : '';
      throw new DepthcullError(`${name}: ${where}not valid JSON (${e.message.split('\n')[0]})`);
    }
  }
  if (!isObject(doc)) fail(name, 'top level', 'expected a JSON object with "images" and "draws"');
  const vp = object(name, field(name, doc, '', 'viewport'), 'viewport');
  const viewport = {
    x: number(name, field(name, vp, 'viewport', 'x'), 'viewport.x'),
    y: number(name, field(name, vp, 'viewport', 'y'), 'viewport.y'),
    width: integer(name, field(name, vp, 'viewport', 'width'), 'viewport.width', INT32_MAX),
    height: integer(name, field(name, vp, 'viewport', 'height'), 'viewport.height', INT32_MAX),
  };
  const depthTest = field(name, doc, '', 'depth_test');
  if (typeof depthTest !== 'boolean') fail(name, 'depth_test', 'must be true or false');
  let filter = 'nearest'; // absent in files written before it was
  if ('filter' in doc) {
    if (doc.filter !== 'nearest' && doc.filter !== 'linear') fail(name, 'filter', 'must be "nearest" or "linear"');
    filter = doc.filter;
  }
  const imagesIn = array(name, field(name, doc, '', 'images'), 'images', limits.maxImages);
  const images = [];
  const ids = new Map(); // a draw names the first entry with its id
  for (let i = 0; i < imagesIn.length; ++i) {
    images.push(readImage(name, imagesIn[i], at('images', i), baseUrl));
    if (!ids.has(images[i].id)) ids.set(images[i].id, i);
  }
  const drawsIn = array(name, field(name, doc, '', 'draws'), 'draws', limits.maxDraws);
  const totals = { vertices: 0, indices: 0 };
  const draws = [];
  for (let i = 0; i < drawsIn.length; ++i) draws.push(readDraw(name, drawsIn[i], at('draws', i), ids, totals));
  const out = { viewport, depthTest, filter, images, draws, stats: 'stats' in doc ? readStats(name, doc.stats) : {}, animations: [], animated: [] };
  readAnimations(name, doc, out);
  return out;
}

/**
 * Either form: an ArrayBuffer / Uint8Array starting with "DCMESH" is the
 * binary form, anything else JSON text.
 */
export function parseMeshes(data, options = {}) {
  const bytes = data instanceof ArrayBuffer ? new Uint8Array(data) : ArrayBuffer.isView(data) ? new Uint8Array(data.buffer, data.byteOffset, data.byteLength) : null;
  if (bytes) {
    if (bytes.length >= 6 && String.fromCharCode(...bytes.subarray(0, 6)) === 'DCMESH') return parseMeshesBinary(bytes, options);
    return parseMeshesJson(new TextDecoder().decode(bytes), options);
  }
  return parseMeshesJson(data, options);
}

/** Fetches and parses a meshes file; image URLs resolve against its URL. */
export async function loadMeshes(url, { name = String(url), fetch: f = globalThis.fetch } = {}) {
  let response;
  try {
    response = await f(url);
  } catch (e) {
    throw new DepthcullError(`${name}: cannot read (${e.message})`);
  }
  if (!response.ok) throw new DepthcullError(`${name}: cannot read (HTTP ${response.status})`);
  const baseUrl = new URL(url, globalThis.location?.href ?? 'file:///').href;
  return parseMeshes(await response.arrayBuffer(), { name, baseUrl });
}

export function parseMeshesBinary(bytes, { name = 'meshes' } = {}) {
  void bytes;
  throw new DepthcullError(`${name}: the binary meshes form is not read in JavaScript yet; write JSON (optimize -o X.meshes.json)`);
}
