import type { Container, TextureSource } from 'pixi.js';
export interface SceneJson {
  viewport: { x: number; y: number; width: number; height: number };
  images: { id: string; path?: string; trans?: string; fill?: string }[];
  elements: { image: string; rect?: [number, number, number, number]; transform?: [number, number, number, number, number, number]; color?: [number, number, number, number]; blend?: 'alpha' | 'add' | 'multiply' }[];
}
export declare function loadSceneSources(scene: SceneJson, baseUrl: string | URL): Promise<Map<string, TextureSource>>;
export declare function sceneSprites(scene: SceneJson, sources: Map<string, TextureSource>): Container;
