import type { RenderContainer, Texture, TextureSource, Assets } from 'pixi.js';
import type { Meshes } from './meshes.js';
export declare class DepthCulledLayer extends RenderContainer {
  constructor(meshes: Meshes, textures: (Texture | TextureSource | null)[], options?: object);
  static from(url: string, options: { Assets: typeof Assets; name?: string }): Promise<DepthCulledLayer>;
  meshes: Meshes;
  stats: { draws: number; triangles: number };
}
/** A colour channel (0..1) as the normalized byte Pixi's batcher feeds its shader (channel 3: alpha). */
export declare function pixiColorByte(c: number, channel: number): number;
