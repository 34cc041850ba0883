// Runs in the page sprites.html: the same moving sprites in a plain Pixi
// Container and in a DepthCulledSpriteContainer (polygons analysed in the
// page by the wasm core), frame by frame, with Pixi objects behind and in
// front; the frames are compared pixel for pixel (compare.js).
import * as PIXI from 'pixi.js';
import { loadDepthcull } from '../../src/index.js';
import { DepthCulledSpriteContainer } from '../../src/pixi-sprites.js';
import { compareFrames, readPixels, rendererString } from './compare.js';

// Deterministic numbers in [0, 1).
function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}

// Sprite k at frame f: texture, position, scale, anchor, tint, alpha, blend.
function specs(textures, count, seed) {
  const rnd = random(seed);
  const names = Object.keys(textures);
  return Array.from({ length: count }, () => {
    const name = names[Math.floor(rnd() * names.length)];
    return {
      name,
      x: Math.floor(rnd() * 300) - 10, y: Math.floor(rnd() * 220) - 10,
      vx: Math.floor(rnd() * 7) - 3, vy: Math.floor(rnd() * 5) - 2,
      scale: [[1, 1], [2, 2], [-1, 1], [1, -1]][Math.floor(rnd() * 4)],
      anchor: rnd() < 0.5 ? 0 : 0.5,
      tint: rnd() < 0.2 ? 0xd9a066 : 0xffffff,
      alpha: rnd() < 0.15 ? 0.6 : 1,
      blend: name === 'glow' ? 'add' : 'normal',
    };
  });
}

function makeSprite(textures, s) {
  const sprite = new PIXI.Sprite(textures[s.name]);
  sprite.anchor.set(s.anchor);
  sprite.scale.set(...s.scale);
  sprite.tint = s.tint;
  sprite.alpha = s.alpha;
  sprite.blendMode = s.blend;
  return sprite;
}

// What compare.js needs of a sprite: its frame and texel-to-world transform.
function element(sprite) {
  sprite.updateLocalTransform();
  const m = sprite.localTransform, tex = sprite.texture, f = tex.frame;
  const dx = (tex.trim ? tex.trim.x : 0) - sprite.anchor.x * tex.orig.width;
  const dy = (tex.trim ? tex.trim.y : 0) - sprite.anchor.y * tex.orig.height;
  return { rect: [f.x, f.y, f.width, f.height], transform: [m.a, m.b, m.c, m.d, m.a * dx + m.c * dy + m.tx, m.b * dx + m.d * dy + m.ty] };
}

window.spritesTest = {
  async identity({ images, count = 40, frames = 5, seed = 1 }) {
    const depthcull = await loadDepthcull();
    const width = 320, height = 240;
    const app = new PIXI.Application();
    await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, preserveDrawingBuffer: true, autoStart: false });
    document.body.appendChild(app.canvas);
    const textures = {};
    for (const [name, url] of Object.entries(images)) {
      textures[name] = await PIXI.Assets.load({ src: url, loadParser: 'loadTextures' });
      textures[name].source.scaleMode = 'nearest';
    }
    const list = specs(textures, count, seed);
    const plain = new PIXI.Container();
    for (const s of list) plain.addChild(makeSprite(textures, s));
    const layer = new DepthCulledSpriteContainer({ depthcull });
    for (const s of list) layer.addSprite(makeSprite(textures, s));
    const back = new PIXI.Graphics().rect(0, 0, width, height).fill(0x336699);
    const front = new PIXI.Graphics().rect(width / 4, height / 4, width / 2, height / 8).fill({ color: 0xffcc00, alpha: 0.5 });
    app.stage.addChild(back, plain, layer, front);
    const result = { differ: 0, offEdges: 0, examples: [], frames: [] };
    for (let f = 0; f < frames; ++f) {
      list.forEach((s, k) => {
        plain.children[k].position.set(s.x + s.vx * f, s.y + s.vy * f);
        layer.sprites.children[k].position.set(s.x + s.vx * f, s.y + s.vy * f);
      });
      plain.visible = true;
      layer.visible = false;
      app.renderer.render(app.stage);
      const a = readPixels(app.renderer.gl);
      plain.visible = false;
      layer.visible = true;
      app.renderer.render(app.stage);
      const b = readPixels(app.renderer.gl);
      const r = compareFrames(plain.children.map(element), { x: 0, y: 0 }, a, b, width, height);
      result.differ = Math.max(result.differ, r.differ);
      result.offEdges += r.offEdges;
      result.examples = result.examples.concat(r.examples.map((e) => `frame ${f}: ${e}`)).slice(0, 5);
      result.frames.push(layer.stats);
    }
    result.glRenderer = rendererString(app.renderer.gl);
    app.destroy(true, { children: true });
    return result;
  },
};
// Frames of an atlas `depthcull atlas` wrote, as sprites in a plain
// Container and in the layer with the atlas's polygons (no analysis): the
// same pixels. Rotated frames are left out (the layer refuses them).
window.spritesTest.atlas = async ({ atlasUrl }) => {
  const width = 256, height = 128;
  const app = new PIXI.Application();
  await app.init({ width, height, preference: 'webgl', antialias: false, resolution: 1, background: 0x000000, preserveDrawingBuffer: true, autoStart: false });
  document.body.appendChild(app.canvas);
  const sheet = await PIXI.Assets.load(atlasUrl);
  sheet.textureSource.scaleMode = 'nearest';
  const names = Object.keys(sheet.textures).filter((n) => !sheet.textures[n].rotate).sort();
  const plain = new PIXI.Container();
  const layer = new DepthCulledSpriteContainer();
  const set = layer.setPolygonsFromSpritesheet(sheet);
  const place = (s, i, k) => {
    s.anchor.set(0.5);
    s.scale.set(...[[1, 1], [2, 2], [-1, 1], [1, -2]][k]);
    s.position.set(24 + k * 56, 16 + i * 28 + (k % 2) * 3);
    return s;
  };
  names.forEach((n, i) => [0, 1, 2, 3].forEach((k) => {
    plain.addChild(place(new PIXI.Sprite(sheet.textures[n]), i, k));
    layer.addSprite(place(new PIXI.Sprite(sheet.textures[n]), i, k));
  }));
  app.stage.addChild(new PIXI.Graphics().rect(0, 0, width, height).fill(0x336699), plain, layer);
  layer.visible = false;
  app.renderer.render(app.stage);
  const a = readPixels(app.renderer.gl);
  plain.visible = false;
  layer.visible = true;
  app.renderer.render(app.stage);
  const b = readPixels(app.renderer.gl);
  let differ = 0;
  for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) ++differ;
  const stats = layer.stats;
  app.destroy(true, { children: true });
  return { differ, frames: names.length, set, stats };
};
window.depthcullReady = true;
