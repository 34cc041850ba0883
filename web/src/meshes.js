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
  maxInsertionPoints: 2 ** 16,
  maxDepthLevels: 2 ** 21 - 1, // kMaxDepthLevels
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

// SceneMeshes::depth_denominator from the stated depth_bits (the writers
// write 2 + log2 D): 0 when it names no usable mapping.
function depthDenominator(bits) {
  return bits >= 2 && bits <= 62 ? 2 ** (bits - 2) : 0;
}

// The highest depth level the draws' z values use (depth_levels_of_draws).
function levelsOfDraws(draws, denominator) {
  if (denominator < 2) return 0;
  let top = 0;
  for (const d of draws) for (let k = 2; k < d.vertices.length; k += VERTEX_FLOATS) if (d.vertices[k] > top) top = d.vertices[k];
  return Math.ceil((top * denominator) / 2);
}

// src/io/mesh_common.h's check_depth_levels: the stated depth_levels covers
// the draws' levels and fits the mapping, so sprites go above them.
function checkDepthLevels(name, m) {
  const stated = m.stats.depthLevels ?? 0;
  const bits = m.stats.depthBits ?? 0;
  const den = depthDenominator(bits);
  const most = den >= 2 ? Math.min(limits.maxDepthLevels, den / 2) : limits.maxDepthLevels;
  if (stated > most)
    throw new DepthcullError(`${name}: stats depth_levels ${stated} is more than the depth mapping resolves (${most} levels for depth_bits ${bits}; kMaxDepthLevels)`);
  const used = levelsOfDraws(m.draws, den);
  if (stated < used) throw new DepthcullError(`${name}: stats depth_levels ${stated} is lower than the ${used} levels its draws' z values use`);
}

// The last draw not in the blend pass (-1: none), which insertionPointProblem
// takes so that checking every point is one pass over the draws, not one
// per point (65,536 points over 131,072 draws took 21 s).
function lastNonBlendDraw(draws) {
  for (let d = draws.length - 1; d >= 0; --d) if (draws[d].pass !== 'blend') return d;
  return -1;
}

// src/io/mesh_common.h's insertion_point_problem: why point k cannot be
// drawn at, as [field, problem], or null. `lastNonBlend`: lastNonBlendDraw(m.draws).
function insertionPointProblem(m, k, lastNonBlend) {
  const p = m.insertionPoints[k];
  const prev = k ? m.insertionPoints[k - 1] : null;
  const elements = m.stats.elements ?? 0;
  const levels = m.stats.depthLevels ?? 0;
  if (p.element > elements) return ['element', `element ${p.element} is past the scene's ${elements} elements (stats elements)`];
  if (prev && p.element < prev.element) return ['element', `element ${p.element} is before the previous point's (points go in element order)`];
  if (p.levels < 0 || p.levels > limits.maxDepthLevels) return ['levels', `levels ${p.levels} is outside 0..${limits.maxDepthLevels}`];
  if (depthDenominator(m.stats.depthBits ?? 0) < 2) return ['first_level', 'insertion points need depth values (stats depth_bits names no depth mapping)'];
  if (p.firstLevel < 0 || p.firstLevel > levels - p.levels)
    return ['first_level', `levels ${p.firstLevel} + ${p.levels} are not inside the ${levels} depth levels of stats depth_levels`];
  if (prev && p.firstLevel < prev.firstLevel + prev.levels) return ['first_level', `first_level ${p.firstLevel} overlaps the previous point's levels`];
  if (p.blendDraw > m.draws.length) return ['blend_draw', `blend_draw ${p.blendDraw} is past the ${m.draws.length} draws`];
  if (prev && p.blendDraw < prev.blendDraw) return ['blend_draw', `blend_draw ${p.blendDraw} is before the previous point's`];
  if (p.blendDraw <= lastNonBlend) {
    // The first such draw from blendDraw on, as the C++ reader names it
    // (walked once: the point is refused).
    let d = p.blendDraw;
    while (m.draws[d].pass === 'blend') ++d;
    return ['blend_draw', `blend_draw ${p.blendDraw} is not in the blend pass (draw ${d} is opaque)`];
  }
  return null;
}

// src/io/mesh_common.h's insertion_levels_problem: no static vertex lies in
// a point's reserved levels (sprites there would tie in the depth test).
function insertionLevelsProblem(m) {
  const points = m.insertionPoints;
  const den = depthDenominator(m.stats.depthBits ?? 0);
  if (!points.length || den < 2) return null;
  for (let d = 0; d < m.draws.length; ++d) {
    const v = m.draws[d].vertices;
    for (let k = 2; k < v.length; k += VERTEX_FLOATS) {
      const level = Math.ceil(v[k] * (den / 2)) - 1;
      // The last point starting at or below the level: the points' first
      // levels ascend (insertionPointProblem checked them), so a binary
      // search, as the C++ reader's upper_bound (a scan per vertex took
      // 233 s on a 40 MB file).
      let lo = 0, hi = points.length;
      while (lo < hi) {
        const mid = (lo + hi) >>> 1;
        if (points[mid].firstLevel <= level) lo = mid + 1;
        else hi = mid;
      }
      const i = lo - 1;
      if (i >= 0 && level < points[i].firstLevel + points[i].levels)
        return `draw ${d} vertex ${(k - 2) / VERTEX_FLOATS} has depth level ${level}, reserved by insertion point ${i}`;
    }
  }
  return null;
}

function readInsertionPointsJson(name, doc, out) {
  if (!('insertion_points' in doc)) return;
  const points = array(name, doc.insertion_points, 'insertion_points', limits.maxInsertionPoints);
  const lastNonBlend = lastNonBlendDraw(out.draws);
  for (let k = 0; k < points.length; ++k) {
    const where = at('insertion_points', k);
    object(name, points[k], where);
    const p = {
      element: integer(name, field(name, points[k], where, 'element'), at(where, 'element'), Number.MAX_SAFE_INTEGER),
      levels: integer(name, field(name, points[k], where, 'levels'), at(where, 'levels'), limits.maxDepthLevels),
      firstLevel: integer(name, field(name, points[k], where, 'first_level'), at(where, 'first_level'), limits.maxDepthLevels),
      blendDraw: integer(name, field(name, points[k], where, 'blend_draw'), at(where, 'blend_draw'), 2 ** 32 - 1),
    };
    out.insertionPoints.push(p);
    const problem = insertionPointProblem(out, k, lastNonBlend);
    if (problem) fail(name, at(where, problem[0]), problem[1]);
  }
  const problem = insertionLevelsProblem(out);
  if (problem) fail(name, 'insertion_points', problem);
}

/**
 * The meshes JSON text (or its parsed value) as
 * `{viewport, depthTest, filter, images, draws, stats, animations, animated,
 * insertionPoints}` (points `{element, levels, firstLevel, blendDraw}`);
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
  const out = { viewport, depthTest, filter, images, draws, stats: 'stats' in doc ? readStats(name, doc.stats) : {}, animations: [], animated: [], insertionPoints: [] };
  readAnimations(name, doc, out);
  checkDepthLevels(name, out);
  readInsertionPointsJson(name, doc, out);
  return out;
}

/**
 * Either form: an ArrayBuffer / Uint8Array starting with "DCMESH" is the
 * binary form, anything else JSON text.
 */
export function parseMeshes(data, options = {}) {
  const bytes = data instanceof ArrayBuffer ? new Uint8Array(data) : ArrayBuffer.isView(data) ? new Uint8Array(data.buffer, data.byteOffset, data.byteLength) : null;
  if (bytes) {
    if (isBinaryMeshes(bytes)) return parseMeshesBinary(bytes, options);
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


const MAGIC = [0x44, 0x43, 0x4d, 0x45, 0x53, 0x48, 0, 0]; // "DCMESH\0\0"

/** Whether the bytes start with the binary form's magic (is_binary_meshes). */
export function isBinaryMeshes(bytes) {
  return bytes.length >= 8 && MAGIC.every((b, i) => bytes[i] === b);
}

// The C++ reader's Reader: little-endian fields at `pos`, every failure
// "NAME: byte N: what" at the field's offset from the file's start.
class ByteReader {
  constructor(bytes, name) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.name = name;
    this.pos = 0;
  }
  fail(at, what) {
    throw new DepthcullError(`${this.name}: byte ${at}: ${what}`);
  }
  left() {
    return this.bytes.length - this.pos;
  }
  need(n, what) {
    if (this.left() < n) this.fail(this.pos, `the file ends inside ${what}`);
  }
  take(n, what) {
    this.need(n, what);
    const at = this.pos;
    this.pos += n;
    return at;
  }
  u8(what) {
    return this.view.getUint8(this.take(1, what));
  }
  u16(what) {
    return this.view.getUint16(this.take(2, what), true);
  }
  u32(what) {
    return this.view.getUint32(this.take(4, what), true);
  }
  i32(what) {
    return this.view.getInt32(this.take(4, what), true);
  }
  i64(what) {
    return this.view.getBigInt64(this.take(8, what), true);
  }
  u64(what) {
    return this.view.getBigUint64(this.take(8, what), true);
  }
  f64(what) {
    return this.view.getFloat64(this.take(8, what), true);
  }
  finite(what) {
    const at = this.pos;
    const v = this.f64(what);
    if (!Number.isFinite(v)) this.fail(at, `${what} is not a finite number`);
    return v;
  }
  size(what, max) {
    const at = this.pos;
    const v = this.i32(what);
    if (v < 0 || v > max) this.fail(at, `${what} ${v} is outside 0..${max}`);
    return v;
  }
  str(what) {
    const at = this.pos;
    const n = this.u32(what);
    if (n > limits.maxStringBytes) this.fail(at, `${what} is longer than ${limits.maxStringBytes} bytes`);
    const start = this.take(n, what);
    return new TextDecoder().decode(this.bytes.subarray(start, start + n));
  }
  pad4(what) {
    while (this.pos % 4) if (this.u8(what) !== 0) this.fail(this.pos - 1, `${what} padding is not zero`);
  }
}

const MIN_IMAGE_BYTES = 16; // two empty strings and the sizes
const DRAW_HEADER_BYTES = 16;
const COLOUR_KEYED = 1 << 24;
const SOLID_FILL = 1 << 25;
const hex = (key) => (key & 0xffffff).toString(16).padStart(6, '0');

function readBinaryHeader(r, out) {
  if (!isBinaryMeshes(r.bytes)) r.fail(0, 'not a depthcull binary meshes file (no "DCMESH" magic)');
  r.pos = 8;
  const version = r.u32('the header');
  if (version !== 1) r.fail(8, `format version ${version} is not supported (expected 1)`);
  const flags = r.u32('the header');
  if (flags & ~31)
    r.fail(12, `unknown flags ${flags} (bit 0 depth_test, bit 1 colour keys, bit 2 linear filtering, bit 3 animations and bit 4 insertion points are defined)`);
  out.depthTest = Boolean(flags & 1);
  out.filter = flags & 4 ? 'linear' : 'nearest';
  const x = r.finite('viewport x');
  const y = r.finite('viewport y');
  out.viewport = { x, y, width: r.size('viewport width', INT32_MAX), height: r.size('viewport height', INT32_MAX) };
  const countsAt = r.pos;
  const images = r.u32('the header');
  const draws = r.u32('the header');
  if (images > limits.maxImages) r.fail(countsAt, `more than ${limits.maxImages} images`);
  if (draws > limits.maxDraws) r.fail(countsAt + 4, `more than ${limits.maxDraws} draws`);
  for (const key of ['elements', 'drawCalls', 'triangles', 'depthLevels', 'depthBits', 'graphEdges']) {
    const at = r.pos;
    const v = r.i64('the header');
    if (v < 0n) r.fail(at, 'a negative stats count');
    out.stats[key] = Number(v);
  }
  const secondsAt = r.pos;
  out.stats.seconds = r.finite('stats seconds');
  if (out.stats.seconds < 0) r.fail(secondsAt, 'negative stats seconds');
  const left = r.left();
  if (Math.floor(left / MIN_IMAGE_BYTES) < images || Math.floor((left - images * MIN_IMAGE_BYTES) / DRAW_HEADER_BYTES) < draws)
    r.fail(countsAt, `${images} images and ${draws} draws do not fit in the ${left} bytes left`);
  return { flags, images, draws };
}

function readBinaryImage(r, colourKeys, baseUrl) {
  const id = r.str('an image id');
  const path = r.str('an image path');
  r.pad4('an image entry');
  const img = { id, path, width: r.size('image width', limits.maxImageSide), height: r.size('image height', limits.maxImageSide) };
  img.url = resolvePath(baseUrl, path);
  if (colourKeys) {
    const at = r.pos;
    const key = r.u32('an image colour key');
    // One encoding per value: a word with neither bit is 0.
    if (key & ~(COLOUR_KEYED | SOLID_FILL | 0xffffff) || (key & COLOUR_KEYED && key & SOLID_FILL) || (!(key & (COLOUR_KEYED | SOLID_FILL)) && key))
      r.fail(at, `colour key ${key} has unknown bits`);
    if (key & SOLID_FILL) {
      if (path) r.fail(at, 'a solid fill image names a path');
      img.fill = hex(key);
      img.url = '';
    }
    if (key & COLOUR_KEYED) img.trans = hex(key);
  }
  return img;
}

function readBinaryDraw(r, imageCount, totals) {
  const at = r.pos;
  const image = r.u32('a draw header');
  if (image >= imageCount) r.fail(at, `draw names image ${image} of ${imageCount}`);
  const pass = r.u8('a draw header');
  if (pass > 1) r.fail(at + 4, `unknown pass ${pass} (0 opaque, 1 blend)`);
  const blend = r.u8('a draw header');
  if (blend > 3) r.fail(at + 5, `unknown blend ${blend} (0 alpha, 1 add, 2 multiply, 3 opaque)`);
  if (r.u16('a draw header') !== 0) r.fail(at + 6, 'reserved field is not 0');
  const vertexCount = r.u32('a draw header');
  const indexCount = r.u32('a draw header');
  if (vertexCount > limits.maxVertices - totals.vertices) r.fail(at + 8, `more than ${limits.maxVertices} vertices in all draws`);
  if (indexCount > limits.maxIndices - totals.indices) r.fail(at + 12, `more than ${limits.maxIndices} indices in all draws`);
  if (indexCount % 3) r.fail(at + 12, `index count ${indexCount} is not a multiple of 3 (triangles)`);
  const payload = vertexCount * VERTEX_FLOATS * 4 + indexCount * 4;
  if (payload > r.left()) r.fail(at + 8, `${vertexCount} vertices and ${indexCount} indices do not fit in the ${r.left()} bytes left`);
  totals.vertices += vertexCount;
  totals.indices += indexCount;
  // Copied out (the file's offsets need not be 4-aligned in memory): typed
  // arrays a renderer uploads as they are.
  const verticesAt = r.pos;
  const vertices = new Float32Array(vertexCount * VERTEX_FLOATS);
  for (let k = 0; k < vertices.length; ++k) {
    vertices[k] = r.view.getFloat32(verticesAt + 4 * k, true);
    const problem = vertexProblem(k, vertices[k]);
    if (problem) r.fail(verticesAt + 4 * k, `vertex ${Math.floor(k / VERTEX_FLOATS)} value ${k % VERTEX_FLOATS} ${problem}`);
  }
  r.pos += vertices.length * 4;
  const indicesAt = r.pos;
  const indices = new Uint32Array(indexCount);
  for (let k = 0; k < indexCount; ++k) {
    indices[k] = r.view.getUint32(indicesAt + 4 * k, true);
    if (indices[k] >= vertexCount) r.fail(indicesAt + 4 * k, `index ${indices[k]} is not below the draw's vertex count ${vertexCount}`);
  }
  r.pos += indexCount * 4;
  return { image, pass: pass === 0 ? 'opaque' : 'blend', blend: BLENDS[blend], vertices, indices };
}

function readBinaryAnimations(r, out) {
  const draws = out.draws.length;
  const at = r.pos;
  const count = r.u32('the animation count');
  if (count === 0) r.fail(at, 'flags bit 3 (animations) is set but the animation count is 0');
  if (count > limits.maxAnimations) r.fail(at, `more than ${limits.maxAnimations} animations`);
  const FRAME = 24;
  const RUN = 12;
  if (Math.floor(r.left() / (4 + FRAME)) < count || Math.floor((r.left() - count * (4 + FRAME)) / 4) < draws)
    r.fail(at, `${count} animations and the runs of ${draws} draws do not fit in the ${r.left()} bytes left`);
  for (let i = 0; i < count; ++i) {
    const framesAt = r.pos;
    const frames = r.u32('an animation');
    if (frames === 0) r.fail(framesAt, `animation ${i} has no frames`);
    if (frames > limits.maxAnimationFrames) r.fail(framesAt, `more than ${limits.maxAnimationFrames} frames in an animation`);
    if (Math.floor(r.left() / FRAME) < frames) r.fail(framesAt, `${frames} frames do not fit in the ${r.left()} bytes left`);
    const anim = { frames: [] };
    for (let k = 0; k < frames; ++k) {
      const frameAt = r.pos;
      const image = r.u32('an animation frame');
      if (image >= out.images.length) r.fail(frameAt, `frame names image ${image} of ${out.images.length}`);
      const rect = ['frame x', 'frame y', 'frame width', 'frame height'].map((w) => r.size(w, limits.maxImageSide));
      if (rect[2] <= 0 || rect[3] <= 0) r.fail(frameAt + 12, 'an empty frame rect');
      if (k && (rect[2] !== anim.frames[0].rect[2] || rect[3] !== anim.frames[0].rect[3])) r.fail(frameAt + 12, `frame ${k} is not the size of frame 0`);
      anim.frames.push({ image, rect, duration: r.size('frame duration', INT32_MAX) });
    }
    out.animations.push(anim);
  }
  for (let d = 0; d < draws; ++d) {
    const runsAt = r.pos;
    const runs = r.u32("a draw's animated runs");
    if (Math.floor(r.left() / RUN) < runs || r.left() - runs * RUN < (draws - d - 1) * 4)
      r.fail(runsAt, `${runs} animated runs of draw ${d} do not fit in the ${r.left()} bytes left`);
    const vertices = out.draws[d].vertices.length / VERTEX_FLOATS;
    for (let k = 0; k < runs; ++k) {
      const runAt = r.pos;
      const firstVertex = r.u32('an animated run');
      const vertexCount = r.u32('an animated run');
      const animation = r.u32('an animated run');
      if (vertexCount === 0 || firstVertex + vertexCount > vertices)
        r.fail(runAt, `run of vertices ${firstVertex} + ${vertexCount} is not inside draw ${d}'s ${vertices}`);
      if (animation >= out.animations.length) r.fail(runAt + 8, `run names animation ${animation} of ${out.animations.length}`);
      out.animated.push({ draw: d, firstVertex, vertexCount, animation });
    }
  }
}

const POINT_FIELD_OFFSETS = { element: 0, levels: 8, first_level: 16, blend_draw: 24 };

function readBinaryInsertionPoints(r, out) {
  const at = r.pos;
  const count = r.u32('the insertion point count');
  if (count === 0) r.fail(at, 'flags bit 4 (insertion points) is set but the insertion point count is 0');
  if (count > limits.maxInsertionPoints) r.fail(at, `more than ${limits.maxInsertionPoints} insertion points`);
  if (Math.floor(r.left() / 32) < count) r.fail(at, `${count} insertion points do not fit in the ${r.left()} bytes left`);
  const lastNonBlend = lastNonBlendDraw(out.draws);
  for (let k = 0; k < count; ++k) {
    const pointAt = r.pos;
    const element = r.u64('an insertion point');
    const levels = r.i64('an insertion point');
    const firstLevel = r.i64('an insertion point');
    const blendDraw = r.u32('an insertion point');
    if (r.u32('an insertion point') !== 0) r.fail(pointAt + 28, 'insertion point reserved field is not 0');
    if (element > 0x7fffffffffffffffn) r.fail(pointAt, `insertion point element ${element} is past the scene's elements`);
    // Values past 2^53 are far outside every range checked below, so the
    // rounding of Number() changes no verdict (the message may round).
    out.insertionPoints.push({ element: Number(element), levels: Number(levels), firstLevel: Number(firstLevel), blendDraw });
    const problem = insertionPointProblem(out, k, lastNonBlend);
    if (problem) r.fail(pointAt + POINT_FIELD_OFFSETS[problem[0]], `insertion point ${k}: ${problem[1]}`);
  }
  const problem = insertionLevelsProblem(out);
  if (problem) r.fail(at, problem);
}

/**
 * The binary form (docs/mesh-format.md; src/io/mesh_binary_reader.cpp),
 * checked as the C++ reader checks it, every count against the bytes left
 * before allocating; the same object as parseMeshesJson. Errors:
 * "NAME: byte N: what".
 */
export function parseMeshesBinary(data, { name = 'meshes', baseUrl } = {}) {
  const bytes = data instanceof ArrayBuffer ? new Uint8Array(data) : new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const r = new ByteReader(bytes, name);
  const out = { viewport: null, depthTest: false, filter: 'nearest', images: [], draws: [], stats: {}, animations: [], animated: [], insertionPoints: [] };
  const { flags, images, draws } = readBinaryHeader(r, out);
  for (let i = 0; i < images; ++i) out.images.push(readBinaryImage(r, Boolean(flags & 2), baseUrl));
  // Bit 1 is set exactly when some image has a key or a fill (the writer's rule).
  if (flags & 2 && !out.images.some((img) => img.trans !== undefined || img.fill !== undefined))
    r.fail(12, 'flags bit 1 (colour keys) is set but no image has a colour key or fill');
  const totals = { vertices: 0, indices: 0 };
  for (let i = 0; i < draws; ++i) out.draws.push(readBinaryDraw(r, images, totals));
  if (flags & 8) readBinaryAnimations(r, out);
  checkDepthLevels(name, out);
  if (flags & 16) readBinaryInsertionPoints(r, out);
  if (r.left()) r.fail(r.pos, `${r.left()} bytes after the ${flags & 16 ? 'insertion points' : flags & 8 ? 'animations' : 'last draw'}`);
  return out;
}
