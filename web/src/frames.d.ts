import type { Meshes } from './meshes.js';
export interface FrameSprite {
  image?: number;
  animation?: number;
  frame?: number;
  /** screen = (a*u + c*v + e, b*u + d*v + f), u, v texels of the picture; or x, y */
  transform?: [number, number, number, number, number, number];
  x?: number;
  y?: number;
  color?: [number, number, number, number];
  blend?: 'alpha' | 'add' | 'multiply' | 'opaque';
}
export interface FrameStats { sprites: number; drawCalls: number; opaqueDraws: number; triangles: number; blendBatches: number; overBudget: number }
export interface AssembledFrame {
  vertices: Float32Array;
  indices: Uint32Array;
  /** 5 numbers a draw: texture, pass (0 opaque, 1 blend), blend (0 alpha, 1 add, 2 multiply, 3 opaque), first index, index count */
  draws: Uint32Array;
  drawCount: number;
  opaqueDraws: number;
  /** 3 numbers a point: static draw, first draw, end draw */
  points: Uint32Array;
  pointCount: number;
  depthTest: boolean;
  stats: FrameStats;
}
export declare class FrameAssembler {
  addImage(image: { width: number; height: number; data: Uint8Array | Uint8ClampedArray }, options?: { texture?: number; rect?: { x: number; y: number; width: number; height: number }; name?: string; [option: string]: unknown }): number;
  addAnimation(ids: number[]): number;
  setStaticMeshes(meshes: Meshes | null): void;
  assemble(sprites: FrameSprite[] | FrameSprite[][], bounds: { x?: number; y?: number; width: number; height: number }): AssembledFrame;
  free(): void;
}
