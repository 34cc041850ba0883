// Phaser 4: our polygons as Mesh2D game objects (tight outlines), and a
// depth-culled layer drawing a scene optimized by `depthcull optimize`.
//
// Mesh2D (Phaser >= 4.2): a frame of an atlas `depthcull atlas` wrote (the
// TexturePacker polygon fields "vertices", "verticesUV", "triangles", which
// Phaser's atlas parsers keep in frame.customData) becomes a Mesh2D drawing
// only the triangles of our boundary polygons, where a Sprite draws the
// whole frame rectangle. Mesh2D goes through Phaser's own quad batcher and
// shader, so what it shows is what the Sprite shows, minus nothing: the
// texels it leaves out are transparent.
//
// The layer (line numbers of Phaser 4.2.1): Phaser's WebGL renderer is WebGL 1 (getContext('webgl'),
// src/renderer/webgl/WebGLRenderer.js init, line 709) but takes a context of
// the game config's `context` (line 703), and its setExtensions says a WebGL 2 context
// is supported; MeshRenderer needs WebGL 2 (uint32 indices, samplers, VAOs
// without extensions). The main framebuffer has a depth buffer (the context
// is made with `depth: true`, WebGLRenderer.js contextCreationConfig; ours
// must be too). An Extern game object gets the GL context between
// YieldContext and RebindContext (gameobjects/extern/ExternWebGLRenderer.js),
// which flush Phaser's batch and afterwards re-apply Phaser's cached state,
// so raw GL there is what Phaser expects. Phaser's own framebuffers (a
// camera with filters, DynamicTexture) are made without depth
// (src/renderer/webgl/DrawingContext.js, resize: createFramebuffer(texture,
// stencil, false)); the layer refuses to draw into one (one-line error).
import * as Phaser from 'phaser';
import { DepthcullError } from './index.js';
import { MeshRenderer } from './renderer.js';
import { loadMeshes } from './meshes.js';

// The double a colour had in the scene file: parseMeshes keeps vertices as
// float32, and a float32 of a byte boundary lands on the other side of it
// (0.7 is 0.699999988 as float32: * 255 = 178.4999970 rounds to 178, where
// the scene's 0.7 * 255 = 178.5 rounds to 179, the byte Phaser draws the
// scene's 0.7 with). The shortest decimal that reads back as the same
// float32 (9 digits at most) is what the file said, unless the scene gave
// more digits than a float32 keeps.
function sceneDouble(f) {
  for (let p = 1; p < 9; ++p) {
    const d = Number(f.toPrecision(p));
    if (Math.fround(d) === f) return d;
  }
  return f;
}

// float32 rounding moves c * 255 by at most 255 * 2^-24 (1.5e-5): only a
// value this close to a byte boundary may round to another byte than the
// scene's double, so only those take sceneDouble's string work (frames
// quantize every moving sprite's vertex colours).
const NEAR_BOUNDARY = 1e-4;

// Phaser feeds a tint to its shader as bytes: rgb as the integer colour
// given to setTint (a scene's 0..1 colour rounded), alpha truncated
// (renderer/webgl/Utils.js getTintAppendFloatAlpha: (a * 255) | 0), each
// of the colour as the scene file gives it (sceneDouble).
function phaserColorByte(c, channel) {
  let v = Math.min(1, Math.max(0, c)) * 255;
  const frac = v - Math.floor(v);
  const boundary = channel === 3 ? Math.min(frac, 1 - frac) : Math.abs(frac - 0.5);
  if (boundary < NEAR_BOUNDARY && c > 0 && c < 1) v = Math.min(1, Math.max(0, sceneDouble(c))) * 255;
  return channel === 3 ? v | 0 : Math.round(v);
}

/**
 * Makes a game config's WebGL 2 `context` (with depth) on `canvas`, for
 * DepthCulledExtern: `new Phaser.Game({ type: Phaser.WEBGL, canvas, context: webgl2Context(canvas), ... })`.
 * `attributes` as Phaser passes them (antialias, preserveDrawingBuffer...).
 */
export function webgl2Context(canvas, attributes = {}) {
  const gl = canvas.getContext('webgl2', { alpha: false, antialias: false, premultipliedAlpha: true, ...attributes, depth: true });
  if (!gl) throw new DepthcullError('webgl2Context: this browser gives no WebGL 2 context');
  return gl;
}

// Frame polygons in Phaser's Mesh2D layout: vertices x, y, u, v (step 4)
// relative to the game object's position; indices a, b, c, page (step 4).
function frameMesh(frame, originX, originY, name) {
  const data = frame.customData ?? {};
  const { vertices, verticesUV, triangles } = data;
  if (!Array.isArray(vertices) || !Array.isArray(verticesUV) || !Array.isArray(triangles) || vertices.length !== verticesUV.length)
    throw new DepthcullError(`${name}: frame "${frame.name}" has no polygon ("vertices", "verticesUV", "triangles": run \`depthcull atlas\` on the atlas)`);
  const source = frame.source;
  // The untrimmed sprite's top-left is where a Sprite of this frame with the
  // same origin puts it: -origin * (untrimmed size).
  const ox = originX * frame.realWidth, oy = originY * frame.realHeight;
  const out = new Array(vertices.length * 4);
  vertices.forEach(([x, y], k) => {
    const [s, t] = verticesUV[k];
    out[k * 4] = x - ox;
    out[k * 4 + 1] = y - oy;
    // Phaser uploads textures flipped (UNPACK_FLIP_Y) and its frames' v is
    // 1 - y / height (textures/Frame.js updateUVs); flipV makes Mesh2D
    // compute that same 1 - v from our top-down v.
    out[k * 4 + 2] = s / source.width;
    out[k * 4 + 3] = t / source.height;
  });
  const page = frame.sourceIndex ?? 0;
  const indices = [];
  for (const tri of triangles) {
    if (!Array.isArray(tri) || tri.length !== 3 || tri.some((i) => !Number.isInteger(i) || i < 0 || i >= vertices.length))
      throw new DepthcullError(`${name}: frame "${frame.name}": triangles: each must be three indices in 0..${vertices.length - 1}`);
    indices.push(tri[0], tri[1], tri[2], page);
  }
  return { vertices: out, indices };
}

/**
 * A Mesh2D of an atlas frame drawn by its polygon: `scene.add.existing(polygonMesh2D(scene, x, y, 'atlas', 'hero.png'))`.
 * The origin is a Sprite's (the frame's pivot, else 0.5) unless given.
 * Needs the atlas `depthcull atlas` wrote (loaded with scene.load.atlas /
 * multiatlas). `ordered`: pair the triangles into quads
 * (buildOrderedIndices(1)), as Phaser's Mesh2D docs advise for a fixed
 * topology; off by default, as in Phaser 4.2.1 it changes pixels (7 on the
 * bundled atlas, measured by test/phaser.test.js's page): each triangle is
 * then sent as a quad with a repeated corner, which draws exactly it.
 */
export function polygonMesh2D(scene, x, y, texture, frameName, { originX, originY, ordered = false } = {}) {
  const tex = typeof texture === 'string' ? scene.textures.get(texture) : texture;
  const frame = tex.get(frameName);
  if (!frame || (frameName !== undefined && frame.name !== String(frameName)))
    throw new DepthcullError(`polygonMesh2D: texture "${tex.key}" has no frame "${frameName}"`);
  const ox = originX ?? (frame.customPivot ? frame.pivotX : 0.5);
  const oy = originY ?? (frame.customPivot ? frame.pivotY : 0.5);
  const { vertices, indices } = frameMesh(frame, ox, oy, tex.key);
  const mesh = new Phaser.GameObjects.Mesh2D(scene, x, y, tex, vertices, indices, true);
  if (ordered) {
    mesh.buildOrderedIndices(1);
    mesh.setUseOrderedIndices(true);
  }
  return mesh;
}

/** Every frame of a polygon atlas as {name: {vertices, indices}} in Mesh2D's layout, origin (originX, originY). */
export function atlasMeshes(scene, texture, { originX = 0, originY = 0 } = {}) {
  const tex = typeof texture === 'string' ? scene.textures.get(texture) : texture;
  const out = {};
  for (const name of tex.getFrameNames()) out[name] = frameMesh(tex.get(name), originX, originY, tex.key);
  return out;
}

/**
 * A scene optimized by `depthcull optimize` as one Phaser game object,
 * drawn depth-culled (MeshRenderer: opaque pass front to back with depth
 * writes, then the blend pass) at its place in the display list. Its local
 * coordinates are the meshes' world pixels; the camera's scroll and zoom
 * and the object's transform apply as to any game object.
 * `textures`: one Phaser texture key (or Texture) per `meshes.images`
 * entry (null for a `fill` image), loaded as the whole image, nearest
 * filtering for pixel identity with Sprites.
 * Needs the game's context to be WebGL 2 with depth (webgl2Context).
 */
export class DepthCulledExtern extends Phaser.GameObjects.Extern {
  constructor(scene, meshes, textures) {
    super(scene);
    if (!meshes || !Array.isArray(meshes.draws)) throw new DepthcullError('DepthCulledExtern: meshes must come from parseMeshes or loadMeshes');
    if (!Array.isArray(textures) || textures.length !== meshes.images.length)
      throw new DepthcullError(`DepthCulledExtern: ${meshes.images.length} images in the meshes, ${Array.isArray(textures) ? textures.length : 'no'} textures given`);
    this.textureRefs = textures.map((t, i) => {
      const img = meshes.images[i];
      if (t == null) {
        if (!img.fill) throw new DepthcullError(`DepthCulledExtern: no texture for image "${img.id}" (${img.path})`);
        return null;
      }
      const tex = typeof t === 'string' ? scene.textures.get(t) : t;
      if (!tex || tex.key === '__MISSING') throw new DepthcullError(`DepthCulledExtern: no Phaser texture "${t}" for image "${img.id}"`);
      return tex;
    });
    // Phaser's textures are flipped on upload: v becomes 1 - v, computed in
    // double as Phaser computes its frames' v, so both sample the same texel.
    this.meshes = {
      ...meshes,
      draws: meshes.draws.map((d) => {
        const v = Float32Array.from(d.vertices);
        for (let k = 4; k < v.length; k += 9) v[k] = 1 - d.vertices[k];
        return { ...d, vertices: v };
      }),
    };
    this.stats = { draws: 0, triangles: 0 };
    this._renderer = null;
    this.assembler = null;
    this.movingSprites = null;
    this.frameStats = null;
  }

  /**
   * Moving sprites drawn with the layer every frame, depth-culled at the
   * meshes' insertion points (`optimize --insert-at`), as
   * DepthCulledLayer.setMovingSprites (src/pixi.js): `assembler` a
   * FrameAssembler (depthcull.createFrameAssembler(), src/frames.js) whose
   * images name textures by their index in `textures` (Phaser texture keys
   * or Textures, the whole images; the assembler's u, v are of the whole
   * image). Then set `layer.movingSprites` each frame: one sprite list per
   * insertion point (assemble()'s input; with meshes without points, one
   * list drawn on top). Sprite colours are made the bytes Phaser feeds its
   * shader for an Image's tint and alpha (phaserColorByte), so tinted and
   * translucent sprites draw what Phaser Images draw too.
   */
  setMovingSprites(assembler, textures) {
    if (!assembler || typeof assembler.assemble !== 'function') throw new DepthcullError('DepthCulledExtern.setMovingSprites: expected a FrameAssembler');
    if (!Array.isArray(textures)) throw new DepthcullError('DepthCulledExtern.setMovingSprites: expected an array of textures');
    const refs = textures.map((t, i) => {
      const tex = typeof t === 'string' ? this.scene.textures.get(t) : t;
      if (!tex || tex.key === '__MISSING') throw new DepthcullError(`DepthCulledExtern.setMovingSprites: no Phaser texture "${t}" for texture ${i}`);
      return tex;
    });
    assembler.setStaticMeshes(this.meshes);
    this.assembler = assembler;
    this.frameTextureRefs = refs;
    this.movingSprites = [];
    this._frameVertices = null;
  }

  // The frame's vertices with v flipped as the static meshes' (Phaser's
  // textures are flipped on upload) and colours quantized as Phaser's
  // (k / 255 in float32: measured identical to the normalized byte the
  // static meshes use; as floats, the meadow test's tinted sprites were a
  // level off at 49252 pixels in 60 frames), copied out of the wasm's
  // memory into one reused array (grown, never shrunk).
  #flipFrame(frame) {
    const src = frame.vertices;
    if (!this._frameVertices || this._frameVertices.length < src.length) this._frameVertices = new Float32Array(Math.max(src.length, 2 * (this._frameVertices?.length ?? 0)));
    const v = this._frameVertices.subarray(0, src.length);
    v.set(src);
    for (let k = 4; k < v.length; k += 9) {
      v[k] = 1 - src[k];
      // The colour as the byte Phaser would feed its shader for it.
      for (let c = 0; c < 4; ++c) v[k + 1 + c] = phaserColorByte(src[k + 1 + c], c) / 255;
    }
    this._frameOut = Object.assign(this._frameOut ?? {}, frame);
    this._frameOut.vertices = v;
    return this._frameOut;
  }

  /** Loads a meshes file and its images through the scene's loader, then adds the layer to the scene. */
  static async from(scene, url, { name } = {}) {
    const meshes = await loadMeshes(url, { name });
    const keys = meshes.images.map((img, i) => (img.fill ? null : `depthcull:${url}:${i}`));
    meshes.images.forEach((img, i) => {
      if (img.trans) throw new DepthcullError(`${name ?? url}: image "${img.id}" has a colour key (trans); load it yourself and pass textures`);
      if (keys[i] && !scene.textures.exists(keys[i])) scene.load.image(keys[i], img.url);
    });
    await new Promise((resolve) => {
      scene.load.once('complete', resolve);
      scene.load.start();
    });
    keys.forEach((k) => k && scene.textures.get(k).setFilter(meshes.filter === 'linear' ? Phaser.Textures.FilterMode.LINEAR : Phaser.Textures.FilterMode.NEAREST));
    return scene.add.existing(new DepthCulledExtern(scene, meshes, keys));
  }

  render(renderer, drawingContext, calcMatrix) {
    const gl = renderer.gl;
    if (typeof WebGL2RenderingContext === 'undefined' || !(gl instanceof WebGL2RenderingContext))
      throw new DepthcullError('DepthCulledExtern: the game needs a WebGL 2 context (config.context: webgl2Context(canvas))');
    if (gl.getParameter(gl.DEPTH_BITS) === 0)
      throw new DepthcullError('DepthCulledExtern: the framebuffer has no depth buffer (a camera with filters or a DynamicTexture: Phaser makes those without depth)');
    let r = this._renderer;
    if (!r || r.gl !== gl) {
      r = this._renderer = new MeshRenderer(gl, { premultipliedAlpha: true });
      r.setMeshes(this.meshes, { colorByte: phaserColorByte });
      r.fillTextures = this.meshes.images.some((img) => img.fill) ? r.uploadImages([], { fillsOnly: true }) : [];
    }
    r.setTextures(this.textureRefs.map((t, i) => (t ? t.source[0].glTexture.webGLTexture : r.fillTextures[i])));
    // calcMatrix: local to the drawing context's pixels (camera included);
    // then to clip space, y down on the canvas.
    const [a, b, c, d, tx, ty] = calcMatrix.matrix;
    const sx = 2 / drawingContext.width, sy = -2 / drawingContext.height;
    const matrix = new Float32Array([sx * a, sy * b, 0, sx * c, sy * d, 0, sx * tx - 1, sy * ty + 1, 1]);
    let frame, frameTextures;
    if (this.assembler && this.movingSprites) {
      const assembled = this.assembler.assemble(this.movingSprites, this.meshes.viewport);
      this.frameStats = assembled.stats;
      frame = this.#flipFrame(assembled);
      frameTextures = this.frameTextureRefs.map((t) => t.source[0].glTexture.webGLTexture);
    }
    this.stats = r.draw({ matrix, frame, frameTextures });
  }

  preDestroy() {
    this._renderer?.destroy();
    this._renderer = null;
  }
}
