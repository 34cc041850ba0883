import type * as Phaser from 'phaser';
import type { Meshes } from './meshes.js';
import type { FrameAssembler, FrameSprite, FrameStats } from './frames.js';
export declare function webgl2Context(canvas: HTMLCanvasElement | OffscreenCanvas, attributes?: WebGLContextAttributes): WebGL2RenderingContext;
export declare function polygonMesh2D(scene: Phaser.Scene, x: number, y: number, texture: string | Phaser.Textures.Texture, frame: string | number,
  options?: { originX?: number; originY?: number; ordered?: boolean }): Phaser.GameObjects.Mesh2D;
export declare function atlasMeshes(scene: Phaser.Scene, texture: string | Phaser.Textures.Texture, options?: { originX?: number; originY?: number }):
  Record<string, { vertices: number[]; indices: number[] }>;
export declare class DepthCulledExtern extends Phaser.GameObjects.Extern {
  constructor(scene: Phaser.Scene, meshes: Meshes, textures: (string | Phaser.Textures.Texture | null)[]);
  static from(scene: Phaser.Scene, url: string, options?: { name?: string }): Promise<DepthCulledExtern>;
  meshes: Meshes;
  stats: { draws: number; triangles: number };
  /** Moving sprites at the meshes' insertion points: `textures` by the assembler's texture numbers; then set movingSprites each frame. */
  setMovingSprites(assembler: FrameAssembler, textures: (string | Phaser.Textures.Texture)[]): void;
  /** One sprite list per insertion point (one list on top without points), drawn at the next render. */
  movingSprites: FrameSprite[] | FrameSprite[][] | null;
  /** The last frame's assembler stats. */
  frameStats: FrameStats | null;
}
