// GPU residency: one 3D texture of brick slots (each (B + 1)^3 texels, corner samples, so
// hardware trilinear filtering inside a slot is exact), and per texture an indirection 3D
// texture with one mip level per brick level: texel (x, y, z) of mip l holds the slot of brick
// (x, y, z) of level l, alpha 255 when resident. Least recently wanted slots are reused.
import type { DecodedBrick } from "./brick_decoder";

export const BRICK = 16;
export const SLOT = BRICK + 1;

export interface BrickKey {
  texture: number; // index into the viewer's textures
  level: number;
  x: number;
  y: number;
  z: number;
}

export const keyString = (k: BrickKey): string => `${k.texture}/${k.level}/${k.x}/${k.y}/${k.z}`;

interface Slot {
  key: BrickKey | null;
  lastWanted: number;
}

export class BrickPool {
  readonly texture: WebGLTexture;
  readonly slotsPerAxis: number;
  private readonly slots: Slot[] = [];
  private readonly resident = new Map<string, number>(); // key -> slot
  private readonly rgba = new Uint8Array(SLOT * SLOT * SLOT * 4);

  constructor(private readonly gl: WebGL2RenderingContext, slotsPerAxis: number) {
    this.slotsPerAxis = slotsPerAxis;
    const size = slotsPerAxis * SLOT;
    this.texture = gl.createTexture()!;
    gl.bindTexture(gl.TEXTURE_3D, this.texture);
    gl.texStorage3D(gl.TEXTURE_3D, 1, gl.RGBA8, size, size, size);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    for (const wrap of [gl.TEXTURE_WRAP_S, gl.TEXTURE_WRAP_T, gl.TEXTURE_WRAP_R]) {
      gl.texParameteri(gl.TEXTURE_3D, wrap, gl.CLAMP_TO_EDGE);
    }
    for (let i = 0; i < slotsPerAxis ** 3; ++i) this.slots.push({ key: null, lastWanted: -1 });
  }

  get capacity(): number {
    return this.slots.length;
  }
  get residentCount(): number {
    return this.resident.size;
  }
  has(key: BrickKey): boolean {
    return this.resident.has(keyString(key));
  }
  touch(key: BrickKey, frame: number): void {
    const slot = this.resident.get(keyString(key));
    if (slot !== undefined) this.slots[slot].lastWanted = frame;
  }

  // A slot for a new brick: a free one, else the least recently wanted one not wanted in
  // `frame`; null when every slot holds a brick the current view wants.
  private allocate(frame: number, evicted: (key: BrickKey) => void): number | null {
    let best = -1;
    for (let i = 0; i < this.slots.length; ++i) {
      const slot = this.slots[i];
      if (slot.key === null) return i;
      if (slot.lastWanted < frame && (best < 0 || slot.lastWanted < this.slots[best].lastWanted)) best = i;
    }
    if (best < 0) return null;
    const old = this.slots[best].key!;
    this.resident.delete(keyString(old));
    evicted(old);
    this.slots[best].key = null;
    return best;
  }

  // Uploads the brick's colour (planes R, G, B; one plane is grey) and returns its slot's
  // coordinates, or null when the pool is full of wanted bricks.
  upload(key: BrickKey, brick: DecodedBrick, frame: number, evicted: (key: BrickKey) => void): [number, number, number] | null {
    const index = this.allocate(frame, evicted);
    if (index === null) return null;
    const n = SLOT * SLOT * SLOT;
    const planes = brick.channels >= 3 ? [0, 1, 2] : [0, 0, 0];
    for (let i = 0; i < n; ++i) {
      this.rgba[4 * i] = brick.samples[planes[0] * n + i];
      this.rgba[4 * i + 1] = brick.samples[planes[1] * n + i];
      this.rgba[4 * i + 2] = brick.samples[planes[2] * n + i];
      this.rgba[4 * i + 3] = 255;
    }
    const s = this.slotsPerAxis;
    const at: [number, number, number] = [index % s, Math.floor(index / s) % s, Math.floor(index / (s * s))];
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_3D, this.texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texSubImage3D(gl.TEXTURE_3D, 0, at[0] * SLOT, at[1] * SLOT, at[2] * SLOT, SLOT, SLOT, SLOT, gl.RGBA, gl.UNSIGNED_BYTE, this.rgba);
    this.slots[index] = { key, lastWanted: frame };
    this.resident.set(keyString(key), index);
    return at;
  }
}

// One texture's indirection: mip level l is (2^(L - 4) >> l)^3 texels.
export class Indirection {
  readonly texture: WebGLTexture;
  constructor(private readonly gl: WebGL2RenderingContext, readonly levels: number, readonly bricksPerAxis0: number) {
    this.texture = gl.createTexture()!;
    gl.bindTexture(gl.TEXTURE_3D, this.texture);
    gl.texStorage3D(gl.TEXTURE_3D, levels, gl.RGBA8, bricksPerAxis0, bricksPerAxis0, bricksPerAxis0);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MIN_FILTER, gl.NEAREST_MIPMAP_NEAREST);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    for (let l = 0; l < levels; ++l) {
      const n = bricksPerAxis0 >> l;
      gl.texSubImage3D(gl.TEXTURE_3D, l, 0, 0, 0, n, n, n, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(n * n * n * 4));
    }
  }

  set(key: BrickKey, slot: [number, number, number] | null): void {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_3D, this.texture);
    const texel = slot ? new Uint8Array([slot[0], slot[1], slot[2], 255]) : new Uint8Array(4);
    gl.texSubImage3D(gl.TEXTURE_3D, key.level, key.x, key.y, key.z, 1, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, texel);
  }

  dispose(): void {
    this.gl.deleteTexture(this.texture);
  }
}
