import type { Meshes } from './meshes.js';
export interface FrameStats { draws: number; triangles: number }
export declare function cameraMatrix(camera: { x?: number; y?: number; width: number; height: number; flipY?: boolean }): Float32Array;
export declare class MeshRenderer {
  constructor(gl: WebGL2RenderingContext, options?: { premultipliedAlpha?: boolean; fragmentPrecision?: 'highp' | 'mediump' });
  stats: FrameStats;
  setMeshes(meshes: Meshes, options?: { colorByte?: (c: number, channel: number) => number }): void;
  setTextures(textures: (WebGLTexture | null)[]): void;
  uploadImages(sources: (TexImageSource | null)[], options?: { fillsOnly?: boolean }): (WebGLTexture | null)[];
  draw(options?: { matrix?: Float32Array; camera?: { x?: number; y?: number; width: number; height: number }; clearDepth?: boolean }): FrameStats;
  destroy(): void;
}
