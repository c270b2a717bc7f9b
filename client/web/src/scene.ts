// The scene as soltex-scene-export writes it (client/web/export): the scene file's objects
// prepared by the C++ scene loader, so meshes, volumes and texture ids match soltex-view's.
import type { Vec3 } from "./math";

export interface Registration {
  texture: unknown;
  volume: { min: Vec3; max: Vec3; finest_level_log2: number };
  brick_size: number;
  mip_mode: string;
}

export interface SceneObject {
  name: string;
  positions: number[];
  normals: number[];
  texcoords: number[];
  indices: number[];
  registration: Registration;
  specular: number;
  shininess: number;
  unlit: boolean;
  double_sided: boolean;
  solid: boolean; // a clip plane shows its inside (a cap); a sheet shows its other side
  clip_planes: [number, number, number, number][];
  world_to_volume: number[]; // column-major 4x4
}

export interface PreparedScene {
  description: string;
  image: { width: number; height: number };
  camera: { position: Vec3; target: Vec3; up: Vec3; fov_y_degrees: number; near: number; far: number };
  ambient: Vec3;
  lights: ({ directional: { direction: Vec3; radiance: Vec3 } } | { point: { position: Vec3; radiance: Vec3 } })[];
  objects: SceneObject[];
}

// What POST /v1/textures answers (docs/PROTOCOL.md section 9).
export interface TextureHandle {
  id: string;
  levels: number;
  brick_size: number;
  finest_level_log2: number;
  channels: string[];
  bricks: string; // URL template with {level}/{x}/{y}/{z}, ending in ?spec=...
}

export async function loadScene(url: string): Promise<PreparedScene> {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`scene ${url}: HTTP ${response.status}`);
  return (await response.json()) as PreparedScene;
}

export async function registerTexture(server: string, registration: Registration): Promise<TextureHandle> {
  const response = await fetch(`${server}/v1/textures`, { method: "POST", body: JSON.stringify(registration) });
  if (!response.ok) throw new Error(`registering a texture: HTTP ${response.status}: ${await response.text()}`);
  return (await response.json()) as TextureHandle;
}

// Textures the viewer can switch an object to (keys 1 to 4), over the object's own volume.
export const PRESET_TEXTURES: unknown[] = [
  { marble: { frequency: 2 } },
  { wood: { ring_spacing: 0.15 } },
  { checker: { three_d: true, size: [0.25, 0.25, 0.25] } },
  { turbulence: {} },
];
