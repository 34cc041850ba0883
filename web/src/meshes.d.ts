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
}
export declare const limits: Readonly<Record<string, number>>;
export declare function parseMeshesJson(text: string | object, options?: { name?: string; baseUrl?: string }): Meshes;
export declare function parseMeshes(data: string | ArrayBuffer | ArrayBufferView, options?: { name?: string; baseUrl?: string }): Meshes;
export declare function parseMeshesBinary(bytes: Uint8Array, options?: { name?: string }): Meshes;
export declare function loadMeshes(url: string | URL, options?: { name?: string; fetch?: typeof fetch }): Promise<Meshes>;
