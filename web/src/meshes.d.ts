export interface MeshImage { id: string; path: string; url: string; width: number; height: number; trans?: string; fill?: string }
export interface MeshDraw { image: number; pass: 'opaque' | 'blend'; blend: 'alpha' | 'add' | 'multiply' | 'opaque'; vertices: Float32Array; indices: Uint32Array }
export interface Meshes {
  viewport: { x: number; y: number; width: number; height: number };
  depthTest: boolean;
  filter: 'nearest' | 'linear';
  images: MeshImage[];
  draws: MeshDraw[];
  stats: { elements?: number; drawCalls?: number; triangles?: number; depthLevels?: number; depthBits?: number; graphEdges?: number; seconds?: number };
  animations: { frames: { image: number; rect: [number, number, number, number]; duration: number }[] }[];
  animated: { draw: number; firstVertex: number; vertexCount: number; animation: number }[];
  /** Where moving sprites go between the layers (docs/mesh-format.md "insertion_points"; binary flags bit 4). */
  insertionPoints: InsertionPoint[];
}
export interface InsertionPoint { element: number; levels: number; firstLevel: number; blendDraw: number }
export declare const limits: Readonly<Record<string, number>>;
export declare function parseMeshesJson(text: string | object, options?: { name?: string; baseUrl?: string }): Meshes;
export declare function parseMeshes(data: string | ArrayBuffer | ArrayBufferView, options?: { name?: string; baseUrl?: string }): Meshes;
export declare function parseMeshesBinary(bytes: ArrayBuffer | ArrayBufferView, options?: { name?: string; baseUrl?: string }): Meshes;
export declare function isBinaryMeshes(bytes: Uint8Array): boolean;
export declare function loadMeshes(url: string | URL, options?: { name?: string; fetch?: typeof fetch }): Promise<Meshes>;
