import type { Container, RenderContainer, Sprite, Spritesheet, Texture } from 'pixi.js';
import type { AnalyzeOptions, Polygon } from './index.js';
export declare class DepthCulledSpriteContainer extends RenderContainer {
  constructor(options?: { depthcull?: { analyzeImage: Function } | null; analyze?: AnalyzeOptions; label?: string });
  /** The sprites drawn, in order (later ones in front); outside the scene graph. */
  sprites: Container<Sprite>;
  addSprite(...sprites: Sprite[]): Sprite;
  setPolygons(texture: Texture, polygons: { boundary: Polygon[]; opaque?: Polygon[] }): void;
  setPolygonsFromSpritesheet(sheet: Spritesheet): number;
  stats: { draws: number; triangles: number; sprites: number; opaqueSprites: number };
}
