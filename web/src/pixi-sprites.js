// PixiJS v8: a depth-culled container of ordinary Pixi sprites. Each frame
// its sprites are drawn as depthcull draws a scene (paper 3): the opaque
// polygons of every sprite front to back with depth writes (no blending:
// their texels are all opaque), then the boundary polygons back to front
// with depth test and blending, so a texel hidden behind an opaque region
// of a sprite in front is never shaded. It shows what a plain Container of
// the same sprites shows (test/sprites.test.js compares them frame by frame).
//
// The sprites live in `container.sprites`, a Container outside the scene
// graph: were they children of a display object on the stage, Pixi would
// draw them itself (its instruction set collects every child). So
// `layer.sprites.addChild(sprite)` where a Container has `addChild(sprite)`;
// move, tint, hide, swap textures as usual: each frame reads them afresh.
//
// Polygons per texture: analysed at first use by the wasm core
// (analyzeImage on the texture's frame; pass `depthcull` from loadDepthcull),
// or given with setPolygons (e.g. from an atlas `depthcull atlas` wrote:
// boundary only). A texture with neither is drawn as its frame rectangle in
// the blend pass (correct, no saving).
import { Container, RenderContainer, earcut } from 'pixi.js';
import { DepthcullError } from './index.js';
import { MeshRenderer } from './renderer.js';
import { pixiColorByte } from './pixi.js';

const BLENDS = { normal: 'alpha', add: 'add', multiply: 'multiply' };

// Triangles of polygons ([[x, y], ...]) as flat coordinates and indices.
function triangulate(polygons) {
  const coords = [], indices = [];
  for (const p of polygons) {
    if (p.length < 3) continue;
    const flat = p.flat();
    const base = coords.length / 2;
    for (const i of earcut(flat)) indices.push(base + i);
    coords.push(...flat);
  }
  return { coords: Float64Array.from(coords), indices: Uint32Array.from(indices) };
}

export class DepthCulledSpriteContainer extends RenderContainer {
  /**
   * `depthcull`: loadDepthcull()'s module, to analyse textures at first use
   * (omit it to give polygons with setPolygons only). `analyze`: options of
   * analyzeImage ({ filter: 'nearest' } by default: the polygons hold for
   * nearest sampling, which pixel identity needs).
   */
  constructor({ depthcull = null, analyze = {}, ...options } = {}) {
    super(options);
    this.label = options.label ?? 'DepthCulledSpriteContainer';
    this.sprites = new Container();
    this.depthcull = depthcull;
    this.analyzeOptions = { filter: 'nearest', ...analyze };
    this.stats = { draws: 0, triangles: 0, sprites: 0, opaqueSprites: 0 };
    this._polygons = new WeakMap(); // Texture -> {blend, opaque} triangulated, in source texels
    this._pixels = new WeakMap(); // TextureSource -> ImageData (analysis only)
    this._renderers = new Map();
  }

  /** Adds sprites (as sprites.addChild); returns the first. */
  addSprite(...sprites) {
    return this.sprites.addChild(...sprites);
  }

  /**
   * Polygons of `texture` in texels of its source (as analyzeImage returns
   * them): `boundary` covers every non-transparent texel of the frame,
   * `opaque` (may be empty) only opaque texels.
   */
  setPolygons(texture, { boundary, opaque = [] }) {
    this._polygons.set(texture, { blend: triangulate(boundary), opaque: triangulate(opaque) });
  }

  /**
   * The polygons `depthcull atlas` wrote into a TexturePacker atlas
   * (`verticesUV`, page texels, and `triangles`), for every frame of a
   * Pixi Spritesheet made from it: boundary only, so those sprites are
   * drawn in the blend pass alone, with tight outlines (analyse the page
   * instead for an opaque pass). Frames without the fields are left to
   * analysis. Returns how many frames were set.
   */
  setPolygonsFromSpritesheet(sheet) {
    let n = 0;
    for (const [name, frame] of Object.entries(sheet.data?.frames ?? {})) {
      const tex = sheet.textures[name];
      const { verticesUV, triangles } = frame;
      if (!tex || !Array.isArray(verticesUV) || !Array.isArray(triangles)) continue;
      const k = verticesUV.length;
      if (triangles.some((t) => !Array.isArray(t) || t.length !== 3 || t.some((i) => !Number.isInteger(i) || i < 0 || i >= k)))
        throw new DepthcullError(`setPolygonsFromSpritesheet: frame "${name}": triangles: each must be three indices in 0..${k - 1}`);
      // Pixi's frame of a page scaled by its resolution is in page pixels / resolution.
      const r = tex.source.resolution || 1;
      this._polygons.set(tex, {
        blend: { coords: Float64Array.from(verticesUV.flat(), (v) => v / r), indices: Uint32Array.from(triangles.flat()) },
        opaque: { coords: new Float64Array(0), indices: new Uint32Array(0) },
      });
      ++n;
    }
    return n;
  }

  #pixelsOf(source) {
    let data = this._pixels.get(source);
    if (!data) {
      const res = source.resource;
      if (!res || typeof res !== 'object' || !('width' in res)) throw new DepthcullError(`DepthCulledSpriteContainer: texture source "${source.label}" has no image to analyse; give its polygons with setPolygons`);
      const canvas = new OffscreenCanvas(source.pixelWidth, source.pixelHeight);
      const ctx = canvas.getContext('2d', { willReadFrequently: true });
      ctx.drawImage(res, 0, 0);
      data = ctx.getImageData(0, 0, source.pixelWidth, source.pixelHeight); // only alpha is read
      this._pixels.set(source, data);
    }
    return data;
  }

  #polygonsOf(texture) {
    let p = this._polygons.get(texture);
    if (p) return p;
    const f = texture.frame;
    if (this.depthcull && texture.source.resolution === 1) {
      const a = this.depthcull.analyzeImage(this.#pixelsOf(texture.source), {
        ...this.analyzeOptions,
        rect: { x: f.x, y: f.y, width: f.width, height: f.height },
        name: texture.source.label || 'texture',
      });
      this.setPolygons(texture, a);
    } else {
      this.setPolygons(texture, { boundary: [[[f.x, f.y], [f.x + f.width, f.y], [f.x + f.width, f.y + f.height], [f.x, f.y + f.height]]] });
    }
    return this._polygons.get(texture);
  }

  addBounds(bounds) {
    for (const s of this.sprites.children) {
      if (!s.visible) continue;
      s.updateLocalTransform();
      const b = s.getLocalBounds();
      bounds.addRect(b.rectangle ?? b, s.localTransform);
    }
  }

  // This frame's sprites as MeshRenderer meshes: per source image, an
  // opaque draw (front to back) and blend draws in sprite order.
  #assemble() {
    const sprites = this.sprites.children.filter((s) => s.visible && s.renderable !== false && s.texture && s.alpha > 0);
    const n = sprites.length;
    const images = [], imageOf = new Map();
    const opaque = new Map(); // image -> {v: [], i: []}
    const blendDraws = [];
    let opaqueSprites = 0;
    sprites.forEach((s, k) => {
      const tex = s.texture;
      if (tex.rotate) throw new DepthcullError(`DepthCulledSpriteContainer: sprite ${k}: rotated atlas frames are not supported`);
      const source = tex.source;
      let image = imageOf.get(source);
      if (image === undefined) {
        image = images.length;
        imageOf.set(source, image);
        images.push(source);
      }
      const mode = !s.blendMode || s.blendMode === 'inherit' ? 'normal' : s.blendMode;
      const blend = BLENDS[mode];
      if (!blend) throw new DepthcullError(`DepthCulledSpriteContainer: sprite ${k}: blend mode "${mode}" is not supported (normal, add, multiply)`);
      s.updateLocalTransform();
      const m = s.localTransform;
      // Sprite-local point of source texel (x, y): Pixi's quad is the frame
      // at (trim.x - anchor.x * orig.width, trim.y - anchor.y * orig.height).
      const f = tex.frame, orig = tex.orig, trim = tex.trim;
      const ox = (trim ? trim.x : 0) - s.anchor.x * orig.width - f.x;
      const oy = (trim ? trim.y : 0) - s.anchor.y * orig.height - f.y;
      const sw = source.width, sh = source.height;
      // The sprite's tint (rgb) and alpha, as Pixi feeds them.
      const tint = s.tint ?? 0xffffff;
      const color = [((tint >> 16) & 255) / 255, ((tint >> 8) & 255) / 255, (tint & 255) / 255, s.alpha];
      const z = (k + 1) / (n + 1); // in front: larger (depth GREATER)
      const poly = this.#polygonsOf(tex);
      const emit = (tri, out) => {
        const base = out.v.length / 9;
        for (let j = 0; j < tri.coords.length; j += 2) {
          const px = tri.coords[j], py = tri.coords[j + 1];
          const lx = px + ox, ly = py + oy;
          out.v.push(m.a * lx + m.c * ly + m.tx, m.b * lx + m.d * ly + m.ty, z, px / sw, py / sh, ...color);
        }
        for (const i of tri.indices) out.i.push(base + i);
      };
      // Opaque texels shown with full alpha and normal blending replace
      // what is behind: only such sprites go to the opaque pass.
      if (blend === 'alpha' && s.alpha >= 1 && poly.opaque.indices.length) {
        if (!opaque.has(image)) opaque.set(image, { v: [], i: [] });
        emit(poly.opaque, opaque.get(image));
        ++opaqueSprites;
      }
      let last = blendDraws[blendDraws.length - 1];
      if (!last || last.image !== image || last.blend !== blend) blendDraws.push((last = { image, blend, v: [], i: [] }));
      emit(poly.blend, last);
    });
    const draws = [];
    for (const [image, d] of opaque) draws.push({ image, pass: 'opaque', blend: 'alpha', vertices: Float32Array.from(d.v), indices: Uint32Array.from(d.i) });
    for (const d of blendDraws) draws.push({ image: d.image, pass: 'blend', blend: d.blend, vertices: Float32Array.from(d.v), indices: Uint32Array.from(d.i) });
    return { meshes: { depthTest: true, filter: 'nearest', images: images.map((s, i) => ({ id: String(i) })), draws, viewport: null }, sources: images, sprites: n, opaqueSprites };
  }

  render(renderer) {
    const gl = renderer.gl;
    if (!gl) throw new DepthcullError('DepthCulledSpriteContainer: needs Pixi\'s WebGL renderer (preference: "webgl")');
    let r = this._renderers.get(gl);
    if (!r) {
      r = new MeshRenderer(gl, { premultipliedAlpha: true, fragmentPrecision: 'mediump' });
      this._renderers.set(gl, r);
    }
    const { meshes, sources, sprites, opaqueSprites } = this.#assemble();
    r.setMeshes(meshes, { colorByte: pixiColorByte });
    r.setTextures(sources.map((s) => renderer.texture.getGlSource(s).texture));
    const u = renderer.globalUniforms.globalUniformData;
    const m = u.projectionMatrix.clone().append(u.worldTransformMatrix).append(this.groupTransform);
    const stats = r.draw({ matrix: new Float32Array([m.a, m.b, 0, m.c, m.d, 0, m.tx, m.ty, 1]) });
    this.stats = { ...stats, sprites, opaqueSprites };
  }

  destroy(options) {
    for (const r of this._renderers.values()) r.destroy();
    this._renderers.clear();
    this.sprites.destroy(options);
    super.destroy(options);
  }
}
