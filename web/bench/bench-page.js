// Runs in bench.html: one scene drawn by a PixiJS app as plain sprites and
// with a DepthCulledLayer (the meshes `depthcull optimize` wrote), timed
// frame by frame; draws and triangles counted on the GL context (every
// draw call Pixi or the layer makes). window.bench is what run.js calls.
import * as PIXI from 'pixi.js';
import { DepthCulledLayer } from '../src/pixi.js';
import { loadMeshes } from '../src/meshes.js';
import { loadSceneSources, sceneSprites } from '../src/pixi-scene.js';
import { DepthCulledSpriteContainer } from '../src/pixi-sprites.js';
import { loadDepthcull } from '../src/index.js';

// Counts the draw calls and triangles made on `gl` while `fn` runs.
function counted(gl, fn) {
  const saved = { drawElements: gl.drawElements, drawArrays: gl.drawArrays, drawElementsInstanced: gl.drawElementsInstanced, drawArraysInstanced: gl.drawArraysInstanced };
  const c = { draws: 0, triangles: 0 };
  const tri = (mode, count, instances = 1) => (mode === gl.TRIANGLES ? count / 3 : mode === gl.TRIANGLE_STRIP || mode === gl.TRIANGLE_FAN ? Math.max(0, count - 2) : 0) * instances;
  gl.drawElements = (mode, count, ...rest) => (++c.draws, (c.triangles += tri(mode, count)), saved.drawElements.call(gl, mode, count, ...rest));
  gl.drawArrays = (mode, first, count) => (++c.draws, (c.triangles += tri(mode, count)), saved.drawArrays.call(gl, mode, first, count));
  gl.drawElementsInstanced = (mode, count, type, offset, n) => (++c.draws, (c.triangles += tri(mode, count, n)), saved.drawElementsInstanced.call(gl, mode, count, type, offset, n));
  gl.drawArraysInstanced = (mode, first, count, n) => (++c.draws, (c.triangles += tri(mode, count, n)), saved.drawArraysInstanced.call(gl, mode, first, count, n));
  try {
    fn();
  } finally {
    Object.assign(gl, saved);
  }
  return c;
}

function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? (s[(s.length - 1) >> 1] + s[s.length >> 1]) / 2 : NaN;
}

// Draws, triangles (one frame, counted on the context) and the median ms
// per frame of `frames` frames after `warmup`; `step(f)` moves things first.
async function timed(app, frames, warmup, step = () => {}) {
  const gl = app.renderer.gl;
  // GPU time where the browser exposes it (EXT_disjoint_timer_query_webgl2).
  const timer = gl.getExtension('EXT_disjoint_timer_query_webgl2');
  const pixel = new Uint8Array(4);
  step(0);
  const count = counted(gl, () => app.renderer.render(app.stage));
  const ms = [], queries = [];
  for (let f = 0; f < warmup + frames; ++f) {
    step(f + 1);
    const q = timer && f >= warmup ? gl.createQuery() : null;
    if (q) gl.beginQuery(timer.TIME_ELAPSED_EXT, q);
    const t0 = performance.now();
    app.renderer.render(app.stage);
    if (q) gl.endQuery(timer.TIME_ELAPSED_EXT);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); // waits for the frame
    const t1 = performance.now();
    if (f >= warmup) ms.push(t1 - t0);
    if (q) queries.push(q);
  }
  // Query results become available only after control returns to the
  // browser's event loop (WebGL 2 spec, 5.35).
  const gpu = [];
  for (let tries = 0; queries.length && tries < 100 && !gl.getQueryParameter(queries[queries.length - 1], gl.QUERY_RESULT_AVAILABLE); ++tries)
    await new Promise((r) => setTimeout(r, 10));
  const disjoint = timer && gl.getParameter(timer.GPU_DISJOINT_EXT);
  for (const q of queries) {
    if (!disjoint && gl.getQueryParameter(q, gl.QUERY_RESULT_AVAILABLE)) gpu.push(gl.getQueryParameter(q, gl.QUERY_RESULT) / 1e6);
    gl.deleteQuery(q);
  }
  return { ...count, ms: median(ms), gpuMs: gpu.length ? median(gpu) : null, timerQuery: !!timer };
}

window.bench = {
  async run({ sceneUrl, meshesUrl, noOpaqueUrl, frames = 60, warmup = 5 }) {
    const scene = await (await fetch(sceneUrl)).json();
    const meshes = await loadMeshes(meshesUrl);
    const noOpaque = await loadMeshes(noOpaqueUrl);
    const { width, height } = meshes.viewport;
    const app = new PIXI.Application();
    await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, autoStart: false });
    document.body.appendChild(app.canvas);
    const gl = app.renderer.gl;
    const sources = await loadSceneSources(scene, sceneUrl);
    const world = new PIXI.Container();
    world.position.set(-meshes.viewport.x, -meshes.viewport.y);
    app.stage.addChild(world);
    const modes = {
      plain: sceneSprites(scene, sources),
      // Same layer and shader, meshes without the opaque pass (boundary
      // polygons back to front): what the shader alone changes.
      noOpaque: new DepthCulledLayer(noOpaque, noOpaque.images.map((img) => sources.get(img.id))),
      layer: new DepthCulledLayer(meshes, meshes.images.map((img) => sources.get(img.id))),
    };
    const results = {};
    for (const [name, object] of Object.entries(modes)) {
      world.removeChildren();
      world.addChild(object);
      results[name] = await timed(app, frames, warmup);
    }
    const ext = gl.getExtension('WEBGL_debug_renderer_info');
    const renderer = gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
    app.destroy(true, { children: true });
    return { width, height, elements: scene.elements.length, results, renderer, timerQuery: results.plain.timerQuery, userAgent: navigator.userAgent };
  },
};
// Moving sprites: `count` sprites of `images` wandering over 640x480, as a
// plain Container and as a DepthCulledSpriteContainer (polygons analysed by
// the wasm core before timing), moved every frame.
window.bench.sprites = async ({ images, count = 500, frames = 60, warmup = 5 }) => {
  const width = 640, height = 480;
  const app = new PIXI.Application();
  await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, autoStart: false });
  document.body.appendChild(app.canvas);
  const textures = [];
  for (const url of images) {
    const t = await PIXI.Assets.load({ src: url, loadParser: 'loadTextures' });
    t.source.scaleMode = 'nearest';
    textures.push(t);
  }
  let seed = 1;
  const rnd = () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) / 2 ** 32);
  const walkers = Array.from({ length: count }, () => ({ t: Math.floor(rnd() * textures.length), x: rnd() * width, y: rnd() * height, vx: rnd() * 4 - 2, vy: rnd() * 4 - 2 }));
  const plain = new PIXI.Container();
  const layer = new DepthCulledSpriteContainer({ depthcull: await loadDepthcull() });
  for (const w of walkers) {
    plain.addChild(new PIXI.Sprite(textures[w.t]));
    layer.addSprite(new PIXI.Sprite(textures[w.t]));
  }
  const results = {};
  for (const [name, object, list] of [['plain', plain, plain.children], ['layer', layer, layer.sprites.children]]) {
    app.stage.removeChildren();
    app.stage.addChild(object);
    const step = (f) => walkers.forEach((w, k) => list[k].position.set(Math.round((((w.x + w.vx * f) % width) + width) % width), Math.round((((w.y + w.vy * f) % height) + height) % height)));
    results[name] = await timed(app, frames, warmup, step);
  }
  app.destroy(true, { children: true });
  return { width, height, elements: count, results };
};
window.depthcullReady = true;
