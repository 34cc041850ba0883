// Moving sprites depth-culled every frame: include/depthcull/frame.h's
// FrameAssembler through the wasm (src/wasm/wasm_api.cpp's dcw_frame_*).
// Each frame's sprites, in painter's order, become an opaque pass (front to
// back, depth writes) and blend draws batched by texture where the overlap
// allows; with the insertion points of static meshes (optimize
// --insert-at), the sprites of point k go between the static layers.
//
// No per-frame allocation in the wasm after warm-up (its buffers keep their
// capacity), and none here while the frame's sizes stay the same: the
// sprites are written into one reused Float64Array of linear memory, and the
// frame's arrays are views of linear memory, made again only when a buffer
// moved or changed size. The views are valid until the next assemble().
import { DepthcullError } from './index.js';

const SPRITE_DOUBLES = 14; // image, animation, frame, a b c d e f, r g b a, blend
// The wasm's limits (src/wasm/wasm_api.cpp), checked before it allocates.
const MAX_SPRITES = 2 ** 21 - 1; // kMaxDepthLevels: sprites of one frame, all lists together
const MAX_POINTS = 2 ** 16; // insertion points
const MAX_ANIMATION_FRAMES = 2 ** 16;
// The scene elements' bounds (src/io/scene_json.cpp: kMaxCoordinate; colours 0..1).
const MAX_COORDINATE = 1e9;
const BLENDS = { alpha: 0, add: 1, multiply: 2, opaque: 3 };
const BLEND_NAMES = ['alpha', 'add', 'multiply', 'opaque'];
const FILTERS = { nearest: 0, linear: 1 };

function spriteError(message) {
  return new DepthcullError(`assemble: ${message}`);
}

export class FrameAssembler {
  #core;
  #handle = 0;
  #lists = 1; // sprite lists a frame takes: one without insertion points
  #points = false;
  #onTop = false; // static meshes without points: one list on top
  #input = null; // Float64Array view of dcw_frame_input's doubles
  #inputPtr = 0;
  #inputCap = -1;
  #frame = null;
  #views = {};
  #staging = new Float64Array(0); // a frame's input, read here before any wasm call
  #generation = 0; // core.generation() when made: the instance its handle lives in
  #busy = false; // reading assemble()'s sprites (their getters may call back)

  constructor(core, { opaquePass = true, filter = 'nearest' } = {}) {
    this.#core = core;
    this.#generation = core.generation();
    if (!Object.hasOwn(FILTERS, filter)) throw new DepthcullError(`filter: '${filter}' is not one of nearest, linear`);
    const ex = core.exports();
    if (ex.dcw_frame_new(opaquePass ? 1 : 0, FILTERS[filter]) !== 0) throw core.error();
    this.#handle = new Float64Array(ex.memory.buffer, ex.dcw_result(), 1)[0];
    this.#frame = {
      vertices: null, indices: null, draws: null, drawCount: 0, opaqueDraws: 0, points: null, pointCount: 0, depthTest: true,
      stats: { sprites: 0, drawCalls: 0, opaqueDraws: 0, triangles: 0, blendBatches: 0, overBudget: 0 },
    };
  }

  #ex() {
    if (!this.#handle) throw new DepthcullError('FrameAssembler: freed');
    if (this.#busy) throw new DepthcullError("FrameAssembler: called from a sprite's getter while assemble() reads the sprites");
    // After a trap the instance is a fresh one, where this handle is nothing
    // (or another assembler's).
    if (this.#core.generation() !== this.#generation) {
      this.#handle = 0;
      throw new DepthcullError('FrameAssembler: made before a WebAssembly error replaced the instance; make a new one (createFrameAssembler)');
    }
    return this.#core.exports();
  }

  #call(name, fn) {
    try {
      return fn();
    } catch (e) {
      // A trap makes a fresh instance, without this assembler's handle.
      if (e instanceof WebAssembly.RuntimeError) {
        this.#handle = 0;
        throw this.#core.trapped(name, e);
      }
      throw e;
    }
  }

  /**
   * A picture sprites show: `rect` ({x, y, width, height}, default the
   * whole image) of an RGBA8 texture (ImageData or {width, height, data}),
   * analysed with analyzeImage's options; `texture` is the number the
   * frame's draws name (the renderer's texture index). Returns its id.
   */
  addImage(image, { texture = 0, ...options } = {}) {
    const { name, data, args, copy } = this.#core.prepare(image, options);
    const ex = this.#ex();
    return this.#call(name, () => {
      let pixels = 0;
      try {
        if (copy) {
          pixels = ex.dcw_alloc(data.length);
          new Uint8Array(ex.memory.buffer, pixels, data.length).set(data);
        }
        const [width, height, ...rest] = args;
        const status = this.#core.withString(name, (namePtr) =>
          ex.dcw_frame_add_image(this.#handle, typeof texture === 'number' ? texture : NaN, pixels, width, height, ...rest, namePtr));
        if (status !== 0) throw this.#core.error();
        return new Float64Array(ex.memory.buffer, ex.dcw_result(), 1)[0];
      } finally {
        if (pixels && this.#core.exports() === ex) ex.dcw_free(pixels);
      }
    });
  }

  /** An animation: the picture ids it shows in turn. Returns its id. */
  addAnimation(ids) {
    if (!Array.isArray(ids)) throw new DepthcullError('addAnimation: expected an array of image ids');
    // The count before anything is allocated for it (a sparse array of any
    // length is a few bytes); the ids read before memory is touched.
    if (ids.length < 1 || ids.length > MAX_ANIMATION_FRAMES)
      throw new DepthcullError(`addAnimation: frames: Value ${ids.length} not in range 1 to ${MAX_ANIMATION_FRAMES}`);
    this.#ex();
    const values = Float64Array.from(ids, num);
    const ex = this.#ex();
    return this.#call('addAnimation', () => {
      const ptr = ex.dcw_alloc(values.length * 8);
      try {
        new Float64Array(ex.memory.buffer, ptr, values.length).set(values);
        if (ex.dcw_frame_add_animation(this.#handle, ptr, values.length) !== 0) throw this.#core.error();
        return new Float64Array(ex.memory.buffer, ex.dcw_result(), 1)[0];
      } finally {
        ex.dcw_free(ptr);
      }
    });
  }

  /**
   * Frames drawn with static meshes (parseMeshes' result): at their
   * insertion points (insertionPoints, stats.depthBits, depthTest), one
   * sprite list per point; meshes without points take one list, drawn on
   * top of the whole scene (the levels above stats.depthLevels, as a point
   * after the last element would reserve them). null: fully dynamic frames
   * again (sprite i at depth level i, no static meshes).
   */
  setStaticMeshes(meshes) {
    // Everything checked and read before the wasm call, and this object
    // changed only after it succeeded: a refused call changes nothing.
    // Each value read once (what was checked is what the wasm gets).
    let points = meshes?.insertionPoints ?? [];
    if (!Array.isArray(points)) throw new DepthcullError('setStaticMeshes: insertionPoints must be an array');
    const bits = meshes?.stats?.depthBits ?? 0;
    let n = points.length;
    let onTop = false;
    if (meshes && n === 0) {
      const top = bits >= 2 && bits <= 62 ? 2 ** (bits - 3) : 0; // D / 2 levels
      const first = meshes.stats?.depthLevels ?? 0;
      if (!(top - first >= 1)) throw new DepthcullError('setStaticMeshes: the meshes leave no depth level above them for sprites (stats depth_levels, depth_bits)');
      points = [{ levels: Math.min(top - first, 2 ** 21 - 1), firstLevel: first, blendDraw: meshes.draws?.length }];
      n = 1;
      onTop = true;
    }
    if (n > MAX_POINTS) throw new DepthcullError(`setInsertionPoints: insertionPoints.length: Value ${n} not in range 0 to ${MAX_POINTS}`);
    const values = new Float64Array(n * 3);
    for (let k = 0; k < n; ++k) {
      const p = points[k];
      values[3 * k] = num(p?.levels);
      values[3 * k + 1] = num(p?.firstLevel);
      values[3 * k + 2] = num(p?.blendDraw);
    }
    const depthBits = num(bits);
    const depthTest = meshes?.depthTest === false ? 0 : 1;
    const ex = this.#ex();
    this.#call('setStaticMeshes', () => {
      const ptr = ex.dcw_alloc(Math.max(1, values.length) * 8);
      try {
        new Float64Array(ex.memory.buffer, ptr, values.length).set(values);
        const status = ex.dcw_frame_set_points(this.#handle, ptr, n, depthBits, depthTest);
        if (status !== 0) throw this.#core.error();
      } finally {
        ex.dcw_free(ptr);
      }
    });
    this.#onTop = onTop;
    this.#points = n > 0;
    this.#lists = this.#points ? n : 1;
    this.#inputCap = -1; // dcw_frame_input's room is for a list count
  }

  /**
   * One frame. `sprites`: with insertion points an array of sprite lists
   * (list k at point k; fewer lists than points leave the rest empty),
   * without them one list. A sprite: {image} (an addImage id) or
   * {animation, frame}, `transform` [a, b, c, d, e, f] (screen = (a*u + c*v
   * + e, b*u + d*v + f), u, v texels of the picture) or `x, y` (a
   * translation), `color` [r, g, b, a] (default white), `blend` alpha, add,
   * multiply or opaque. `bounds` {x, y, width, height}: the world part the
   * camera shows (the overlap grid's extent).
   *
   * Returns the frame (the same object each call, its arrays views of
   * linear memory valid until the next call): vertices (9 floats each),
   * indices, draws (5 numbers each: texture, pass 0 opaque / 1 blend,
   * blend, first index, index count; drawCount of them, the first
   * opaqueDraws the opaque pass), points (3 each: static draw, first draw,
   * end draw: the point's blend draws go before that static draw), stats.
   */
  assemble(sprites, bounds) {
    this.#ex();
    // Every sprite is read (getters and Proxies run) into #staging before
    // the wasm is called or its memory viewed: a getter that grows memory
    // would detach a view, one that calls back into this assembler would
    // reuse its buffers, so such calls are refused while reading.
    this.#busy = true;
    let nl, need, b;
    try {
      // Lists, their lengths and sprites read once each (a Proxy may answer
      // differently the second time).
      const withPoints = this.#points && !this.#onTop;
      const lists = withPoints ? sprites : [sprites];
      const listError = () => spriteError(withPoints ? 'expected an array of sprite lists, one per insertion point' : 'expected an array of sprites');
      if (!Array.isArray(lists)) throw listError();
      nl = lists.length;
      if (nl > this.#lists) throw spriteError(`${nl} sprite lists but the meshes have ${this.#lists} insertion points`);
      const arrays = [];
      let total = 0;
      for (let k = 0; k < nl; ++k) {
        const list = lists[k];
        if (!Array.isArray(list)) throw listError();
        const n = list.length;
        arrays.push([list, n]);
        total += n;
      }
      // The documented limit, whatever the assembler did before (and
      // before anything is allocated for them).
      if (total > MAX_SPRITES) throw spriteError(`${total} sprites, more than the ${MAX_SPRITES} depth levels a frame has (kMaxDepthLevels)`);
      need = nl + total * SPRITE_DOUBLES;
      // Doubling, so frames that grow a little reallocate rarely.
      if (need > this.#staging.length)
        this.#staging = new Float64Array(Math.max(need, Math.min(2 * this.#staging.length, this.#lists + MAX_SPRITES * SPRITE_DOUBLES)));
      const input = this.#staging;
      let at = nl;
      let index = 0;
      for (let k = 0; k < nl; ++k) {
        const [list, n] = arrays[k];
        input[k] = n;
        for (let j = 0; j < n; ++j, ++index, at += SPRITE_DOUBLES) readSprite(input, at, list[j], index);
      }
      const bb = bounds ?? {};
      b = [num(bb.x ?? 0), num(bb.y ?? 0), num(bb.width), num(bb.height)];
    } finally {
      this.#busy = false;
    }
    const ex = this.#ex(); // a getter's call may have replaced the instance
    return this.#call('assemble', () => {
      if (need > this.#inputCap) {
        // Room to spare, so a frame of a few more sprites moves nothing
        // (at most the limit: the room never decides what is accepted).
        const total = (need - nl) / SPRITE_DOUBLES;
        const room = Math.min(Math.max(total * 2, 16), MAX_SPRITES);
        this.#inputPtr = ex.dcw_frame_input(this.#handle, this.#lists, room);
        if (!this.#inputPtr) throw this.#core.error();
        this.#inputCap = this.#lists + room * SPRITE_DOUBLES;
        this.#input = null;
      }
      // Memory growth detaches views: made again then.
      if (!this.#input || this.#input.buffer !== ex.memory.buffer) this.#input = new Float64Array(ex.memory.buffer, this.#inputPtr, this.#inputCap);
      this.#input.set(this.#staging.subarray(0, need));
      const status = ex.dcw_frame_assemble(this.#handle, nl, ...b);
      if (status !== 0) throw this.#core.error();
      return this.#read(ex);
    });
  }

  #view(key, Type, ptr, length, buffer) {
    const v = this.#views[key];
    if (v && v.buffer === buffer && v.byteOffset === ptr && v.length === length) return v;
    return (this.#views[key] = new Type(buffer, ptr, length));
  }

  #read(ex) {
    const buffer = ex.memory.buffer;
    const info = this.#view('info', Uint32Array, ex.dcw_frame_info(this.#handle), 16, buffer);
    const f = this.#frame;
    f.vertices = this.#view('vertices', Float32Array, info[0], info[1], buffer);
    f.indices = this.#view('indices', Uint32Array, info[2], info[3], buffer);
    f.draws = this.#view('draws', Uint32Array, info[4], info[5] * 5, buffer);
    f.drawCount = info[5];
    f.opaqueDraws = info[6];
    f.points = this.#view('points', Uint32Array, info[7], info[8] * 3, buffer);
    f.pointCount = info[8];
    f.depthTest = info[9] !== 0;
    const st = f.stats;
    st.sprites = info[10];
    st.drawCalls = info[11];
    st.opaqueDraws = info[12];
    st.triangles = info[13];
    st.blendBatches = info[14];
    st.overBudget = info[15];
    return f;
  }

  /** Frees the wasm side; the assembler cannot be used after. */
  free() {
    if (this.#busy) throw new DepthcullError("FrameAssembler: called from a sprite's getter while assemble() reads the sprites");
    // A handle of an earlier instance is not freed in the new one.
    if (this.#handle && this.#core.generation() === this.#generation) this.#core.exports().dcw_frame_free(this.#handle);
    this.#handle = 0;
    this.#staging = new Float64Array(0);
  }
}

function num(v) {
  return typeof v === 'number' ? v : NaN; // the wasm words the error
}

// Sprite `index` (all lists counted) into out[at ..]: each value read once
// and checked where the wasm would not word it: the transform and colour
// as scene elements' (src/io/scene_json.cpp: values within +-1e9,
// kMaxCoordinate; colours 0..1), so no vertex is Infinity.
function readSprite(out, at, s, index) {
  if (s === null || typeof s !== 'object') throw spriteError(`sprite ${index}: a sprite must be an object`);
  const animation = s.animation ?? -1;
  out[at] = animation >= 0 ? 0 : num(s.image);
  out[at + 1] = num(animation);
  out[at + 2] = num(s.frame ?? 0);
  const t = s.transform;
  if (t) {
    for (let k = 0; k < 6; ++k) out[at + 3 + k] = coordinate(index, `transform[${k}]`, t[k]);
  } else {
    out[at + 3] = 1;
    out[at + 4] = 0;
    out[at + 5] = 0;
    out[at + 6] = 1;
    out[at + 7] = coordinate(index, 'x', s.x ?? 0);
    out[at + 8] = coordinate(index, 'y', s.y ?? 0);
  }
  const c = s.color;
  for (let k = 0; k < 4; ++k) {
    const v = c ? c[k] : 1;
    if (!(typeof v === 'number' && v >= 0 && v <= 1)) throw spriteError(`sprite ${index}: color[${k}]: ${String(v)} is not in 0..1`);
    out[at + 9 + k] = v;
  }
  const blend = s.blend ?? 'alpha';
  if (!Object.hasOwn(BLENDS, blend)) throw spriteError(`sprite ${index}: blend '${blend}' is not one of alpha, add, multiply, opaque`);
  out[at + 13] = BLENDS[blend];
}

function coordinate(index, field, v) {
  if (!(typeof v === 'number' && Math.abs(v) <= MAX_COORDINATE))
    throw spriteError(`sprite ${index}: ${field}: ${String(v)} is not a finite number within +-1e9 (kMaxCoordinate)`);
  return v;
}

export { BLEND_NAMES };
