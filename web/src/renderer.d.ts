import type { Meshes } from './meshes.js';
import type { AssembledFrame } from './frames.js';
export interface FrameStats { draws: number; triangles: number }
export declare function cameraMatrix(camera: { x?: number; y?: number; width: number; height: number; flipY?: boolean }): Float32Array;
export declare class MeshRenderer {
  constructor(gl: WebGL2RenderingContext, options?: { premultipliedAlpha?: boolean; fragmentPrecision?: 'highp' | 'mediump' });
  stats: FrameStats;
  /** `colorByte`: colours fed to the shader as these bytes (PixiJS's) instead of floats. */
  setMeshes(meshes: Meshes, options?: { colorByte?: (c: number, channel: number) => number }): void;
  setTextures(textures: (WebGLTexture | null)[]): void;
  uploadImages(sources: (TexImageSource | null)[], options?: { fillsOnly?: boolean }): (WebGLTexture | null)[];
  /** `frame`: moving sprites (FrameAssembler.assemble's result) drawn with the meshes; its draws name `frameTextures` (default the meshes' textures); `frameColorByte`: its colours as these bytes. */
  draw(options?: { matrix?: Float32Array; camera?: { x?: number; y?: number; width: number; height: number }; clearDepth?: boolean; frame?: AssembledFrame; frameTextures?: (WebGLTexture | null)[]; frameColorByte?: (c: number, channel: number) => number }): FrameStats;
  destroy(): void;
}
