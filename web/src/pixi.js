// PixiJS v8: a display object that draws a scene optimized by
// `depthcull optimize` with the depth-tested meshes, in its place among the
// other Pixi objects.
//
// How it hooks into Pixi v8: a RenderContainer (renderPipeId "customRender")
// makes Pixi's CustomRenderPipe break the current batch and call render()
// at this object's place in the instruction list, with Pixi's current
// render target bound. render() draws with raw WebGL 2 through MeshRenderer,
// which saves and restores every GL state it changes, so Pixi's state
// caches stay true; it uses Pixi's own GL textures (premultiplied on
// upload, as Pixi's sprites see them) and Pixi's blend factors and colour
// quantization, so it draws what Pixi would draw with plain sprites.
import { RenderContainer } from 'pixi.js';
import { DepthcullError } from './index.js';
import { MeshRenderer } from './renderer.js';
import { loadMeshes } from './meshes.js';

// Pixi passes a sprite's tint and alpha to its shader as normalized bytes:
// the tint rounded (a 0.85 red is 217; measured: truncating to 216 made the
// tinted rocks of examples/meadow.json one level darker), the alpha
// truncated (groupColorAlpha: alpha * 255 | 0). The layer's colours are
// made the same bytes, or the frames would differ by one level.
export function pixiColorByte(c, channel) {
  const v = Math.min(1, Math.max(0, c)) * 255;
  return channel === 3 ? v | 0 : Math.round(v);
}

export class DepthCulledLayer extends RenderContainer {
  /**
   * `meshes`: parseMeshes's / loadMeshes's result. `textures`: one Pixi
   * Texture (or TextureSource) per `meshes.images` entry, the whole image
   * (u, v are of the whole image); set their scaleMode to the meshes'
   * filter ('nearest' for the pixel-identity guarantee). A `fill` image's
   * texture may be null: the layer makes its 16x16 texture of that colour.
   * The layer's local coordinates are the meshes' world pixels: position
   * it at (-viewport.x, -viewport.y) to show the viewport at the origin.
   */
  constructor(meshes, textures, options = {}) {
    super(options);
    if (!meshes || !Array.isArray(meshes.draws)) throw new DepthcullError('DepthCulledLayer: meshes must come from parseMeshes or loadMeshes');
    if (!Array.isArray(textures) || textures.length !== meshes.images.length)
      throw new DepthcullError(`DepthCulledLayer: ${meshes.images.length} images in the meshes, ${Array.isArray(textures) ? textures.length : 'no'} textures given`);
    meshes.images.forEach((img, i) => {
      if (!textures[i] && !img.fill) throw new DepthcullError(`DepthCulledLayer: no texture for image "${img.id}" (${img.path})`);
    });
    this.meshes = meshes;
    this.sources = textures.map((t) => (t ? t.source ?? t : null));
    this.label = options.label ?? 'DepthCulledLayer';
    this.stats = { draws: 0, triangles: 0 };
    this._renderers = new Map(); // per GL context (one Pixi renderer usually)
    this.assembler = null;
    this.movingSprites = null;
    this.frameStats = null;
  }

  /**
   * Moving sprites drawn with the layer every frame, depth-culled at the
   * meshes' insertion points (`optimize --insert-at`): `assembler` a
   * FrameAssembler (depthcull.createFrameAssembler(), src/frames.js) whose
   * images name textures by their index in `textures` (Pixi Textures or
   * TextureSources of the whole images, premultiplied as Pixi uploads
   * them). Then set `layer.movingSprites` each frame: one sprite list per
   * insertion point (assemble()'s input; with meshes without points, one
   * list drawn on top). Sprite colours ([r, g, b, a], 0..1) go to the
   * shader as the bytes Pixi makes of a sprite's tint and alpha
   * (pixiColorByte), so tinted and translucent sprites draw what Pixi's draw.
   */
  setMovingSprites(assembler, textures) {
    if (!assembler || typeof assembler.assemble !== 'function') throw new DepthcullError('DepthCulledLayer.setMovingSprites: expected a FrameAssembler');
    if (!Array.isArray(textures)) throw new DepthcullError('DepthCulledLayer.setMovingSprites: expected an array of textures');
    assembler.setStaticMeshes(this.meshes);
    this.assembler = assembler;
    this.frameSources = textures.map((t) => (t ? t.source ?? t : null));
    this.movingSprites = [];
  }

  /** Loads a meshes file and its images through Pixi's Assets, nearest (or the file's filter). */
  static async from(url, { Assets, name } = {}) {
    if (!Assets) throw new DepthcullError('DepthCulledLayer.from: pass { Assets } from pixi.js');
    const meshes = await loadMeshes(url, { name });
    const textures = await Promise.all(
      meshes.images.map(async (img) => {
        if (img.fill) return null;
        if (img.trans) throw new DepthcullError(`${name ?? url}: image "${img.id}" has a colour key (trans); load it yourself and pass textures`);
        const t = await Assets.load(img.url);
        t.source.scaleMode = meshes.filter;
        return t;
      }),
    );
    return new DepthCulledLayer(meshes, textures);
  }

  addBounds(bounds) {
    const v = this.meshes.viewport;
    bounds.addFrame(v.x, v.y, v.x + v.width, v.y + v.height);
  }

  render(renderer) {
    const gl = renderer.gl;
    if (!gl) throw new DepthcullError('DepthCulledLayer: needs Pixi\'s WebGL renderer (preference: "webgl")');
    let r = this._renderers.get(gl);
    if (!r) {
      r = new MeshRenderer(gl, { premultipliedAlpha: true, fragmentPrecision: 'mediump' });
      r.setMeshes(this.meshes, { colorByte: pixiColorByte });
      r.fillTextures = this.meshes.images.some((img) => img.fill) ? r.uploadImages([], { fillsOnly: true }) : [];
      this._renderers.set(gl, r);
    }
    // Pixi's textures, uploaded (premultiplied) by Pixi if not yet.
    r.setTextures(this.sources.map((s, i) => (s ? renderer.texture.getGlSource(s).texture : r.fillTextures[i])));
    // Pixi's vertex shader: projection * worldTransform * (group-space vertex).
    const u = renderer.globalUniforms.globalUniformData;
    const m = u.projectionMatrix.clone().append(u.worldTransformMatrix).append(this.groupTransform);
    const matrix = new Float32Array([m.a, m.b, 0, m.c, m.d, 0, m.tx, m.ty, 1]);
    let frame;
    if (this.assembler && this.movingSprites) {
      frame = this.assembler.assemble(this.movingSprites, this.meshes.viewport);
      this.frameStats = frame.stats;
    }
    const frameTextures = frame ? this.frameSources.map((s) => (s ? renderer.texture.getGlSource(s).texture : null)) : undefined;
    this.stats = r.draw({ matrix, frame, frameTextures, frameColorByte: pixiColorByte });
  }

  destroy(options) {
    for (const r of this._renderers.values()) r.destroy();
    this._renderers.clear();
    super.destroy(options);
  }
}
