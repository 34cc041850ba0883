import type { FrameAssembler } from './frames.js';
import type { Meshes } from './meshes.js';
// TypeScript declarations for src/index.js.

/** Thrown for every refused input, with the CLI's one-line message. */
export class DepthcullError extends Error {
  name: 'DepthcullError';
}

/** A polygon: [x, y] vertices in texel coordinates of the whole image, clockwise with y down. */
export type Polygon = Array<[number, number]>;

export interface Rect {
  x: number;
  y: number;
  width: number;
  height: number;
}

/** ImageData, or anything with its shape: RGBA8, rows packed, not premultiplied (only alpha matters). */
export interface ImageLike {
  width: number;
  height: number;
  data: Uint8Array | Uint8ClampedArray;
}

/** `depthcull analyze`'s options, under JavaScript names; omitted ones take the CLI's defaults. */
export interface AnalyzeOptions {
  /** --max-vertices: most vertices per boundary polygon, 4..1000 (10). */
  maxVertices?: number;
  /** false for --no-split: one boundary polygon per image (true). */
  split?: boolean;
  /** --filter: the texture filtering the polygons must be correct for ('nearest'). */
  filter?: 'nearest' | 'linear';
  /** --opaque: the opaque polygon algorithm ('fast'). */
  opaque?: 'fast' | 'grow' | 'paper';
  /** --max-opaque: most opaque polygons, 0..64 (4; 0 disables). */
  maxOpaque?: number;
  /** --min-coverage: stop adding opaque polygons at this fraction of opaque texels covered, 0..1 (0.75). */
  minCoverage?: number;
  /** --min-opaque-area: texels a new opaque polygon must add, 1..2^30 (64). */
  minOpaqueArea?: number;
  /** The texels to analyze, as IMAGE:x,y,w,h (the whole image). */
  rect?: Rect;
  /** Starts each error message, as the CLI's start with the file's path ('image'). */
  name?: string;
}

/** The analyzer's figures; best cases: boundary_area == nontransparent_texels, opaque_coverage == 1. */
export interface ImageStats {
  nontransparent_texels: number;
  opaque_texels: number;
  boundary_area: number;
  bbox_area: number;
  boundary_vertices: number;
  opaque_area: number;
  opaque_covered_texels: number;
  opaque_coverage: number;
}

export interface ImageAnalysis {
  rect: Rect;
  /** Paper 2.1: every non-transparent texel lies inside one of them; empty when all are transparent. */
  boundary: Polygon[];
  /** Paper 2.2: convex, touching only opaque texels. */
  opaque: Polygon[];
  stats: ImageStats;
}

export interface LoadOptions {
  /** Where depthcull.wasm is: a URL, its bytes, a fetch Response or a compiled module (default: dist/depthcull.wasm in this package). */
  wasm?: URL | string | ArrayBuffer | ArrayBufferView | Response | WebAssembly.Module;
  /** Where the wasm's stdout/stderr lines go (console.error). */
  log?: (line: string) => void;
}

/** A scene image: a file's decoded RGBA8 texels, or a `fill` colour (no pixels). */
export interface SceneImageInput {
  id?: string;
  /** The file: images with the same path (and key) share analyses and meshes, as in the CLI. */
  path?: string;
  /** A colour key "rrggbb" (Tiled's trans): texels of exactly that colour become transparent. */
  trans?: string;
  /** A solid colour "rrggbb" (a map's backgroundcolor): 16x16, no pixels needed. */
  fill?: string;
  width?: number;
  height?: number;
  data?: Uint8Array | Uint8ClampedArray;
}

/** The scene JSON `depthcull import` writes, with each image's pixels added. */
export interface SceneInput {
  viewport: { x?: number; y?: number; width: number; height: number };
  filter?: 'nearest' | 'linear';
  images: SceneImageInput[];
  /** `image`: an image id or index; `animation`: an index into `animations` (the element shows its frame 0). */
  elements: { image: string | number; rect?: [number, number, number, number] | Rect; transform?: [number, number, number, number, number, number]; color?: [number, number, number, number]; blend?: 'alpha' | 'add' | 'multiply' | 'opaque'; animation?: number }[];
  animations?: { frames: { image: string | number; rect: [number, number, number, number] | Rect; duration?: number }[] }[];
  /** Element indices where moving sprites go (levels from ReconstructOptions.insertionLevels). */
  insertion_points?: number[];
  /** The insertion points outright (instead of insertion_points). */
  insertionPoints?: { element: number; levels: number }[];
}

/** A profile `depthcull calibrate` wrote (docs/cost-model.md). */
export interface CostProfileJson {
  depthcull_profile: 1;
  name?: string;
  renderer?: string;
  source?: string;
  frame_us: number;
  clear_color_ns_per_pixel: number;
  clear_depth_ns_per_pixel: number;
  draw_call_us: number;
  texture_switch_us: number;
  triangle_us: number;
  triangle_perimeter_ns_per_pixel: number;
  fragment_opaque_ns: number;
  fragment_blend_ns: number;
  fragment_rejected_ns: number;
  min_opaque_area?: number;
  wall?: unknown;
}

export type ReconstructOptions = Omit<AnalyzeOptions, 'rect' | 'name' | 'filter'> & {
  /** false: optimize --no-opaque. */
  opaquePolygons?: boolean;
  /** optimize --target: a built-in profile name (llvmpipe, ipad1), or a calibrated profile (its JSON text or object). */
  target?: string | CostProfileJson;
  /** optimize --insert-at INDEX. */
  insertAt?: number[];
  /** optimize --insertion-levels (default 1024 with insertAt, else 0: none). */
  insertionLevels?: number;
};

export interface TargetReport {
  predictedMs: number;
  meshesOnlyMs: number;
  overpaintMs: number;
  elementsDropped: number;
  elementsOpaque: number;
  elementsReverted: number;
}

export class Depthcull {
  private constructor();
  /** Boundary and opaque polygons of an image, as `depthcull analyze` computes them. Throws DepthcullError. */
  analyzeImage(image: ImageLike, options?: AnalyzeOptions): ImageAnalysis;
  /**
   * Paper 2.3 in the wasm, as `depthcull optimize` does it for the same
   * scene JSON (colour keys, fills, animations, insertion points, --target
   * with a built-in or calibrated profile): meshes as parseMeshes returns them.
   */
  reconstructScene(scene: SceneInput, options?: ReconstructOptions): Meshes & { target?: TargetReport };
  /** Moving sprites depth-culled every frame (src/frames.js). */
  createFrameAssembler(options?: { opaquePass?: boolean; filter?: 'nearest' | 'linear' }): FrameAssembler;
}

export function loadDepthcull(options?: LoadOptions): Promise<Depthcull>;
