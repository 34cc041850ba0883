// PixiJS v8: a depthcull scene (the JSON `depthcull import` writes) as
// plain Pixi sprites, one per element, in the scene's order: the reference
// a DepthCulledLayer is compared with (npm run bench, web/examples), and a
// way to show a scene before or without its meshes.
import { Container, ImageSource, Matrix, Rectangle, Sprite, Texture, Assets } from 'pixi.js';
import { DepthcullError } from './index.js';

async function keyedSource(url, trans) {
  const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const ctx = canvas.getContext('2d');
  ctx.drawImage(bitmap, 0, 0);
  const data = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
  const [r, g, b] = [0, 2, 4].map((k) => parseInt(trans.slice(k, k + 2), 16));
  const px = data.data;
  // The colour key becomes transparent, as the CLI reads a `trans` image.
  for (let i = 0; i < px.length; i += 4) if (px[i] === r && px[i + 1] === g && px[i + 2] === b) px[i] = px[i + 1] = px[i + 2] = px[i + 3] = 0;
  ctx.putImageData(data, 0, 0);
  return new ImageSource({ resource: canvas, scaleMode: 'nearest', alphaMode: 'premultiply-alpha-on-upload' });
}

/**
 * The scene's images as Pixi texture sources by id, nearest filtering:
 * files by `path` resolved against `baseUrl` (the scene's URL), `trans`
 * colour keys applied, `fill` images as 16x16 of their colour.
 */
export async function loadSceneSources(scene, baseUrl) {
  const out = new Map();
  for (const img of scene.images) {
    let source;
    if (img.fill) {
      const canvas = new OffscreenCanvas(16, 16);
      const ctx = canvas.getContext('2d');
      ctx.fillStyle = `#${img.fill.replace('#', '')}`;
      ctx.fillRect(0, 0, 16, 16);
      source = new ImageSource({ resource: canvas, scaleMode: 'nearest' });
    } else if (img.trans) source = await keyedSource(new URL(img.path, baseUrl).href, img.trans.replace('#', ''));
    else {
      source = (await Assets.load({ src: new URL(img.path, baseUrl).href, loadParser: 'loadTextures' })).source;
      source.scaleMode = 'nearest';
    }
    out.set(img.id, source);
  }
  return out;
}

const PIXI_BLEND = { alpha: 'normal', add: 'add', multiply: 'multiply' };

/** A Container of one Sprite per element (rect, transform, colour, blend), in world pixels. */
export function sceneSprites(scene, sources) {
  const c = new Container();
  for (const [n, e] of scene.elements.entries()) {
    const source = sources.get(e.image);
    if (!source) throw new DepthcullError(`sceneSprites: elements[${n}]: no source for image "${e.image}"`);
    const [x, y, w, h] = e.rect ?? [0, 0, source.width, source.height];
    const s = new Sprite(new Texture({ source, frame: new Rectangle(x, y, w, h) }));
    const [a, b, cc, d, tx, ty] = e.transform ?? [1, 0, 0, 1, 0, 0];
    s.setFromMatrix(new Matrix(a, b, cc, d, tx, ty));
    if (e.color) {
      s.tint = e.color.slice(0, 3);
      s.alpha = e.color[3];
    }
    const blend = PIXI_BLEND[e.blend ?? 'alpha'];
    if (!blend) throw new DepthcullError(`sceneSprites: elements[${n}]: blend "${e.blend}" has no Pixi equivalent`);
    s.blendMode = blend;
    c.addChild(s);
  }
  return c;
}
