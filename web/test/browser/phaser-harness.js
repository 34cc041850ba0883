// Runs in the page phaser.html: Phaser 4 drawing the same things two ways
// in one game, frames compared pixel for pixel. window.phaserTest is what
// test/phaser.test.js calls.
//   mesh2d: atlas frames as Images, then as polygonMesh2D (our polygons).
//   layer: a scene's elements as Images, then as one DepthCulledExtern.
import * as Phaser from 'phaser';
import { DepthCulledExtern, polygonMesh2D, webgl2Context } from '../../src/phaser.js';
import { loadMeshes } from '../../src/meshes.js';
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

window.phaserTest = {
  async mesh2d({ atlasUrl, pageUrl, rotated = false, ordered = false }) {
    const width = 256, height = 128;
    const { game, scene } = await makeGame(width, height, (s) => s.load.atlas('sheet', pageUrl, atlasUrl));
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
        images.push(scene.add.image(x, y, 'sheet', name).setScale(sx, sy));
        const m = scene.add.existing(polygonMesh2D(scene, x, y, 'sheet', name, { ordered })).setScale(sx, sy);
        meshes.push(m);
        triangles += m.indices.length / 4;
        rectTriangles += 2;
      }),
    );
    // A half-transparent object in front of both.
    scene.add.rectangle(width / 4, height / 4, width / 2, height / 8, 0xffcc00, 0.5).setOrigin(0);
    meshes.forEach((m) => m.setVisible(false));
    const a = await nextFrame(game);
    images.forEach((m) => m.setVisible(false));
    meshes.forEach((m) => m.setVisible(true));
    const b = await nextFrame(game);
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
    return { differ, examples, covered, frames: names.length, objects: meshes.length, triangles, rectTriangles, glRenderer, webgl2: game.renderer.gl instanceof WebGL2RenderingContext };
  },

  async layer({ sceneUrl, meshesUrl, frames = 2 }) {
    const doc = await (await fetch(sceneUrl)).json();
    const meshes = await loadMeshes(meshesUrl);
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
    const blends = { alpha: Phaser.BlendModes.NORMAL, add: Phaser.BlendModes.ADD, multiply: Phaser.BlendModes.MULTIPLY };
    const elements = [];
    const plain = doc.elements.map((e, n) => {
      const tex = scene.textures.get(e.image);
      const rect = e.rect ?? [0, 0, tex.source[0].width, tex.source[0].height];
      const frame = `rect${rect.join(',')}`;
      if (!tex.has(frame)) tex.add(frame, 0, ...rect);
      const [a, b, c, d, tx, ty] = e.transform ?? [1, 0, 0, 1, 0, 0];
      elements.push({ rect, transform: [a, b, c, d, tx, ty] });
      // Phaser's Transform is translate * rotate * scale: no skew.
      const sx = Math.hypot(a, b), sy = (a * d - b * c) / sx;
      if (Math.abs(a * c + b * d) > 1e-12)
        throw new Error(`element ${n}: a skewed transform has no Phaser Image equivalent`);
      const img = scene.add.image(tx, ty, e.image, frame).setOrigin(0).setScale(sx, sy).setRotation(Math.atan2(b, a));
      if (e.color) {
        const [r, g, bl, al] = e.color;
        img.setTint((Math.round(r * 255) << 16) | (Math.round(g * 255) << 8) | Math.round(bl * 255));
        img.setAlpha(al);
      }
      img.setBlendMode(blends[e.blend ?? 'alpha']);
      return img;
    });
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
