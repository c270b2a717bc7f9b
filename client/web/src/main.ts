// soltex in the browser: loads a prepared scene (soltex-scene-export), registers each object's
// texture with soltexd over HTTP, and draws it with WebGL2 from bricks fetched as the view
// needs them. URL parameters: scene (default scenes/default.json), server (default this page's
// origin), width and height (default: the scene's image scaled to this machine).
import { BRICK, BrickPool, Indirection, keyString, type BrickKey } from "./brick_pool";
import { BrickLoader, type Want } from "./brick_loader";
import { chooseCapability } from "./capability";
import { add, length, lookAt, multiply, normalize, perspective, scale, sub, transform, type Vec3 } from "./math";
import { Renderer, uploadMesh, type DrawObject } from "./renderer";
import { loadScene, PRESET_TEXTURES, registerTexture, type PreparedScene, type Registration, type TextureHandle } from "./scene";

interface ViewerTexture {
  handle: TextureHandle;
  indirection: Indirection;
}

interface ViewerObject {
  draw: DrawObject;
  registration: Registration;
  texture: number; // index into textures
  positions: number[];
  normals: number[];
  texcoords: number[];
  indices: number[];
  worldPerVolume: number; // world units per unit of texture-volume coordinate
}

// What a test (or a person) can read: whether the view has every brick it wants.
interface ViewerStatus {
  converged: boolean;
  frames: number;
  wanted: number;
  resident: number;
  error: string | null;
  stats?: unknown;
  textures?: number; // textures registered so far (one per distinct id)
}
declare global {
  interface Window {
    soltex: ViewerStatus;
  }
}

const params = new URLSearchParams(location.search);
const server = params.get("server") ?? location.origin;
const status: ViewerStatus = { converged: false, frames: 0, wanted: 0, resident: 0, error: null };
window.soltex = status;

function worldPerVolume(o: { positions: number[]; texcoords: number[] }): number {
  // The longest world-space edge over its texture-space length, from the first triangles.
  let best = 0;
  for (let i = 0; i + 5 < Math.min(o.positions.length, 300); i += 3) {
    const dw = Math.hypot(o.positions[i + 3] - o.positions[i], o.positions[i + 4] - o.positions[i + 1], o.positions[i + 5] - o.positions[i + 2]);
    const dt = Math.hypot(o.texcoords[i + 3] - o.texcoords[i], o.texcoords[i + 4] - o.texcoords[i + 1], o.texcoords[i + 5] - o.texcoords[i + 2]);
    if (dt > 1e-9) best = Math.max(best, dw / dt);
  }
  return best || 1;
}

async function main(): Promise<void> {
  const scene: PreparedScene = await loadScene(params.get("scene") ?? "scenes/default.json");
  const capability = chooseCapability(scene.image, params);
  const canvas = document.getElementById("view") as HTMLCanvasElement;
  canvas.width = capability.width;
  canvas.height = capability.height;
  const gl = canvas.getContext("webgl2", { antialias: false, preserveDrawingBuffer: true });
  if (!gl) throw new Error("this browser has no WebGL2");
  const pool = new BrickPool(gl, Math.min(capability.poolSlotsPerAxis, Math.floor(gl.getParameter(gl.MAX_3D_TEXTURE_SIZE) / 17)));
  const renderer = new Renderer(gl);
  const textures: ViewerTexture[] = [];
  const objects: ViewerObject[] = [];

  // One entry per texture id: switching back to a texture finds its indirection and the bricks
  // it left in the pool, and switching back and forth allocates nothing more on the GPU.
  const textureById = new Map<string, number>();
  const addTexture = async (registration: Registration): Promise<number> => {
    const handle = await registerTexture(server, registration);
    const known = textureById.get(handle.id);
    if (known !== undefined) return known;
    const indirection = new Indirection(gl, handle.levels, 1 << (handle.finest_level_log2 - Math.log2(BRICK)));
    textures.push({ handle, indirection });
    textureById.set(handle.id, textures.length - 1);
    return textures.length - 1;
  };
  for (const o of scene.objects) {
    const texture = await addTexture(o.registration);
    const t = textures[texture];
    objects.push({
      draw: {
        mesh: uploadMesh(gl, o.positions, o.normals, o.texcoords, o.indices),
        indirection: t.indirection.texture,
        levels: t.handle.levels,
        bricks0: 1 << (t.handle.finest_level_log2 - 4),
        specular: o.specular,
        shininess: o.shininess,
        unlit: o.unlit,
        doubleSided: o.double_sided,
        solid: o.solid ?? true, // scenes exported before the field: every mesh a solid
        clipPlanes: o.clip_planes,
        worldToVolume: new Float32Array(o.world_to_volume),
      },
      registration: o.registration,
      texture,
      positions: o.positions,
      normals: o.normals,
      texcoords: o.texcoords,
      indices: o.indices,
      worldPerVolume: worldPerVolume(o),
    });
  }

  const urlOf = (key: BrickKey): string =>
    server + textures[key.texture].handle.bricks.replace("{level}/{x}/{y}/{z}", `${key.level}/${key.x}/${key.y}/${key.z}`) + "&codec=lz4";
  let frame = 0;
  let dirty = true; // a brick arrived or the view moved: draw again
  let lastDraw = 0;
  let drawInterval = 100; // grows with what a frame costs here (readPixels waits for the frame)
  const loader = new BrickLoader(urlOf, capability.maxInFlight, (key, brick) => {
    const slot = pool.upload(key, brick, frame, (old) => textures[old.texture]?.indirection.set(old, null));
    if (slot) textures[key.texture].indirection.set(key, slot);
    dirty = true;
  });

  // The camera orbits its target: yaw and pitch about it, at a distance.
  const c = scene.camera;
  const offset = sub(c.position, c.target);
  let distance = length(offset);
  let yaw = Math.atan2(offset[0], offset[2]);
  let pitch = Math.asin(offset[1] / distance);
  const eye = (): Vec3 => add(c.target, scale([Math.sin(yaw) * Math.cos(pitch), Math.sin(pitch), Math.cos(yaw) * Math.cos(pitch)], distance));
  let viewChanged = true;
  let clip: number[] | null = null;
  let clipOffset = 0;
  let showLevels = false;

  const lights = {
    ambient: scene.ambient,
    directional: scene.lights.flatMap((l) => ("directional" in l ? [{ toLight: normalize(scale(l.directional.direction, -1)), radiance: l.directional.radiance }] : [])),
    point: scene.lights.flatMap((l) => ("point" in l ? [{ position: l.point.position, radiance: l.point.radiance }] : [])),
  };

  // The bricks the view wants. Each triangle is sampled on a barycentric grid fine enough to
  // touch every brick it crosses at its own level; each visible sample wants the level its pixel
  // footprint asks for, the next coarser one (the shader blends the two), and every coarser
  // ancestor (the fallback while finer bricks load).
  const computeWants = (viewProjection: Float32Array, camera: Vec3): Want[] => {
    const wants = new Map<string, Want>();
    const pixelAngle = (2 * Math.tan((c.fov_y_degrees * Math.PI) / 360)) / canvas.height;
    objects.forEach((o) => {
      const planes = clip ? [...o.draw.clipPlanes, clip] : o.draw.clipPlanes;
      const t = textures[o.texture];
      const levels = t.handle.levels;
      const bricks0 = 1 << (t.handle.finest_level_log2 - 4);
      const cell0 = o.worldPerVolume / (bricks0 * BRICK);
      const sample = (p: Vec3, n: Vec3, tc: number[]) => {
        if (planes.some((q) => q[0] * p[0] + q[1] * p[1] + q[2] * p[2] - q[3] > 0)) return;
        const clipPos = transform(viewProjection, p);
        const w = clipPos[3];
        if (w <= 0 || Math.abs(clipPos[0]) > 1.1 * w || Math.abs(clipPos[1]) > 1.1 * w) return;
        const toEye = sub(camera, p);
        if (!o.draw.doubleSided && planes.length === 0 && n[0] * toEye[0] + n[1] * toEye[1] + n[2] * toEye[2] < -1e-3 * length(toEye)) return;
        const d = length(toEye);
        // The shader takes the longer axis of the pixel's footprint, stretched by 1/cos on a
        // slanted surface.
        const facing = Math.max(0.05, Math.abs(n[0] * toEye[0] + n[1] * toEye[1] + n[2] * toEye[2]) / (d * (length(n) || 1)));
        const lod = Math.log2(Math.max((d * pixelAngle) / (cell0 * facing), 1e-9)) + capability.lodBias;
        const first = Math.min(levels - 1, Math.max(0, Math.floor(lod)));
        for (let level = first; level < levels; ++level) {
          const count = bricks0 >> level;
          const [x, y, z] = tc.map((v) => Math.min(count - 1, Math.max(0, Math.floor(v * count))));
          const key = { texture: o.texture, level, x, y, z };
          const id = keyString(key);
          const old = wants.get(id);
          if (!old || old.distance > d) wants.set(id, { key, distance: d });
        }
      };
      const at = (a: number[], i: number): Vec3 => [a[3 * i], a[3 * i + 1], a[3 * i + 2]];
      const idx = o.indices;
      for (let f = 0; f < idx.length; f += 3) {
        const [i0, i1, i2] = [idx[f], idx[f + 1], idx[f + 2]];
        const t0 = at(o.texcoords, i0), t1 = at(o.texcoords, i1), t2 = at(o.texcoords, i2);
        // Steps so that one step spans at most half a brick of the finest level any corner wants.
        const nearest = Math.min(length(sub(camera, at(o.positions, i0))), length(sub(camera, at(o.positions, i1))), length(sub(camera, at(o.positions, i2))));
        const level = Math.min(levels - 1, Math.max(0, Math.floor(Math.log2(Math.max((nearest * pixelAngle) / cell0, 1e-9)) + capability.lodBias)));
        const span = Math.max(length(sub(t1, t0)), length(sub(t2, t0)), length(sub(t2, t1))) * (bricks0 >> level);
        const k = Math.min(64, Math.ceil(span * 2));
        for (let a = 0; a <= k; ++a) {
          for (let b = 0; a + b <= k; ++b) {
            const u = k === 0 ? 1 / 3 : a / k, v = k === 0 ? 1 / 3 : b / k, w = 1 - u - v;
            const mix = (arr: number[]): Vec3 => {
              const p0 = at(arr, i0), p1 = at(arr, i1), p2 = at(arr, i2);
              return [p0[0] * w + p1[0] * u + p2[0] * v, p0[1] * w + p1[1] * u + p2[1] * v, p0[2] * w + p1[2] * u + p2[2] * v];
            };
            sample(mix(o.positions), mix(o.normals), mix(o.texcoords));
            if (k === 0) break;
          }
          if (k === 0) break;
        }
      }
    });
    return [...wants.values()];
  };

  let lastWants: Want[] = [];
  let framesDrawn = 0;
  let lastOverlay = performance.now();
  let shownConverged = false;
  const overlay = document.getElementById("overlay")!;
  // Draws a frame when the view changed or bricks arrived; false when there was nothing to do.
  const draw = (now: number): boolean => {
    // While only bricks arrive, draw at most every 200 ms: on a software-rendered canvas a
    // frame can take longer than a brick, and drawing each arrival would starve the fetches.
    if (!viewChanged && (!dirty || now - lastDraw < drawInterval)) return false;
    lastDraw = now;
    dirty = false;
    ++frame;
    const camera = eye();
    const viewProjection = multiply(perspective(c.fov_y_degrees, canvas.width / canvas.height, c.near, c.far), lookAt(camera, c.target, c.up));
    if (viewChanged) {
      lastWants = computeWants(viewProjection, camera);
      viewChanged = false;
      loader.want(lastWants, (k) => pool.has(k));
      dirty = true;
    }
    for (const w of lastWants) pool.touch(w.key, frame);
    renderer.draw(objects.map((o) => o.draw), viewProjection, camera, lights, pool.texture, pool.slotsPerAxis * 17, { lodBias: capability.lodBias, showLevels, extraClip: clip });
    if (frame % 16 === 1) {
      // A one-pixel read waits for the frame: how long drawing really takes on this machine.
      const t0 = performance.now();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      drawInterval = Math.min(1000, Math.max(100, 3 * (performance.now() - t0 + (t0 - now))));
    }
    return true;
  };
  // The status and the overlay follow the loader on every tick, drawn or not: fetches fail and
  // succeed while no frame is drawn, and the last change (converged) must show at once.
  // Counted again only when it can have changed: a brick arrived (the pool took it, perhaps
  // evicting another) or a frame was drawn (the wants may be new). Not per tick: a view
  // wants thousands of bricks.
  let resident = 0;
  let residentCountedAt = "";
  const report = (now: number) => {
    const changes = `${loader.stats.received}/${frame}`;
    if (changes !== residentCountedAt) {
      resident = lastWants.filter((w) => pool.has(w.key)).length;
      residentCountedAt = changes;
    }
    status.frames = frame;
    status.wanted = lastWants.length;
    status.resident = resident;
    status.stats = loader.stats;
    status.textures = textures.length;
    // Not while the last bricks wait for their frame: what is on screen must be the picture.
    status.converged = !dirty && loader.pending === 0 && (resident === lastWants.length || pool.residentCount === pool.capacity);
    if (now - lastOverlay < 500 && status.converged === shownConverged) return;
    const fps = (framesDrawn * 1000) / Math.max(1, now - lastOverlay);
    framesDrawn = 0;
    lastOverlay = now;
    shownConverged = status.converged;
    const s = loader.stats;
    overlay.textContent =
      `${fps.toFixed(0)} fps  ${canvas.width}x${canvas.height}  bricks ${resident}/${lastWants.length} wanted, ` +
      `${loader.pending} pending, pool ${pool.residentCount}/${pool.capacity}  fetched ${s.received} ` +
      `(${(s.bytes / 1048576).toFixed(1)} MiB, ${s.cacheHits} cache hits, ${s.cancelled} cancelled, ${s.errors} errors` +
      `${s.failed > 0 ? `, ${s.failed} failed for good` : ""})${status.converged ? "  converged" : ""}`;
  };
  const render = (now: number) => {
    requestAnimationFrame(render);
    if (draw(now)) ++framesDrawn;
    report(now);
  };

  // Orbit with the mouse, zoom with the wheel; keys: 1-4 preset textures on every object,
  // 0 the scene's own, C a clip plane through the target (Up/Down move it), L levels in colour.
  let dragging = false;
  canvas.addEventListener("mousedown", () => (dragging = true));
  window.addEventListener("mouseup", () => (dragging = false));
  window.addEventListener("mousemove", (e) => {
    if (!dragging) return;
    yaw -= e.movementX * 0.01;
    pitch = Math.max(-1.5, Math.min(1.5, pitch + e.movementY * 0.01));
    viewChanged = true;
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    distance *= Math.exp(e.deltaY * 0.001);
    viewChanged = true;
  });
  const switchTextures = async (preset: number | null) => {
    for (const o of objects) {
      const registration = preset === null ? o.registration : { ...o.registration, texture: PRESET_TEXTURES[preset] };
      o.texture = await addTexture(registration);
      const t = textures[o.texture];
      o.draw.indirection = t.indirection.texture;
      o.draw.levels = t.handle.levels;
    }
    viewChanged = true;
  };
  window.addEventListener("keydown", (e) => {
    if (e.key >= "1" && e.key <= String(PRESET_TEXTURES.length)) void switchTextures(Number(e.key) - 1);
    else if (e.key === "0") void switchTextures(null);
    else if (e.key === "l" || e.key === "L") showLevels = !showLevels;
    else if (e.key === "c" || e.key === "C") clip = clip ? null : [0, 0, 1, c.target[2] + clipOffset];
    else if ((e.key === "ArrowUp" || e.key === "ArrowDown") && clip) {
      clipOffset += (e.key === "ArrowUp" ? 0.02 : -0.02) * distance;
      clip = [0, 0, 1, c.target[2] + clipOffset];
    } else return;
    viewChanged = true;
  });
  requestAnimationFrame(render);
}

main().catch((e: Error) => {
  status.error = e.message;
  document.getElementById("overlay")!.textContent = `error: ${e.message}`;
  console.error(e);
});
