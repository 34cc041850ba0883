// The example page: a Tiled map (meadow-map.tmx, imported and optimized by
// the CLI when `npm run examples` starts) drawn by a DepthCulledLayer, with
// sprites moving over it in a DepthCulledSpriteContainer, the camera
// scrolling. The checkbox swaps both for plain Pixi sprites (the same
// pixels), to compare the stats and the frame time.
import * as PIXI from 'pixi.js';
import { loadDepthcull } from '../src/index.js';
import { loadMeshes } from '../src/meshes.js';
import { DepthCulledLayer } from '../src/pixi.js';
import { DepthCulledSpriteContainer } from '../src/pixi-sprites.js';
import { loadSceneSources, sceneSprites } from '../src/pixi-scene.js';

const width = 640, height = 480;
const app = new PIXI.Application();
await app.init({ width, height, preference: 'webgl', antialias: false, background: 0x000000 });
document.body.appendChild(app.canvas);

const scene = await (await fetch('/gen/map.scene.json')).json();
const meshes = await loadMeshes('/gen/map.meshes.json');
const sources = await loadSceneSources(scene, location.href);

// The map: depth-culled, and as plain sprites for comparison.
const world = new PIXI.Container();
app.stage.addChild(world);
const layer = new DepthCulledLayer(meshes, meshes.images.map((img) => sources.get(img.id)));
const plainMap = sceneSprites(scene, sources);

// Moving sprites: ordinary Pixi sprites, analysed by the wasm core at first use.
const depthcull = await loadDepthcull();
const names = ['flower', 'ring', 'moons', 'glow', 'rock'];
const textures = {};
for (const n of names) {
  textures[n] = await PIXI.Assets.load(`/examples/art/${n}.png`);
  textures[n].source.scaleMode = 'nearest';
}
const movers = new DepthCulledSpriteContainer({ depthcull });
const plainMovers = new PIXI.Container();
const rnd = (() => { let s = 1; return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32); })();
const walkers = Array.from({ length: 60 }, () => ({
  name: names[Math.floor(rnd() * names.length)],
  x: rnd() * meshes.viewport.width, y: rnd() * meshes.viewport.height,
  vx: (rnd() - 0.5) * 3, vy: (rnd() - 0.5) * 3,
}));
for (const w of walkers) {
  for (const parent of [movers.sprites, plainMovers]) {
    const s = new PIXI.Sprite(textures[w.name]);
    s.anchor.set(0.5);
    if (w.name === 'glow') s.blendMode = 'add';
    parent.addChild(s);
  }
}

const culled = document.getElementById('culled');
const scroll = document.getElementById('scroll');
const stats = document.getElementById('stats');
function show() {
  world.removeChildren();
  world.addChild(...(culled.checked ? [layer, movers] : [plainMap, plainMovers]));
}
culled.onchange = show;
show();

let t = 0, frames = 0, last = performance.now(), fps = 0;
app.ticker.add((ticker) => {
  if (scroll.checked) t += ticker.deltaTime;
  // The camera wanders over the map; whole pixels keep nearest sampling crisp.
  const cx = Math.round((meshes.viewport.width - width) * (0.5 + 0.5 * Math.sin(t / 400)));
  const cy = Math.round((meshes.viewport.height - height) * (0.5 + 0.5 * Math.sin(t / 290)));
  world.position.set(-cx, -cy);
  walkers.forEach((w, k) => {
    w.x = (w.x + w.vx * ticker.deltaTime + meshes.viewport.width) % meshes.viewport.width;
    w.y = (w.y + w.vy * ticker.deltaTime + meshes.viewport.height) % meshes.viewport.height;
    movers.sprites.children[k].position.set(Math.round(w.x), Math.round(w.y));
    plainMovers.children[k].position.set(Math.round(w.x), Math.round(w.y));
  });
  ++frames;
  const now = performance.now();
  if (now - last > 500) {
    fps = (frames * 1000) / (now - last);
    frames = 0;
    last = now;
    stats.textContent = culled.checked
      ? `map: ${layer.stats.draws} draws, ${layer.stats.triangles} triangles; sprites: ${movers.stats.draws} draws, ${movers.stats.opaqueSprites}/${movers.stats.sprites} in the opaque pass; ${fps.toFixed(1)} fps`
      : `plain Pixi: ${scene.elements.length} + ${walkers.length} sprites; ${fps.toFixed(1)} fps`;
  }
});
window.depthcullExampleReady = true;
