import type { RenderContainer, Texture, TextureSource, Assets } from 'pixi.js';
import type { Meshes } from './meshes.js';
import type { FrameAssembler, FrameSprite, FrameStats } from './frames.js';
export declare class DepthCulledLayer extends RenderContainer {
  constructor(meshes: Meshes, textures: (Texture | TextureSource | null)[], options?: object);
  static from(url: string, options: { Assets: typeof Assets; name?: string }): Promise<DepthCulledLayer>;
  meshes: Meshes;
  stats: { draws: number; triangles: number };
  /** Moving sprites each frame at the meshes' insertion points (src/frames.js). */
  setMovingSprites(assembler: FrameAssembler, textures: (Texture | TextureSource | null)[]): void;
  /** This frame's sprite lists, one per insertion point (FrameAssembler.assemble's input). */
  movingSprites: FrameSprite[][] | FrameSprite[] | null;
  frameStats: FrameStats | null;
}
/** A colour channel (0..1) as the normalized byte Pixi's batcher feeds its shader (channel 3: alpha). */
export declare function pixiColorByte(c: number, channel: number): number;
