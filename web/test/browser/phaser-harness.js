// Runs in the page phaser.html: Phaser 4 drawing the same things two ways
// in one game, frames compared pixel for pixel. window.phaserTest is what
// test/phaser.test.js calls.
//   mesh2d: atlas frames as Images, then as polygonMesh2D (our polygons).
//   layer: a scene's elements as Images, then as one DepthCulledExtern.
//   layerMoving: the same with moving sprites at an insertion point, as
//     Images among the elements, then as the layer's moving sprites.
import * as Phaser from 'phaser';
import { DepthCulledExtern, polygonMesh2D, webgl2Context } from '../../src/phaser.js';
import { loadMeshes } from '../../src/meshes.js';
import { loadDepthcull } from '../../src/index.js';
import { compareFrames, readPixels, rendererString } from './compare.js';

// A game on a WebGL 2 context with depth, nearest filtering, no rounding;
// resolves once the scene's preload has finished, with the scene.
function makeGame(width, height, preload) {
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  document.body.appendChild(canvas);
  const context = webgl2Context(canvas, { preserveDrawingBuffer: true });
  return new Promise((resolve, reject) => {
    const game = new Phaser.Game({
      type: Phaser.WEBGL, canvas, context, width, height, backgroundColor: '#000000', banner: false,
      audio: { noAudio: true },
      render: { antialias: false, antialiasGL: false, roundPixels: false, preserveDrawingBuffer: true },
      scene: {
        preload() {
          this.load.on('loaderror', (f) => reject(new Error(`cannot load ${f.src}`)));
          preload(this);
        },
        create() {
          resolve({ game, scene: this });
        },
      },
    });
  });
}

// The pixels of the next frame Phaser draws.
function nextFrame(game) {
  return new Promise((resolve) => game.events.once('postrender', () => resolve(readPixels(game.renderer.gl))));
}

function destroy(game, canvas) {
  game.destroy(false);
  canvas?.remove();
}

// A rotated TexturePacker frame (stored turned 90 degrees clockwise: the
// page holds h x w texels; sprite texel (u, v) is page texel (h - 1 - v,
// u)) as an Image of that page rectangle turned -90 degrees, placed where
// a Sprite of the frame with origin 0.5 at (x, y), scaled (sx, sy), shows
// it: local (u, v) = (trimX - srcW / 2 + pv, trimY - srcH / 2 + h - pu).
function uprightImage(scene, tex, f, x, y, sx, sy) {
  const { x: fx, y: fy, w, h } = f.frame;
  const key = `page${fx},${fy},${h},${w}`;
  if (!tex.has(key)) tex.add(key, 0, fx, fy, h, w);
  const lx = f.spriteSourceSize.x - f.sourceSize.w / 2, ly = f.spriteSourceSize.y - f.sourceSize.h / 2;
  return scene.add.image(x + sx * lx, y + sy * (ly + h), 'sheet', key).setOrigin(0).setScale(sy, sx).setRotation(-Math.PI / 2);
}

// Scene element n as the Phaser Image that draws it in a plain game
// (its rect a frame of its image, its transform, tint, alpha and blend);
// its rect and transform are pushed onto `elements` for the comparison.
function elementImage(scene, e, n, elements) {
  const blends = { alpha: Phaser.BlendModes.NORMAL, add: Phaser.BlendModes.ADD, multiply: Phaser.BlendModes.MULTIPLY };
  const tex = scene.textures.get(e.image);
  const rect = e.rect ?? [0, 0, tex.source[0].width, tex.source[0].height];
  const frame = `rect${rect.join(',')}`;
  if (!tex.has(frame)) tex.add(frame, 0, ...rect);
  const [a, b, c, d, tx, ty] = e.transform ?? [1, 0, 0, 1, 0, 0];
  elements.push({ rect, transform: [a, b, c, d, tx, ty] });
  // Phaser's Transform is translate * rotate * scale: no skew.
  const sx = Math.hypot(a, b), sy = (a * d - b * c) / sx;
  if (Math.abs(a * c + b * d) > 1e-12) throw new Error(`element ${n}: a skewed transform has no Phaser Image equivalent`);
  const img = scene.add.image(tx, ty, e.image, frame).setOrigin(0).setScale(sx, sy).setRotation(Math.atan2(b, a));
  if (e.color) {
    const [r, g, bl, al] = e.color;
    img.setTint((Math.round(r * 255) << 16) | (Math.round(g * 255) << 8) | Math.round(bl * 255));
    img.setAlpha(al);
  }
  img.setBlendMode(blends[e.blend ?? 'alpha']);
  return img;
}

// A game showing a scene's viewport over a plain backdrop, its images
// loaded with nearest filtering (the meshes' document and scene JSON read
// unless given).
async function sceneGame(sceneUrl, meshesUrl, doc, meshes) {
  doc ??= await (await fetch(sceneUrl)).json();
  meshes ??= await loadMeshes(meshesUrl);
  const { width, height } = meshes.viewport;
  const { game, scene } = await makeGame(width, height, (s) => {
    for (const img of doc.images) if (!img.fill) s.load.image(img.id, new URL(img.path, sceneUrl).href);
  });
  for (const img of doc.images) {
    if (img.fill || img.trans) throw new Error(`image ${img.id}: fill and trans images are not in this test`);
    scene.textures.get(img.id).setFilter(Phaser.Textures.FilterMode.NEAREST);
  }
  scene.cameras.main.setScroll(meshes.viewport.x, meshes.viewport.y);
  scene.add.rectangle(0, 0, width, height, 0x336699).setOrigin(0).setScrollFactor(0);
  return { doc, meshes, width, height, game, scene };
}

window.phaserTest = {
  // upright: the Images show each (rotated) frame from its page rectangle
  // as stored, turned back by -90 degrees, instead of by Phaser's frame
  // (whose rotated frames Phaser 4.2.1 draws transposed).
  async mesh2d({ atlasUrl, pageUrl, rotated = false, ordered = false, upright = false }) {
    const width = 256, height = 128;
    const { game, scene } = await makeGame(width, height, (s) => s.load.atlas('sheet', pageUrl, atlasUrl));
    const atlas = upright ? await (await fetch(atlasUrl)).json() : null;
    scene.textures.get('sheet').setFilter(Phaser.Textures.FilterMode.NEAREST);
    scene.add.rectangle(0, 0, width, height, 0x336699).setOrigin(0);
    const tex = scene.textures.get('sheet');
    const names = tex.getFrameNames().sort().filter((n) => tex.get(n).rotated === rotated);
    // Each frame plain, scaled 2 and mirrored (scale -1), with its origin.
    const variants = [[1, 1], [2, 2], [-1, 1], [1, -2]];
    const images = [], meshes = [];
    let triangles = 0, rectTriangles = 0;
    names.forEach((name, i) =>
      variants.forEach(([sx, sy], k) => {
        const x = 24 + k * 56, y = 16 + i * 28 + (k % 2) * 3;
        images.push(upright ? uprightImage(scene, tex, atlas.frames[name], x, y, sx, sy) : scene.add.image(x, y, 'sheet', name).setScale(sx, sy));
        const m = scene.add.existing(polygonMesh2D(scene, x, y, 'sheet', name, { ordered })).setScale(sx, sy);
        meshes.push(m);
        triangles += m.indices.length / 4;
        rectTriangles += 2;
      }),
    );
    // A half-transparent object in front of both.
    scene.add.rectangle(width / 4, height / 4, width / 2, height / 8, 0xffcc00, 0.5).setOrigin(0);
    meshes.forEach((m) => m.setVisible(false));
    images.forEach((m) => m.setVisible(false));
    const empty = await nextFrame(game); // the background and rectangle only
    images.forEach((m) => m.setVisible(true));
    const a = await nextFrame(game);
    images.forEach((m) => m.setVisible(false));
    meshes.forEach((m) => m.setVisible(true));
    const b = await nextFrame(game);
    let drawn = 0; // pixels the Images changed
    for (let i = 0; i < a.length; i += 4) if (a[i] !== empty[i] || a[i + 1] !== empty[i + 1] || a[i + 2] !== empty[i + 2]) ++drawn;
    let differ = 0, covered = 0;
    const examples = [];
    for (let i = 0; i < a.length; i += 4) {
      if (a[i] !== b[i] || a[i + 1] !== b[i + 1] || a[i + 2] !== b[i + 2] || a[i + 3] !== b[i + 3]) {
        if (++differ <= 5) examples.push(`(${(i / 4) % width},${height - 1 - Math.floor(i / 4 / width)}) image ${[...a.subarray(i, i + 4)]} mesh ${[...b.subarray(i, i + 4)]}`);
      }
      if (a[i] !== 0x33 || a[i + 1] !== 0x66 || a[i + 2] !== 0x99) ++covered;
    }
    if (window.keepFrames) window.keptFrames = { a: Array.from(a), b: Array.from(b), width, height };
    const glRenderer = rendererString(game.renderer.gl);
    destroy(game, game.canvas);
    return { differ, examples, covered, drawn, frames: names.length, objects: meshes.length, triangles, rectTriangles, glRenderer, webgl2: game.renderer.gl instanceof WebGL2RenderingContext };
  },

  async layer({ sceneUrl, meshesUrl, frames = 2 }) {
    const { doc, meshes, width, height, game, scene } = await sceneGame(sceneUrl, meshesUrl);
    const elements = [];
    const plain = doc.elements.map((e, n) => elementImage(scene, e, n, elements));
    const layer = scene.add.existing(new DepthCulledExtern(scene, meshes, meshes.images.map((img) => (img.fill ? null : img.id))));
    scene.add.rectangle(width / 4, height / 4, width / 2, height / 8, 0xffcc00, 0.5).setOrigin(0).setScrollFactor(0);
    layer.setVisible(false);
    const a = await nextFrame(game);
    plain.forEach((p) => p.setVisible(false));
    layer.setVisible(true);
    let result = { differ: 0, offEdges: 0, examples: [] };
    for (let f = 0; f < frames; ++f) {
      const b = await nextFrame(game);
      const r = compareFrames(elements, meshes.viewport, a, b, width, height);
      result = { differ: Math.max(result.differ, r.differ), offEdges: result.offEdges + r.offEdges, examples: result.examples.concat(r.examples).slice(0, 5) };
      let maxDiff = 0;
      for (let i = 0; i < a.length; ++i) maxDiff = Math.max(maxDiff, Math.abs(a[i] - b[i]));
      result.maxChannelDiff = Math.max(result.maxChannelDiff ?? 0, maxDiff);
      if (window.keepFrames) window.keptFrames = { a: Array.from(a), b: Array.from(b), width, height };
    }
    const glRenderer = rendererString(game.renderer.gl);
    const stats = layer.stats;
    destroy(game, game.canvas);
    return { ...result, width, height, elements: doc.elements.length, stats, glRenderer };
  },

  // A scene's elements as Images with `count` moving Images among them
  // before element `atElement` (plain Phaser, layer order), then as one
  // DepthCulledExtern with the same sprites given to its FrameAssembler at
  // the meshes' insertion point (made by optimize --insert-at atElement);
  // each of `frames` frames compared. Every tenth frame the Images drawn
  // on top of all elements are compared too (onTop*): what a layer drawing
  // its sprites on top would show, so the scene tells the two apart.
  async layerMoving({ sceneUrl, meshesUrl, frames = 60, count = 24, atElement }) {
    const doc = await (await fetch(sceneUrl)).json();
    const meshes = await loadMeshes(meshesUrl);
    if (meshes.insertionPoints.length !== 1) throw new Error(`expected one insertion point, the meshes have ${meshes.insertionPoints.length}`);
    const depthcull = await loadDepthcull();
    const { width, height, game, scene } = await sceneGame(sceneUrl, meshesUrl, doc, meshes);

    // Up to 6 pictures: whole images of untransformed-size elements, their
    // pixels decoded without premultiplication for the analysis.
    const assembler = depthcull.createFrameAssembler();
    const pictures = [], textures = [];
    for (const img of doc.images) {
      if (pictures.length >= 6 || !doc.elements.some((e) => e.image === img.id && !e.rect)) continue;
      const bitmap = await createImageBitmap(await (await fetch(new URL(img.path, sceneUrl).href)).blob(), { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
      const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
      const ctx = canvas.getContext('2d');
      ctx.drawImage(bitmap, 0, 0);
      const pixels = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
      const texture = textures.push(img.id) - 1;
      // Every third picture added: that image's sprites blend additively.
      pictures.push({ id: assembler.addImage(pixels, { texture, name: img.path }), key: img.id, w: bitmap.width, h: bitmap.height, add: pictures.length % 3 === 2 });
    }
    const place = (k, f) => {
      const p = pictures[k % pictures.length];
      // Whole pixels, a different path per sprite, crossing each other.
      const x = meshes.viewport.x + ((k * 97 + f * (3 + (k % 5))) % Math.max(1, width - p.w));
      const y = meshes.viewport.y + ((k * 61 + f * (2 + (k % 3))) % Math.max(1, height - p.h));
      return { p, x, y };
    };
    // Every fourth sprite tinted, on byte boundaries (0.7 * 255 = 178.5).
    const tint = { color: [1, 0.95, 0.7, 0.8], rgb: (255 << 16) | (Math.round(0.95 * 255) << 8) | Math.round(0.7 * 255) };
    const movingImages = () =>
      Array.from({ length: count }, (_, k) => {
        const { p } = place(k, 0);
        const img = scene.add.image(0, 0, p.key).setOrigin(0).setBlendMode(p.add ? Phaser.BlendModes.ADD : Phaser.BlendModes.NORMAL);
        if (k % 4 === 1) img.setTint(tint.rgb).setAlpha(tint.color[3]);
        return img;
      });

    const elements = [];
    const plain = [];
    let inOrder = null;
    doc.elements.forEach((e, n) => {
      if (n === atElement) inOrder = movingImages();
      plain.push(elementImage(scene, e, n, elements));
    });
    if (!inOrder) throw new Error(`atElement ${atElement}: the scene has ${doc.elements.length} elements`);
    const onTop = movingImages();
    const layer = scene.add.existing(new DepthCulledExtern(scene, meshes, meshes.images.map((img) => (img.fill ? null : img.id))));
    layer.setMovingSprites(assembler, textures);
    scene.add.rectangle(width / 4, height / 4, width / 2, height / 8, 0xffcc00, 0.5).setOrigin(0).setScrollFactor(0);
    const sprites = Array.from({ length: count }, () => ({ image: 0, x: 0, y: 0 }));
    const show = (list, on) => list.forEach((o) => o.setVisible(on));

    let result = { differ: 0, offEdges: 0, examples: [] };
    let onTopDiffer = 0, onTopOffEdges = 0, draws = 0, triangles = 0, frameOpaqueDraws = 0;
    for (let f = 0; f < frames; ++f) {
      for (let k = 0; k < count; ++k) {
        const { p, x, y } = place(k, f);
        inOrder[k].setPosition(x, y);
        onTop[k].setPosition(x, y);
        Object.assign(sprites[k], { image: p.id, x, y, blend: p.add ? 'add' : 'alpha', color: k % 4 === 1 ? tint.color : undefined });
      }
      layer.setVisible(false);
      show(onTop, false);
      show(plain, true);
      show(inOrder, true);
      const a = await nextFrame(game);
      if (f % 10 === 0) {
        show(inOrder, false);
        show(onTop, true);
        const c = await nextFrame(game);
        const r = compareFrames(elements, meshes.viewport, a, c, width, height);
        onTopDiffer += r.differ;
        onTopOffEdges += r.offEdges;
        show(onTop, false);
      }
      show(plain, false);
      show(inOrder, false);
      layer.movingSprites = [sprites];
      layer.setVisible(true);
      const b = await nextFrame(game);
      const r = compareFrames(elements, meshes.viewport, a, b, width, height);
      result = { differ: Math.max(result.differ, r.differ), offEdges: result.offEdges + r.offEdges, examples: result.examples.concat(r.examples.map((x) => `frame ${f}: ${x}`)).slice(0, 5) };
      draws = Math.max(draws, layer.stats.draws);
      triangles = Math.max(triangles, layer.stats.triangles);
      frameOpaqueDraws = Math.max(frameOpaqueDraws, layer.frameStats.opaqueDraws);
    }
    const glRenderer = rendererString(game.renderer.gl);
    assembler.free();
    destroy(game, game.canvas);
    return { ...result, onTopDiffer, onTopOffEdges, width, height, elements: doc.elements.length, sprites: count, pictures: pictures.length, frames, stats: { draws, triangles, frameOpaqueDraws }, glRenderer };
  },

  // DepthCulledExtern.from: loads the meshes and their images, adds the layer.
  async from({ meshesUrl }) {
    const { game, scene } = await makeGame(320, 240, () => {});
    const layer = await DepthCulledExtern.from(scene, meshesUrl);
    await nextFrame(game);
    const inList = scene.children.list.includes(layer);
    const stats = layer.stats;
    destroy(game, game.canvas);
    return { inList, stats };
  },

  // What setMovingSprites says of a texture key the game does not have.
  async movingTextureError({ meshesUrl }) {
    const meshes = await loadMeshes(meshesUrl);
    const depthcull = await loadDepthcull();
    const { game, scene } = await makeGame(64, 64, () => {});
    const layer = new DepthCulledExtern(scene, meshes, meshes.images.map(() => '__WHITE'));
    const assembler = depthcull.createFrameAssembler();
    let message = null;
    try {
      layer.setMovingSprites(assembler, ['__WHITE', 'no-such-texture']);
    } catch (e) {
      message = `${e.name}: ${e.message}`;
    }
    assembler.free();
    destroy(game, game.canvas);
    return message;
  },

  // What DepthCulledExtern says drawn into a DynamicTexture (no depth buffer).
  async dynamicTextureError({ meshesUrl }) {
    const meshes = await loadMeshes(meshesUrl);
    const { game, scene } = await makeGame(64, 64, () => {});
    const layer = new DepthCulledExtern(scene, meshes, meshes.images.map(() => '__WHITE'));
    const dt = scene.textures.addDynamicTexture('dt', 64, 64);
    let message = null;
    try {
      dt.draw(layer);
      dt.render();
    } catch (e) {
      message = `${e.name}: ${e.message}`;
    }
    destroy(game, game.canvas);
    return message;
  },

  // What DepthCulledExtern says in a game on Phaser's own WebGL 1 context.
  async webgl1Error({ meshesUrl }) {
    const meshes = await loadMeshes(meshesUrl);
    const canvas = document.createElement('canvas');
    return new Promise((resolve) => {
      const game = new Phaser.Game({
        type: Phaser.WEBGL, canvas, width: 64, height: 64, banner: false, audio: { noAudio: true },
        scene: {
          create() {
            try {
              const layer = this.add.existing(new DepthCulledExtern(this, meshes, meshes.images.map(() => '__WHITE')));
              layer.render(this.renderer, { width: 64, height: 64 }, { matrix: [1, 0, 0, 1, 0, 0] });
              resolve(null);
            } catch (e) {
              resolve(`${e.name}: ${e.message}`);
            }
            game.destroy(false);
          },
        },
      });
    });
  },
};
window.depthcullReady = true;
