// depthcull in JavaScript: the C++ core (src/common .. src/cost) built as
// WebAssembly by scripts/build-wasm, behind a small API. Runs in browsers
// and in Node >= 18; no framework dependency.
//
//   import { loadDepthcull } from 'depthcull';
//   const depthcull = await loadDepthcull();
//   const { boundary, opaque } = depthcull.analyzeImage(imageData);
//
// Errors are thrown as DepthcullError with the one-line message the CLI
// prints for the same mistake (the option named as JavaScript spells it).

import { wasiImports } from './wasi.js';
import { FrameAssembler } from './frames.js';

export class DepthcullError extends Error {
  constructor(message) {
    super(message);
    this.name = 'DepthcullError';
  }
}

const FILTERS = { nearest: 0, linear: 1 };
const OPAQUE_METHODS = { fast: 1, grow: 2, paper: 0 }; // listed in the CLI's order
// The CLI's defaults (paper 2.1, 2.2: MAX_BOUNDARY_VERTICES = 10,
// MAX_OPAQUE_POLYGONS = 4, MIN_OPAQUE_COVERAGE = 0.75, MIN_OPAQUE_AREA = 64).
const DEFAULTS = Object.freeze({
  maxVertices: 10,
  split: true,
  filter: 'nearest',
  opaque: 'fast',
  maxOpaque: 4,
  minCoverage: 0.75,
  minOpaqueArea: 64,
});
const OPTION_NAMES = new Set([...Object.keys(DEFAULTS), 'rect', 'name']);
const STAT_NAMES = [
  'nontransparent_texels', 'opaque_texels', 'boundary_area', 'bbox_area',
  'boundary_vertices', 'opaque_area', 'opaque_covered_texels', 'opaque_coverage',
];

// io::load_scene_image's fill images: kFillImageSide square.
const FILL_IMAGE_SIDE = 16;

// A colour key or fill, "rrggbb" (or "#rrggbb"), as the scene reader reads it.
function colourKey(where, v) {
  if (typeof v !== 'string' || !/^#?[0-9a-fA-F]{6}$/.test(v)) throw new DepthcullError(`${where}: colour key '${v}' is not RRGGBB hex`);
  return parseInt(v.replace('#', ''), 16);
}

// A cost profile's terms in docs/cost-model.md's order (what dcw_scene_reconstruct takes).
const PROFILE_TERMS = [
  'frame_us', 'clear_color_ns_per_pixel', 'clear_depth_ns_per_pixel', 'draw_call_us', 'texture_switch_us', 'triangle_us',
  'triangle_perimeter_ns_per_pixel', 'fragment_opaque_ns', 'fragment_blend_ns', 'fragment_rejected_ns',
];

// `target`: '' (none), a built-in profile's name, or a profile `depthcull
// calibrate` wrote (JSON text or object), checked as the CLI's
// pipeline::profile_from_json checks a file, with its words.
function targetProfile(target) {
  if (target === '' || target === undefined || target === null) return { targetName: '', profile: null };
  let doc = target;
  if (typeof target === 'string') {
    if (!target.trimStart().startsWith('{')) return { targetName: target, profile: null };
    try {
      doc = JSON.parse(target);
    } catch (e) {
      throw new DepthcullError(`target: not valid JSON (${e.message.split('\n')[0]})`);
    }
  }
  const name = 'target';
  if (doc === null || typeof doc !== 'object' || Array.isArray(doc)) throw new DepthcullError(`${name}: a profile is a JSON object`);
  if (doc.depthcull_profile !== 1) throw new DepthcullError(`${name}: "depthcull_profile": expected 1 (the profile format version)`);
  for (const k of ['name', 'renderer', 'source'])
    if (k in doc && typeof doc[k] !== 'string') throw new DepthcullError(`${name}: "${k}": expected a string`);
  // Each term read once: what was checked is what the wasm gets.
  const terms = PROFILE_TERMS.map((k) => {
    if (!(k in doc)) throw new DepthcullError(`${name}: "${k}" missing (every term of the model is required)`);
    const v = doc[k];
    if (typeof v !== 'number') throw new DepthcullError(`${name}: "${k}": expected a number`);
    if (!Number.isFinite(v) || v < 0) throw new DepthcullError(`${name}: "${k}": ${JSON.stringify(v)} is not a finite number >= 0`);
    return v;
  });
  const knownKeys = new Set(['depthcull_profile', 'name', 'renderer', 'source', 'wall', 'min_opaque_area', ...PROFILE_TERMS]);
  for (const k of Object.keys(doc)) if (!knownKeys.has(k)) throw new DepthcullError(`${name}: "${k}": unknown key`);
  return { targetName: doc.name || 'profile', profile: terms };
}

// The insertion points to reserve: `scene.insertionPoints` outright, else
// optimize's: the scene's insertion_points and options.insertAt (sorted,
// once each), `insertionLevels` levels each (default 1024 with insertAt,
// else 0: none).
// Returned as a Float64Array of (element, levels) pairs: every value read
// (getters run) and the count checked before the wasm allocates for them.
function insertionPoints(scene, o) {
  const fieldOf = (p, key) => (typeof p?.[key] === 'number' ? p[key] : NaN); // the wasm words the error
  if (scene.insertionPoints !== undefined) {
    const points = scene.insertionPoints;
    if (!Array.isArray(points)) throw new DepthcullError('insertionPoints: must be an array of {element, levels}');
    if (points.length > MAX_INSERTION_POINTS)
      throw new DepthcullError(`insertionPoints.length: Value ${points.length} not in range 0 to ${MAX_INSERTION_POINTS}`);
    const out = new Float64Array(points.length * 2);
    for (let k = 0; k < points.length; ++k) {
      const p = points[k];
      out[2 * k] = fieldOf(p, 'element');
      out[2 * k + 1] = fieldOf(p, 'levels');
    }
    return out;
  }
  const listed = scene.insertion_points ?? [];
  const insertAt = o.insertAt ?? [];
  if (!Array.isArray(listed) || !Array.isArray(insertAt))
    throw new DepthcullError('insertion_points, insertAt: must be arrays of element indices');
  if (listed.length + insertAt.length > MAX_INSERTION_POINTS)
    throw new DepthcullError(`insertion_points, insertAt: ${listed.length + insertAt.length} points, more than ${MAX_INSERTION_POINTS}`);
  const at = [...listed, ...insertAt];
  if (at.some((v) => !Number.isInteger(v) || v < 0)) throw new DepthcullError('insertion_points, insertAt: must be arrays of element indices');
  const levels = o.insertionLevels ?? (insertAt.length ? 1024 : 0);
  if (levels === 0) return new Float64Array(0);
  const sorted = [...new Set(at)].sort((a, b) => a - b);
  const out = new Float64Array(sorted.length * 2);
  sorted.forEach((element, k) => out.set([element, typeof levels === 'number' ? levels : NaN], 2 * k));
  return out;
}

// The wasm's limits (src/wasm/wasm_api.cpp; include/depthcull/limits.h,
// image.h), checked here before anything is allocated for the input.
const MAX_IMAGE_SIDE = 16384; // kMaxImageSide
const MAX_IMAGE_TEXELS = 2 ** 28; // kMaxImageTexels
const MAX_DECODED_BYTES = 2 ** 31; // kMaxDecodedBytes
const MAX_SCENE_IMAGES = 2 ** 16; // kMaxSceneImages
const MAX_SCENE_ELEMENTS = 2 ** 22; // kMaxSceneElementsWasm (also animations)
const MAX_ANIMATION_FRAMES = 2 ** 16; // kMaxAnimationFrames
const MAX_INSERTION_POINTS = 2 ** 16;

// dcw_scene_add_image's (and dcw_analyze's) size checks, worded as the wasm
// words them, made before any pixel is copied: null, or the problem.
function sizeProblem(width, height) {
  for (const [key, v] of [['width', width], ['height', height]]) {
    if (typeof v !== 'number') return `${key}: Value ${String(v)} is not a number`;
    if (!Number.isInteger(v)) return `${key}: Value ${v} is not an integer`;
    if (v < 1 || v > MAX_IMAGE_SIDE) return `${key}: Value ${v} not in range 1 to ${MAX_IMAGE_SIDE}`;
  }
  if (width * height > MAX_IMAGE_TEXELS) return `${width}x${height} image exceeds ${MAX_IMAGE_TEXELS} texels`;
  return null;
}

function mib(bytes) {
  return `${Math.ceil(bytes / 2 ** 20)} MiB`;
}

// An element's or a frame's numbers: `v` an array of exactly `keys.length`
// numbers (or undefined: `fallback`); `objectForm` also takes {x, y, width,
// height} as analyzeImage's rect. Every value read once, here.
function numbers(where, field, v, keys, fallback, objectForm = false) {
  if (v === undefined) return fallback;
  const shape = objectForm ? `[${keys.join(', ')}] or {${keys.join(', ')}}` : `[${keys.join(', ')}]`;
  let values;
  if (Array.isArray(v)) {
    if (v.length !== keys.length) throw new DepthcullError(`${where}: ${field} must be ${shape}: ${keys.length} numbers, not ${v.length}`);
    values = keys.map((_, k) => [`${field}[${k}]`, v[k]]);
  } else if (objectForm && v !== null && typeof v === 'object') {
    values = keys.map((key) => [`${field}.${key}`, v[key]]);
  } else {
    throw new DepthcullError(`${where}: ${field} must be ${shape}`);
  }
  return values.map(([name, x]) => {
    if (typeof x !== 'number') throw new DepthcullError(`${where}: ${name}: Value ${String(x)} is not a number`);
    return x;
  });
}

const isNode = typeof process !== 'undefined' && !!process.versions?.node;

async function wasmBytes(source) {
  if (source instanceof WebAssembly.Module) return source;
  if (source instanceof ArrayBuffer || ArrayBuffer.isView(source)) return source;
  if (typeof Response !== 'undefined' && source instanceof Response) return source.arrayBuffer();
  const url = source ?? new URL('../dist/depthcull.wasm', import.meta.url);
  if (isNode && (url instanceof URL ? url.protocol === 'file:' : !/^[a-z]+:\/\//i.test(String(url)))) {
    const { readFile } = await import('node:fs/promises');
    try {
      return await readFile(url);
    } catch (e) {
      throw new DepthcullError(`${url instanceof URL ? url.pathname : url}: cannot read depthcull.wasm (${e.code ?? e.message}; run scripts/build-wasm)`);
    }
  }
  const response = await fetch(url);
  if (!response.ok) throw new DepthcullError(`${url}: cannot fetch depthcull.wasm (HTTP ${response.status})`);
  return response.arrayBuffer();
}

/**
 * Loads depthcull.wasm: by default web/dist/depthcull.wasm next to this
 * package (read from disk in Node, fetched in a browser); or from `wasm`: a
 * URL, the bytes, a fetch Response or a compiled WebAssembly.Module.
 */
export async function loadDepthcull({ wasm, log = (line) => console.error(line) } = {}) {
  const bytes = await wasmBytes(wasm);
  const module = bytes instanceof WebAssembly.Module ? bytes : await WebAssembly.compile(bytes);
  const instance = await WebAssembly.instantiate(module, imports(log, () => instance.exports.memory));
  return new Depthcull(module, instance, log);
}

function imports(log, memory) {
  return wasiImports(memory, log);
}

function choice(name, value, table) {
  if (Object.hasOwn(table, value)) return table[value];
  throw new DepthcullError(`${name}: '${value}' is not one of ${Object.keys(table).join(', ')}`);
}

// Numbers go to the wasm as doubles, which checks them (integers, ranges):
// anything else is refused here rather than converted.
function number(name, value) {
  if (typeof value === 'number') return value;
  if (typeof value === 'boolean') return value ? 1 : 0;
  throw new DepthcullError(`${name}: Value ${String(value)} is not a number`);
}

export class Depthcull {
  #module;
  #instance;
  #log;
  // Counts the instances #trapped made: a FrameAssembler keeps the one it
  // was made in, as its handle and addresses mean nothing in a later one.
  #generation = 0;

  constructor(module, instance, log) {
    this.#module = module;
    this.#instance = instance;
    this.#log = log;
    instance.exports._initialize();
  }

  get #exports() {
    if (!this.#instance) throw new DepthcullError('depthcull: this instance stopped after an earlier WebAssembly error; call loadDepthcull() again');
    return this.#instance.exports;
  }

  #cString(ptr) {
    const memory = new Uint8Array(this.#exports.memory.buffer);
    let end = ptr;
    while (memory[end] !== 0) ++end;
    return new TextDecoder().decode(memory.subarray(ptr, end));
  }

  #withString(text, fn) {
    const bytes = new TextEncoder().encode(text);
    const ptr = this.#exports.dcw_alloc(bytes.length + 1);
    const view = new Uint8Array(this.#exports.memory.buffer, ptr, bytes.length + 1);
    view.set(bytes);
    view[bytes.length] = 0;
    try {
      return fn(ptr);
    } finally {
      this.#exports.dcw_free(ptr);
    }
  }

  // A trap (out of memory: operator new aborts without exceptions) leaves the
  // instance in an unknown state; the next call gets a fresh one.
  // Where a browser refuses a synchronous instance on its main thread, the
  // object stays unusable and says so (loadDepthcull makes a new one).
  #trapped(name, error) {
    const log = this.#log;
    ++this.#generation;
    try {
      let instance;
      instance = new WebAssembly.Instance(this.#module, imports(log, () => instance.exports.memory));
      instance.exports._initialize();
      this.#instance = instance;
    } catch (e) {
      this.#instance = null;
    }
    return new DepthcullError(`${name}: the analysis stopped in WebAssembly (${error.message}): out of memory, or a bug (please report it)`);
  }

  /**
   * Boundary polygons (paper 2.1) and opaque polygons (paper 2.2) of an
   * RGBA8 image (ImageData or any {width, height, data}), as `depthcull
   * analyze` computes them with the same options.
   */
  // analyzeImage's arguments checked: the wasm call's numbers.
  #prepare(image, options) {
    for (const key of Object.keys(options))
      if (!OPTION_NAMES.has(key)) throw new DepthcullError(`analyzeImage: unknown option '${key}' (known: ${[...OPTION_NAMES].join(', ')})`);
    const o = { ...DEFAULTS, ...options };
    const name = o.name === undefined ? 'image' : String(o.name);
    if (image === null || typeof image !== 'object') throw new DepthcullError(`${name}: not an image (expected {width, height, data})`);
    const { width, height, data } = image;
    if (!(data instanceof Uint8Array || data instanceof Uint8ClampedArray))
      throw new DepthcullError(`${name}: data must be a Uint8Array or Uint8ClampedArray of RGBA8 texels`);
    const rect = o.rect ?? { x: 0, y: 0, width, height };
    if (rect === null || typeof rect !== 'object') throw new DepthcullError(`${name}: rect must be {x, y, width, height}`);
    const args = [
      number('width', width), number('height', height),
      number('rect.x', rect.x), number('rect.y', rect.y), number('rect.width', rect.width), number('rect.height', rect.height),
      number('maxVertices', o.maxVertices), number('split', o.split),
      choice('filter', o.filter, FILTERS), choice('opaque', o.opaque, OPAQUE_METHODS),
      number('maxOpaque', o.maxOpaque), number('minCoverage', o.minCoverage), number('minOpaqueArea', o.minOpaqueArea),
    ];
    // The size is checked before anything is copied; a width or height that
    // is not a valid side is left for the wasm to word (pixels stay null).
    const validSides = Number.isInteger(width) && Number.isInteger(height) && width > 0 && height > 0;
    if (validSides && width <= 16384 && height <= 16384 && data.length !== width * height * 4)
      throw new DepthcullError(`${name}: data has ${data.length} bytes, a ${width}x${height} RGBA8 image has ${width * height * 4}`);
    return { name, data, rect, args, copy: validSides && data.length === width * height * 4 };
  }

  analyzeImage(image, options = {}) {
    const { name, data, rect, args, copy } = this.#prepare(image, options);
    const ex = this.#exports;
    let pixels = 0;
    try {
      if (copy) {
        pixels = ex.dcw_alloc(data.length);
        new Uint8Array(ex.memory.buffer, pixels, data.length).set(data);
      }
      const status = this.#withString(name, (namePtr) => ex.dcw_analyze(pixels, ...args, namePtr));
      if (status !== 0) throw new DepthcullError(this.#cString(ex.dcw_last_error()));
      return this.#readAnalysis(rect);
    } catch (e) {
      if (e instanceof WebAssembly.RuntimeError) throw this.#trapped(name, e);
      throw e;
    } finally {
      if (pixels && this.#instance?.exports === ex) ex.dcw_free(pixels);
    }
  }

  /**
   * A FrameAssembler (src/frames.js): moving sprites depth-culled every
   * frame, alone or at the insertion points of static meshes.
   */
  createFrameAssembler(options = {}) {
    return new FrameAssembler(
      {
        exports: () => this.#exports,
        generation: () => this.#generation,
        error: () => new DepthcullError(this.#cString(this.#exports.dcw_last_error())),
        prepare: (image, o) => this.#prepare(image, o),
        withString: (text, fn) => this.#withString(text, fn),
        trapped: (name, e) => this.#trapped(name, e),
      },
      options,
    );
  }

  /**
   * Reconstructs a scene in the wasm as `depthcull optimize` does (paper
   * 2.3; with `target`, optimize --target's choice per image). `scene` is
   * the scene JSON (`depthcull import MAP.tmx -o SCENE.json` writes it) with
   * each image's decoded pixels added:
   * {viewport: {x, y, width, height}, filter, images: [{id, path, trans,
   * fill, width, height, data}], elements: [{image (id or index), rect
   * [x, y, w, h] (default the whole image), transform [a, b, c, d, e, f],
   * color [r, g, b, a], blend, animation}], animations: [{frames: [{image,
   * rect, duration}]}], insertion_points: [element index, ...]}.
   * An image's `data` is its file's RGBA8 texels as decoded (the colour key
   * `trans` "rrggbb" is applied here, as the CLI applies it); a `fill`
   * image needs none. Images with the same `path` (and key) share analyses
   * and meshes, as in the CLI. `insertionPoints: [{element, levels}]`
   * gives the insertion points outright instead of `insertion_points`.
   * options: analyzeImage's (maxVertices, split, opaque, maxOpaque,
   * minCoverage, minOpaqueArea), `opaquePolygons` (false: optimize
   * --no-opaque), `insertAt` (element indices, optimize --insert-at),
   * `insertionLevels` (optimize --insertion-levels: levels reserved at each
   * of insertion_points and insertAt; default 1024 with insertAt, else 0:
   * none), `target`: a built-in profile name (llvmpipe, ipad1) or a
   * profile `depthcull calibrate` wrote (its JSON text or parsed object).
   * Returns meshes as parseMeshes does (MeshRenderer.setMeshes takes them),
   * and with a target `target: {predictedMs, meshesOnlyMs, overpaintMs,
   * elementsDropped, elementsOpaque, elementsReverted}`. The wasm has no
   * Clipper: with a target it does not clip hidden parts (optimize with
   * --no-clip-hidden), so on a profile that prices rejected
   * fragments its meshes may differ from the CLI's (README).
   */
  reconstructScene(scene, options = {}) {
    const known = new Set([...Object.keys(DEFAULTS), 'opaquePolygons', 'target', 'insertAt', 'insertionLevels']);
    for (const key of Object.keys(options))
      if (!known.has(key)) throw new DepthcullError(`reconstructScene: unknown option '${key}' (known: ${[...known].join(', ')})`);
    const o = { ...DEFAULTS, opaquePolygons: true, target: '', ...options, filter: scene?.filter ?? 'nearest' };
    if (scene === null || typeof scene !== 'object' || !Array.isArray(scene.images) || !Array.isArray(scene.elements))
      throw new DepthcullError('reconstructScene: scene must be {viewport, images, elements}');
    const { targetName, profile } = targetProfile(o.target);
    const points = insertionPoints(scene, o);
    const sceneImages = scene.images, sceneElements = scene.elements;
    const animationsIn = scene.animations ?? [];
    if (!Array.isArray(animationsIn)) throw new DepthcullError('animations: must be an array of {frames}');
    // Counts before anything is read or allocated for them (a sparse array
    // is a few bytes of JavaScript for any length).
    if (sceneImages.length > MAX_SCENE_IMAGES)
      throw new DepthcullError(`images: ${sceneImages.length} images, more than ${MAX_SCENE_IMAGES} (kMaxSceneImages)`);
    if (sceneElements.length > MAX_SCENE_ELEMENTS)
      throw new DepthcullError(`elements: ${sceneElements.length} elements, more than the ${MAX_SCENE_ELEMENTS} the wasm takes`);
    if (animationsIn.length > MAX_SCENE_ELEMENTS)
      throw new DepthcullError(`animations: ${animationsIn.length} animations, more than the ${MAX_SCENE_ELEMENTS} the wasm takes`);
    const ids = new Map();
    for (let i = 0; i < sceneImages.length; ++i) {
      const id = sceneImages[i]?.id;
      if (typeof id === 'string' && !ids.has(id)) ids.set(id, i);
    }
    const imageIndex = (v, where) => {
      if (typeof v === 'number') return v;
      if (typeof v === 'string') {
        if (!ids.has(v)) throw new DepthcullError(`${where}: unknown image id "${v}"`);
        return ids.get(v);
      }
      return NaN;
    };
    // Every image checked, in order, before the first is copied: its size
    // (a 16385x4096 image is refused before its 268 MB are copied), its
    // bytes, and the decoded images together against kMaxDecodedBytes, as
    // the CLI sums the headers before it decodes (here each image counts:
    // each holds its own copy in the wasm).
    const inputs = [];
    let decoded = 0;
    for (let i = 0; i < sceneImages.length; ++i) {
      const img = sceneImages[i];
      if (img === null || typeof img !== 'object') throw new DepthcullError(`image ${i}: must be an object`);
      const name = String(img.id ?? `images[${i}]`);
      const fill = img.fill === undefined ? -1 : colourKey(`${name}: fill`, img.fill);
      const trans = img.trans === undefined ? -1 : colourKey(`${name}: trans`, img.trans);
      const path = fill >= 0 ? '' : String(img.path ?? '');
      let { width, height, data } = img;
      if (fill >= 0) {
        width = height = FILL_IMAGE_SIDE;
        data = null;
      } else {
        if (!(data instanceof Uint8Array || data instanceof Uint8ClampedArray))
          throw new DepthcullError(`${name}: data must be a Uint8Array or Uint8ClampedArray of RGBA8 texels`);
        const problem = sizeProblem(width, height);
        if (problem) throw new DepthcullError(`${name}: ${problem}`);
        if (data.length !== width * height * 4)
          throw new DepthcullError(`${name}: data has ${data.length} bytes, a ${width}x${height} RGBA8 image has ${width * height * 4}`);
      }
      decoded += width * height * 4;
      if (decoded > MAX_DECODED_BYTES)
        throw new DepthcullError(`${name}: ${width}x${height} brings the decoded images to ${mib(decoded)}, over the limit of ${mib(MAX_DECODED_BYTES)} (kMaxDecodedBytes)`);
      const out = { id: name, path, url: '', width, height };
      if (trans >= 0) out.trans = img.trans.replace('#', '').toLowerCase();
      if (fill >= 0) out.fill = img.fill.replace('#', '').toLowerCase();
      inputs.push({ name, path, width, height, data, trans, fill, out });
    }
    // Animations as plain numbers too: no getter runs (and maybe grows or
    // reuses wasm memory) while a view of it is held.
    const animations = [];
    const animationRows = [];
    for (let i = 0; i < animationsIn.length; ++i) {
      const a = animationsIn[i];
      const frames = Array.isArray(a?.frames) ? a.frames : [];
      if (frames.length > MAX_ANIMATION_FRAMES)
        throw new DepthcullError(`animation ${i}: frames.length: Value ${frames.length} not in range 1 to ${MAX_ANIMATION_FRAMES}`);
      const rows = new Float64Array(frames.length * 6);
      const list = [];
      for (let k = 0; k < frames.length; ++k) {
        const f = frames[k];
        const where = `animation ${i}: frames[${k}]`;
        const image = imageIndex(f?.image, where);
        const r = numbers(where, 'rect', f?.rect, ['x', 'y', 'width', 'height'], [NaN, NaN, NaN, NaN], true);
        const duration = f?.duration ?? 0;
        rows.set([image, ...r, typeof duration === 'number' ? duration : NaN], 6 * k);
        list.push({ image, rect: r, duration });
      }
      animationRows.push(rows);
      animations.push({ frames: list });
    }
    const vp = scene.viewport ?? {};
    const viewport = { x: vp.x ?? 0, y: vp.y ?? 0, width: vp.width, height: vp.height };
    const args = [
      number('viewport.x', viewport.x), number('viewport.y', viewport.y), number('viewport.width', viewport.width), number('viewport.height', viewport.height),
      choice('filter', o.filter, FILTERS), number('maxVertices', o.maxVertices), number('split', o.split), choice('opaque', o.opaque, OPAQUE_METHODS),
      number('maxOpaque', o.maxOpaque), number('minCoverage', o.minCoverage), number('minOpaqueArea', o.minOpaqueArea), number('opaquePolygons', o.opaquePolygons),
    ];

    const ex = this.#exports;
    const live = () => this.#instance?.exports === ex;
    const fail = () => new DepthcullError(this.#cString(ex.dcw_last_error()));
    let handle = 0;
    // Copies `values` into linear memory for `fn(pointer)`, freed after.
    const withDoubles = (values, fn) => {
      const ptr = ex.dcw_alloc(Math.max(1, values.length) * 8);
      try {
        new Float64Array(ex.memory.buffer, ptr, values.length).set(values);
        return fn(ptr);
      } finally {
        if (live()) ex.dcw_free(ptr);
      }
    };
    try {
      if (ex.dcw_scene_new() !== 0) throw fail();
      handle = new Float64Array(ex.memory.buffer, ex.dcw_result(), 1)[0];
      for (const { name, path, width, height, data, trans, fill } of inputs) {
        const pixels = data ? ex.dcw_alloc(data.length) : 0;
        try {
          if (data) new Uint8Array(ex.memory.buffer, pixels, data.length).set(data);
          const status = this.#withString(name, (namePtr) =>
            this.#withString(path, (pathPtr) => ex.dcw_scene_add_image(handle, pixels, width, height, namePtr, pathPtr, trans, fill)));
          if (status !== 0) throw fail();
        } finally {
          if (pixels && live()) ex.dcw_free(pixels);
        }
      }
      for (const rows of animationRows)
        if (withDoubles(rows, (ptr) => ex.dcw_scene_add_animation(handle, ptr, rows.length / 6)) !== 0) throw fail();
      // Elements one at a time (a few million would be hundreds of MB as
      // rows); their numbers are arguments, so no view of memory is held
      // while an element's getters run.
      const BLEND = { alpha: 0, add: 1, multiply: 2, opaque: 3 };
      for (let i = 0; i < sceneElements.length; ++i) {
        const e = sceneElements[i];
        if (e === null || typeof e !== 'object') throw new DepthcullError(`element ${i}: must be an object`);
        const where = `element ${i}`;
        const image = imageIndex(e.image, where);
        const img = inputs[image]?.out;
        const rect = numbers(where, 'rect', e.rect, ['x', 'y', 'width', 'height'], [0, 0, img?.width ?? 0, img?.height ?? 0], true);
        const t = numbers(where, 'transform', e.transform, ['a', 'b', 'c', 'd', 'e', 'f'], [1, 0, 0, 1, 0, 0]);
        const c = numbers(where, 'color', e.color, ['r', 'g', 'b', 'a'], [1, 1, 1, 1]);
        const blend = e.blend ?? 'alpha';
        if (!Object.hasOwn(BLEND, blend)) throw new DepthcullError(`${where}: blend '${blend}' is not one of alpha, add, multiply, opaque`);
        const animation = e.animation ?? -1;
        if (!live()) throw new DepthcullError('reconstructScene: a call made from an element\'s getter stopped the WebAssembly instance');
        if (ex.dcw_scene_add_element(handle, image, ...rect, ...t, ...c, BLEND[blend], typeof animation === 'number' ? animation : NaN) !== 0)
          throw fail();
      }
      const status = withDoubles(points, (pointsPtr) =>
        withDoubles(profile ?? [], (profilePtr) =>
          this.#withString(targetName, (targetPtr) =>
            ex.dcw_scene_reconstruct(handle, ...args, pointsPtr, points.length / 2, targetPtr, profile ? profilePtr : 0))));
      if (status !== 0) throw fail();
      return this.#readMeshes(viewport, inputs.map((i) => i.out), animations, o.filter, Boolean(targetName));
    } catch (e) {
      if (e instanceof WebAssembly.RuntimeError) throw this.#trapped('reconstructScene', e);
      throw e;
    } finally {
      if (handle && live()) ex.dcw_scene_free(handle);
    }
  }

  #readMeshes(vp, images, animations, filter, targeted) {
    const ex = this.#exports;
    const r = new Float64Array(ex.memory.buffer, ex.dcw_result(), ex.dcw_result_size());
    let i = 0;
    const stats = {};
    for (const key of ['elements', 'drawCalls', 'triangles', 'depthLevels', 'depthBits', 'graphEdges']) stats[key] = r[i++];
    const depthTest = r[i++] !== 0;
    const draws = [];
    const BLENDS = ['alpha', 'add', 'multiply', 'opaque'];
    for (let n = r[i++]; n > 0; --n) {
      const image = r[i++], pass = r[i++] === 0 ? 'opaque' : 'blend', blend = BLENDS[r[i++]];
      const nv = r[i++], ni = r[i++];
      const vertices = Float32Array.from(r.subarray(i, i + nv * 9));
      i += nv * 9;
      const indices = Uint32Array.from(r.subarray(i, i + ni));
      i += ni;
      draws.push({ image, pass, blend, vertices, indices });
    }
    const out = {
      viewport: vp,
      depthTest, filter, images, draws, stats, animations: [], animated: [], insertionPoints: [],
    };
    for (let n = r[i++]; n > 0; --n, i += 4) out.insertionPoints.push({ element: r[i], levels: r[i + 1], firstLevel: r[i + 2], blendDraw: r[i + 3] });
    for (let n = r[i++]; n > 0; --n, i += 4) out.animated.push({ draw: r[i], firstVertex: r[i + 1], vertexCount: r[i + 2], animation: r[i + 3] });
    // As the meshes files: the animations only where a draw shows one.
    if (out.animated.length) out.animations = animations;
    if (targeted) {
      const t = {};
      for (const key of ['predictedMs', 'meshesOnlyMs', 'overpaintMs', 'elementsDropped', 'elementsOpaque', 'elementsReverted']) t[key] = r[i++];
      out.target = t;
    }
    return out;
  }

  #readAnalysis(rect) {
    const ex = this.#exports;
    const r = new Float64Array(ex.memory.buffer, ex.dcw_result(), ex.dcw_result_size());
    let i = 0;
    const polygons = () => {
      const out = [];
      for (let count = r[i++]; count > 0; --count) {
        const polygon = [];
        for (let n = r[i++]; n > 0; --n, i += 2) polygon.push([r[i], r[i + 1]]);
        out.push(polygon);
      }
      return out;
    };
    const boundary = polygons();
    const opaque = polygons();
    const stats = {};
    for (const key of STAT_NAMES) stats[key] = r[i++];
    return { rect: { x: rect.x, y: rect.y, width: rect.width, height: rect.height }, boundary, opaque, stats };
  }
}
