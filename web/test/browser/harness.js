// Runs in the page: draws a scene with PixiJS as plain sprites and as a
// DepthCulledLayer, in one Pixi app, and compares the frames pixel for
// pixel. window.depthcullTest is what test/browser.test.js calls.
import * as PIXI from 'pixi.js';
import { DepthCulledLayer } from '../../src/pixi.js';
import { parseMeshes, loadMeshes } from '../../src/meshes.js';
import { MeshRenderer } from '../../src/renderer.js';
import { loadDepthcull } from '../../src/index.js';

const TEXEL_EDGE_TOLERANCE = 1 / 65536; // render::kTexelEdgeTolerance

async function keyedSource(url, trans) {
  const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const ctx = canvas.getContext('2d');
  ctx.drawImage(bitmap, 0, 0);
  const data = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
  const [r, g, b] = [0, 2, 4].map((k) => parseInt(trans.slice(k, k + 2), 16));
  const px = data.data;
  for (let i = 0; i < px.length; i += 4) if (px[i] === r && px[i + 1] === g && px[i + 2] === b) px[i] = px[i + 1] = px[i + 2] = px[i + 3] = 0;
  ctx.putImageData(data, 0, 0);
  return new PIXI.ImageSource({ resource: canvas, scaleMode: 'nearest', alphaMode: 'premultiply-alpha-on-upload' });
}

function fillSource(fill) {
  const canvas = new OffscreenCanvas(16, 16);
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = `#${fill}`;
  ctx.fillRect(0, 0, 16, 16);
  return new PIXI.ImageSource({ resource: canvas, scaleMode: 'nearest' });
}

// The scene's images as Pixi texture sources, nearest, by id.
async function sceneSources(scene, sceneUrl) {
  const out = new Map();
  for (const img of scene.images) {
    let source;
    if (img.fill) source = fillSource(img.fill.replace('#', ''));
    else if (img.trans) source = await keyedSource(new URL(img.path, sceneUrl).href, img.trans.replace('#', ''));
    else {
      const t = await PIXI.Assets.load({ src: new URL(img.path, sceneUrl).href, loadParser: 'loadTextures' });
      source = t.source;
      source.scaleMode = 'nearest';
    }
    out.set(img.id, source);
  }
  return out;
}

function elementRect(e, source) {
  return e.rect ?? [0, 0, source.width, source.height];
}

const PIXI_BLEND = { alpha: 'normal', add: 'add', multiply: 'multiply' };

function plainSprites(scene, sources) {
  const c = new PIXI.Container();
  for (const e of scene.elements) {
    const source = sources.get(e.image);
    const [x, y, w, h] = elementRect(e, source);
    const s = new PIXI.Sprite(new PIXI.Texture({ source, frame: new PIXI.Rectangle(x, y, w, h) }));
    const [a, b, cc, d, tx, ty] = e.transform ?? [1, 0, 0, 1, 0, 0];
    s.setFromMatrix(new PIXI.Matrix(a, b, cc, d, tx, ty));
    if (e.color) {
      s.tint = e.color.slice(0, 3);
      s.alpha = e.color[3];
    }
    const blend = PIXI_BLEND[e.blend ?? 'alpha'];
    if (!blend) throw new Error(`blend ${e.blend} has no Pixi equivalent`);
    s.blendMode = blend;
    c.addChild(s);
  }
  return c;
}

// Inverse of each element's transform: world point to texel of its image
// (render::count_off_texel_edges).
function texelMaps(scene, sources) {
  return scene.elements.map((e) => {
    const [a, b, c, d, tx, ty] = e.transform ?? [1, 0, 0, 1, 0, 0];
    const det = a * d - b * c;
    return { rect: elementRect(e, sources.get(e.image)), a, b, c, d, tx, ty, det };
  });
}

// One float32 step at |x|: both Pixi and the layer hand the GPU float32
// screen positions, rounded differently (Pixi's quad corners, the layer's
// polygon vertices), so texture coordinates interpolated at a pixel centre
// may differ by about that much, divided by the element's scale.
function ulp32(x) {
  const e = Math.floor(Math.log2(Math.max(Math.abs(x), 2 ** -126)));
  return 2 ** (e - 23);
}

// Within kTexelEdgeTolerance of a texel edge, or within the float32
// position rounding (in texels) at a screen position past 256 pixels:
// examples/meadow.json's pixel (542, 69) has its centre 3.0e-5 texels from
// a "moons" texel edge (u = 19.0000297; scale 1.2), under one float32 step
// at x = 542 (6.1e-5 px = 5.1e-5 texels): either side is a right answer.
// An image file's RGBA8 texels, not premultiplied (what the analysis reads).
async function decodedPixels(url) {
  const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const ctx = canvas.getContext('2d');
  ctx.drawImage(bitmap, 0, 0);
  return ctx.getImageData(0, 0, bitmap.width, bitmap.height);
}

function onTexelEdge(t, tol = TEXEL_EDGE_TOLERANCE) {
  return Math.abs(t - Math.round(t)) <= tol;
}

function compare(scene, sources, a, b, width, height) {
  const maps = texelMaps(scene, sources);
  let differ = 0, offEdges = 0;
  const examples = [];
  for (let row = 0; row < height; ++row)
    for (let x = 0; x < width; ++x) {
      const i = ((height - 1 - row) * width + x) * 4; // readPixels rows are bottom-up
      if (a[i] === b[i] && a[i + 1] === b[i + 1] && a[i + 2] === b[i + 2] && a[i + 3] === b[i + 3]) continue;
      ++differ;
      const sx = (scene.viewport.x ?? 0) + x + 0.5, sy = (scene.viewport.y ?? 0) + row + 0.5; // x, y are optional in scene JSON
      let explained = false;
      for (const m of maps) {
        const px = sx - m.tx, py = sy - m.ty;
        const u = m.rect[0] + (m.d * px - m.c * py) / m.det, v = m.rect[1] + (-m.b * px + m.a * py) / m.det;
        const tol = TEXEL_EDGE_TOLERANCE;
        if (u < m.rect[0] - tol || v < m.rect[1] - tol || u > m.rect[0] + m.rect[2] + tol || v > m.rect[1] + m.rect[3] + tol) continue;
        const rounding = ulp32(Math.max(Math.abs(sx), Math.abs(sy))) / Math.sqrt(Math.abs(m.det));
        const edge = Math.max(TEXEL_EDGE_TOLERANCE, rounding);
        if (onTexelEdge(u, edge) || onTexelEdge(v, edge)) {
          explained = true;
          break;
        }
      }
      if (!explained) {
        ++offEdges;
        if (examples.length < 5) examples.push(`(${x},${row}) plain ${[...a.subarray(i, i + 4)]} layer ${[...b.subarray(i, i + 4)]}`);
      }
    }
  return { differ, offEdges, examples };
}

function readPixels(app) {
  const gl = app.renderer.gl;
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return px;
}

// Other Pixi objects around the layer: one behind, one in front; both
// frames have them, so the layer must draw in its place among them.
function decorations(width, height) {
  const back = new PIXI.Graphics().rect(0, 0, width, height).fill(0x336699);
  const front = new PIXI.Graphics().rect(width / 4, height / 4, width / 2, height / 8).fill({ color: 0xffcc00, alpha: 0.5 });
  return { back, front };
}

export function rendererString(gl) {
  const ext = gl.getExtension('WEBGL_debug_renderer_info');
  return gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
}

window.depthcullTest = {
  rendererString: () => rendererString(new OffscreenCanvas(1, 1).getContext('webgl2')),
  async identity({ sceneUrl, meshesUrl, frames = 1 }) {
    const scene = await (await fetch(sceneUrl)).json();
    const meshes = await loadMeshes(meshesUrl);
    const { width, height } = meshes.viewport;
    const app = new PIXI.Application();
    await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, preserveDrawingBuffer: true, autoStart: false });
    document.body.appendChild(app.canvas);
    const sources = await sceneSources(scene, sceneUrl);
    const world = new PIXI.Container();
    world.position.set(-meshes.viewport.x, -meshes.viewport.y);
    const { back, front } = decorations(width, height);
    app.stage.addChild(back, world, front);

    const plain = plainSprites(scene, sources);
    world.addChild(plain);
    app.renderer.render(app.stage);
    const a = readPixels(app);
    world.removeChild(plain);

    const layer = new DepthCulledLayer(meshes, meshes.images.map((img) => sources.get(img.id)));
    world.addChild(layer);
    let result = { differ: 0, offEdges: 0, examples: [] };
    for (let f = 0; f < frames; ++f) {
      app.renderer.render(app.stage);
      const b = readPixels(app);
      const r = compare(scene, sources, a, b, width, height);
      result = { differ: Math.max(result.differ, r.differ), offEdges: result.offEdges + r.offEdges, examples: result.examples.concat(r.examples).slice(0, 5) };
    }
    const glRenderer = rendererString(app.renderer.gl);
    if (window.keepFrames) window.keptFrames = { a: Array.from(a), b: Array.from(readPixels(app)) };
    const stats = layer.stats;
    app.destroy(true, { children: true });
    return { ...result, width, height, elements: scene.elements.length, stats, glRenderer };
  },

  // Moving sprites for `frames` frames: the scene as plain Pixi sprites with
  // `count` plain Pixi sprites moving on top, against the layer drawing the
  // same sprites through its FrameAssembler (on top of the meshes: the
  // levels above them), frame by frame. The sprites show the pictures of
  // the scene's first plain-image elements, at whole-pixel positions that
  // change every frame (several overlapping).
  //
  // With `atElement` (no meshesUrl): the meshes are reconstructed in the
  // wasm with an insertion point before that element (reconstructScene,
  // as optimize --insert-at), the sprites go there, and the plain app draws
  // them between the elements before it and those after it.
  //
  // `styled`: sprite k is plain (k % 4 == 0), tinted (1), tinted and
  // translucent (2) or tinted, translucent and additive (3), with tints and
  // alphas whose bytes are not exact floats (0.85 * 255 = 216.75), as
  // Pixi's own sprites take them.
  async identityMoving({ sceneUrl, meshesUrl, frames = 60, count = 24, atElement, styled = false }) {
    const scene = await (await fetch(sceneUrl)).json();
    const depthcull = await loadDepthcull();
    let meshes;
    if (atElement === undefined) meshes = await loadMeshes(meshesUrl);
    else {
      // The scene JSON as loaded, each image's pixels added (a fill needs
      // none; a colour key is applied by reconstructScene, as the CLI does).
      const images = [];
      for (const img of scene.images) {
        if (img.fill) images.push(img);
        else {
          const { width, height, data } = await decodedPixels(new URL(img.path, sceneUrl).href); // getters: no spread
          images.push({ ...img, width, height, data });
        }
      }
      meshes = depthcull.reconstructScene({ ...scene, images, insertionPoints: [{ element: atElement, levels: count }] });
    }
    const { width, height } = meshes.viewport;
    const app = new PIXI.Application();
    await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, preserveDrawingBuffer: true, autoStart: false });
    document.body.appendChild(app.canvas);
    const sources = await sceneSources(scene, sceneUrl);
    const world = new PIXI.Container();
    world.position.set(-meshes.viewport.x, -meshes.viewport.y);
    const { back, front } = decorations(width, height);
    app.stage.addChild(back, world, front);

    // Up to 6 distinct pictures (image, rect) of plain images, their
    // pixels decoded without premultiplication for the analysis.
    const assembler = depthcull.createFrameAssembler();
    const pictures = [];
    const textures = [];
    const seen = new Set();
    for (const e of scene.elements) {
      const img = scene.images.find((i) => i.id === e.image);
      if (!img || img.fill || img.trans || pictures.length >= 6) continue;
      const source = sources.get(e.image);
      const rect = elementRect(e, source);
      const key = `${e.image}:${rect}`;
      if (seen.has(key) || rect[2] < 4 || rect[3] < 4) continue;
      seen.add(key);
      const pixels = await decodedPixels(new URL(img.path, sceneUrl).href);
      let texture = textures.indexOf(source);
      if (texture < 0) texture = textures.push(source) - 1;
      const id = assembler.addImage(pixels, { texture, rect: { x: rect[0], y: rect[1], width: rect[2], height: rect[3] }, name: img.path });
      pictures.push({ id, source, rect });
    }
    if (!pictures.length) throw new Error('no plain-image elements to move');
    const place = (k, f) => {
      const p = pictures[k % pictures.length];
      // Whole pixels, a different path per sprite, crossing each other.
      const x = meshes.viewport.x + ((k * 97 + f * (3 + (k % 5))) % Math.max(1, width - p.rect[2]));
      const y = meshes.viewport.y + ((k * 61 + f * (2 + (k % 3))) % Math.max(1, height - p.rect[3]));
      return { p, x, y };
    };

    const plain = plainSprites(scene, sources);
    const moving = new PIXI.Container();
    const pixiSprites = [];
    const styles = [
      { color: [1, 1, 1, 1], blend: 'alpha' },
      { color: [1, 0.85, 0.6, 1], blend: 'alpha' },
      { color: [0.7, 0.9, 1, 0.55], blend: 'alpha' },
      { color: [1, 0.95, 0.7, 0.8], blend: 'add' },
    ];
    const styleOf = (k) => (styled ? styles[k % styles.length] : styles[0]);
    for (let k = 0; k < count; ++k) {
      const { p } = place(k, 0);
      const s = new PIXI.Sprite(new PIXI.Texture({ source: p.source, frame: new PIXI.Rectangle(...p.rect) }));
      const { color, blend } = styleOf(k);
      s.tint = color.slice(0, 3);
      s.alpha = color[3];
      s.blendMode = PIXI_BLEND[blend];
      pixiSprites.push(s);
      moving.addChild(s);
    }
    const layer = new DepthCulledLayer(meshes, meshes.images.map((img) => sources.get(img.id)));
    layer.setMovingSprites(assembler, textures);
    const sprites = Array.from({ length: count }, (_, k) => ({ image: 0, x: 0, y: 0, color: styleOf(k).color, blend: styleOf(k).blend }));
    let result = { differ: 0, offEdges: 0, examples: [] };
    let draws = 0, triangles = 0, opaqueSprites = 0;
    for (let f = 0; f < frames; ++f) {
      for (let k = 0; k < count; ++k) {
        const { p, x, y } = place(k, f);
        pixiSprites[k].position.set(x, y);
        Object.assign(sprites[k], { image: p.id, x, y });
      }
      if (atElement === undefined) world.addChild(plain, moving);
      else {
        plain.addChildAt(moving, atElement);
        world.addChild(plain);
      }
      app.renderer.render(app.stage);
      const a = readPixels(app);
      world.removeChildren();
      if (atElement !== undefined) plain.removeChild(moving);
      layer.movingSprites = atElement === undefined ? sprites : [sprites];
      world.addChild(layer);
      app.renderer.render(app.stage);
      const b = readPixels(app);
      world.removeChildren();
      const r = compare(scene, sources, a, b, width, height);
      result = { differ: Math.max(result.differ, r.differ), offEdges: result.offEdges + r.offEdges, examples: result.examples.concat(r.examples.map((x) => `frame ${f}: ${x}`)).slice(0, 5) };
      draws = Math.max(draws, layer.stats.draws);
      triangles = Math.max(triangles, layer.stats.triangles);
      opaqueSprites = layer.frameStats.opaqueDraws;
    }
    const glRenderer = rendererString(app.renderer.gl);
    assembler.free();
    app.destroy(true, { children: true });
    return { ...result, width, height, elements: scene.elements.length, sprites: count, pictures: pictures.length, frames, stats: { draws, triangles, frameOpaqueDraws: opaqueSprites }, glRenderer };
  },

  // Times the analysis of an atlas page in the browser (what `depthcull
  // atlas` does per frame): the page decoded, every frame's rect analysed
  // with the defaults; the median of 5 runs, after one to warm up.
  async analyzeAtlas({ pngUrl, jsonUrl }) {
    const t0 = performance.now();
    const depthcull = await loadDepthcull();
    const loadMs = performance.now() - t0;
    const wasmBytes = (await (await fetch(new URL('../../dist/depthcull.wasm', import.meta.url))).arrayBuffer()).byteLength;
    const atlas = await (await fetch(jsonUrl)).json();
    const bitmap = await createImageBitmap(await (await fetch(pngUrl)).blob(), { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = canvas.getContext('2d');
    ctx.drawImage(bitmap, 0, 0);
    const image = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
    // A rotated frame lies turned in the page: its w and h swap there.
    const frames = Object.values(atlas.frames).map((f) => (f.rotated ? { x: f.frame.x, y: f.frame.y, w: f.frame.h, h: f.frame.w } : f.frame));
    const run = () => {
      let vertices = 0;
      for (const f of frames) {
        const a = depthcull.analyzeImage(image, { rect: { x: f.x, y: f.y, width: f.w, height: f.h } });
        for (const p of a.boundary) vertices += p.length;
      }
      return vertices;
    };
    const vertices = run();
    const times = [];
    for (let k = 0; k < 5; ++k) {
      const t = performance.now();
      run();
      times.push(performance.now() - t);
    }
    times.sort((x, y) => x - y);
    const whole = performance.now();
    depthcull.analyzeImage(image);
    const wholeMs = performance.now() - whole;
    return { width: image.width, height: image.height, frames: frames.length, vertices, ms: times[2], wholeMs, loadMs, wasmBytes };
  },

  // The error a bad meshes file gives, as the caller sees it.
  async meshesError(text) {
    try {
      parseMeshes(new TextEncoder().encode(text), { name: 'bad.meshes.json' });
      return null;
    } catch (e) {
      return `${e.name}: ${e.message}`;
    }
  },

  // MeshRenderer leaves the GL state as it found it.
  async stateRestored({ meshesUrl }) {
    const meshes = await loadMeshes(meshesUrl);
    const canvas = new OffscreenCanvas(meshes.viewport.width, meshes.viewport.height);
    const gl = canvas.getContext('webgl2', { depth: true });
    const names = ['CURRENT_PROGRAM', 'VERTEX_ARRAY_BINDING', 'ARRAY_BUFFER_BINDING', 'ACTIVE_TEXTURE', 'BLEND', 'BLEND_SRC_RGB', 'BLEND_DST_RGB',
      'BLEND_SRC_ALPHA', 'BLEND_DST_ALPHA', 'BLEND_EQUATION_RGB', 'DEPTH_TEST', 'DEPTH_FUNC', 'DEPTH_WRITEMASK', 'DEPTH_CLEAR_VALUE', 'CULL_FACE',
      'TEXTURE_BINDING_2D', 'UNPACK_FLIP_Y_WEBGL', 'UNPACK_PREMULTIPLY_ALPHA_WEBGL', 'UNPACK_ALIGNMENT'];
    // An engine's state, unlike ours in every item.
    const tex = gl.createTexture();
    gl.activeTexture(gl.TEXTURE3);
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ZERO);
    gl.enable(gl.CULL_FACE);
    gl.depthFunc(gl.LESS);
    gl.depthMask(false);
    gl.clearDepth(0.5);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, true);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 8);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const before = names.map((n) => gl.getParameter(gl[n]));
    const r = new MeshRenderer(gl);
    r.setMeshes(meshes);
    // Placeholder texels: this test is about state, not pixels.
    const images = meshes.images.map((img) => (img.fill ? null : new ImageData(img.width, img.height)));
    r.uploadImages(images);
    const stats = r.draw();
    const after = names.map((n) => gl.getParameter(gl[n]));
    const changed = names.filter((n, i) => before[i] !== after[i]);
    return { changed, stats, error: gl.getError() };
  },
};
window.depthcullReady = true;
