// WebGL2 drawing: per object, triangles with world positions, normals and texture-volume
// coordinates; the fragment shader picks a level per pixel from the coordinates' screen
// derivatives, reads the brick through the indirection texture, falls back to the nearest
// coarser resident level while a brick loads, blends neighbouring levels, and lights the
// result as soltex-view does (ambient plus Blinn-Phong directional and point lights).
import type { Mat4, Vec3 } from "./math";

const VERTEX = `#version 300 es
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 texcoord;
uniform mat4 viewProjection;
out vec3 vWorld;
out vec3 vNormal;
out vec3 vTex;
void main() {
  vWorld = position;
  vNormal = normal;
  vTex = texcoord;
  gl_Position = viewProjection * vec4(position, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
precision highp sampler3D;
in vec3 vWorld;
in vec3 vNormal;
in vec3 vTex;
uniform sampler3D pool;
uniform sampler3D indirection;
uniform float poolTexels;
uniform float bricks0;
uniform int levels;
uniform float lodBias;
uniform vec3 cameraPosition;
uniform vec3 ambient;
uniform int directionalCount;
uniform vec3 toLight[4];
uniform vec3 directionalRadiance[4];
uniform int pointCount;
uniform vec3 pointPosition[4];
uniform vec3 pointRadiance[4];
uniform float specular;
uniform float shininess;
uniform bool unlit;
uniform int clipCount;
uniform bool solid;
uniform vec4 clipPlanes[5];
uniform bool showLevels;
uniform mat4 worldToVolume;
out vec4 colour;

const float SLOT = 17.0;
const float BRICK = 16.0;

// The brick of level l under t, from the indirection texture: its slot, or alpha 0.
bool readLevel(int l, vec3 t, out vec3 albedo) {
  float n = bricks0 / exp2(float(l));
  vec3 cell = t * n;
  vec3 brick = clamp(floor(cell), vec3(0.0), vec3(n - 1.0));
  vec4 entry = texelFetch(indirection, ivec3(brick), l);
  if (entry.a < 0.5) return false;
  vec3 local = clamp(cell - brick, 0.0, 1.0);
  vec3 texel = floor(entry.rgb * 255.0 + 0.5) * SLOT + 0.5 + local * BRICK;
  albedo = texture(pool, texel / poolTexels).rgb;
  return true;
}

// Level l, or the nearest coarser level that is resident.
vec3 sampleFrom(int l, vec3 t, out int used) {
  vec3 albedo = vec3(1.0, 0.0, 1.0);
  for (int k = l; k < levels; ++k) {
    if (readLevel(k, t, albedo)) { used = k; return albedo; }
  }
  used = levels;
  return albedo;
}

vec3 lightTerm(vec3 albedo, vec3 n, vec3 v, vec3 l, vec3 radiance) {
  float nl = dot(n, l);
  if (!(nl > 0.0)) return vec3(0.0);
  vec3 c = albedo * radiance * nl;
  if (specular > 0.0) {
    float nh = dot(n, normalize(l + v));
    if (nh > 0.0) c += radiance * (specular * pow(nh, shininess));
  }
  return c;
}

void main() {
  for (int i = 0; i < clipCount; ++i) {
    if (dot(clipPlanes[i].xyz, vWorld) - clipPlanes[i].w > 0.0) discard;
  }
  // A clipped solid seen through its cut: what shows is the cut face (the cap), where the ray
  // meets the nearest clip plane, textured there and lit with the plane's normal (it points
  // out of the solid that is left).
  vec3 surface = vWorld;
  vec3 n = normalize(vNormal);
  vec3 texcoord = vTex;
  if (clipCount > 0 && solid && !gl_FrontFacing) {
    vec3 ray = vWorld - cameraPosition;
    float best = 1.0;
    for (int i = 0; i < clipCount; ++i) {
      float along = dot(clipPlanes[i].xyz, ray);
      if (along == 0.0) continue;
      float s = (clipPlanes[i].w - dot(clipPlanes[i].xyz, cameraPosition)) / along;
      if (s > 0.0 && s < best) { best = s; n = clipPlanes[i].xyz; }
    }
    vec3 capTexcoord = (worldToVolume * vec4(cameraPosition + best * ray, 1.0)).xyz;
    // A cap lies inside its solid, so within its volume (the object's padded bounds): one
    // traced outside, through a hole or a face wound the wrong way, is no cap.
    if (all(greaterThanEqual(capTexcoord, vec3(0.0))) && all(lessThanEqual(capTexcoord, vec3(1.0)))) {
      surface = cameraPosition + best * ray;
      texcoord = capTexcoord;
    } else {
      n = -normalize(vNormal);
    }
  } else if (!gl_FrontFacing) {
    n = -n;
  }
  vec3 t = clamp(texcoord, 0.0, 1.0);
  // Level 0 has bricks0 * 16 cells per axis: the footprint of a pixel in level-0 cells.
  vec3 dx = dFdx(texcoord) * bricks0 * BRICK;
  vec3 dy = dFdy(texcoord) * bricks0 * BRICK;
  float lod = clamp(log2(max(max(length(dx), length(dy)), 1e-8)) + lodBias, 0.0, float(levels - 1));
  int l0 = int(floor(lod));
  int used0, used1;
  vec3 a0 = sampleFrom(l0, t, used0);
  vec3 a1 = sampleFrom(min(l0 + 1, levels - 1), t, used1);
  vec3 albedo = used0 == l0 ? mix(a0, a1, fract(lod)) : a0;
  if (showLevels) albedo = vec3(float(used0 % 3 == 0), float(used0 % 3 == 1), float(used0 % 3 == 2)) * 0.5 + albedo * 0.5;
  if (unlit) { colour = vec4(albedo, 1.0); return; }
  vec3 v = normalize(cameraPosition - surface);
  vec3 c = albedo * ambient;
  for (int i = 0; i < directionalCount; ++i) c += lightTerm(albedo, n, v, toLight[i], directionalRadiance[i]);
  for (int i = 0; i < pointCount; ++i) {
    vec3 offset = pointPosition[i] - surface;
    float d2 = max(dot(offset, offset), 1e-12);
    c += lightTerm(albedo, n, v, offset / sqrt(d2), pointRadiance[i] / d2);
  }
  colour = vec4(clamp(c, 0.0, 1.0), 1.0);
}`;

function compile(gl: WebGL2RenderingContext, type: number, source: string): WebGLShader {
  const shader = gl.createShader(type)!;
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new Error(`shader: ${gl.getShaderInfoLog(shader)}`);
  }
  return shader;
}

export interface Mesh {
  vao: WebGLVertexArrayObject;
  count: number;
}

export function uploadMesh(gl: WebGL2RenderingContext, positions: number[], normals: number[], texcoords: number[], indices: number[]): Mesh {
  const vao = gl.createVertexArray()!;
  gl.bindVertexArray(vao);
  [positions, normals, texcoords].forEach((data, location) => {
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, 3, gl.FLOAT, false, 0, 0);
  });
  const elements = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, elements);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(indices), gl.STATIC_DRAW);
  gl.bindVertexArray(null);
  return { vao, count: indices.length };
}

export interface DrawLights {
  ambient: Vec3;
  directional: { toLight: Vec3; radiance: Vec3 }[];
  point: { position: Vec3; radiance: Vec3 }[];
}

export interface DrawObject {
  mesh: Mesh;
  indirection: WebGLTexture;
  levels: number;
  bricks0: number;
  specular: number;
  shininess: number;
  unlit: boolean;
  doubleSided: boolean;
  solid: boolean;
  clipPlanes: number[][];
  worldToVolume: Float32Array;
}

export class Renderer {
  private readonly program: WebGLProgram;
  private readonly uniforms = new Map<string, WebGLUniformLocation | null>();

  constructor(private readonly gl: WebGL2RenderingContext) {
    const program = gl.createProgram()!;
    gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(`program: ${gl.getProgramInfoLog(program)}`);
    this.program = program;
  }

  private u(name: string): WebGLUniformLocation | null {
    if (!this.uniforms.has(name)) this.uniforms.set(name, this.gl.getUniformLocation(this.program, name));
    return this.uniforms.get(name)!;
  }

  draw(objects: DrawObject[], viewProjection: Mat4, camera: Vec3, lights: DrawLights, pool: WebGLTexture, poolTexels: number, options: { lodBias: number; showLevels: boolean; extraClip: number[] | null }): void {
    const gl = this.gl;
    gl.enable(gl.DEPTH_TEST);
    gl.clearColor(0.12, 0.12, 0.14, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(this.u("viewProjection"), false, viewProjection);
    gl.uniform3fv(this.u("cameraPosition"), camera);
    gl.uniform3fv(this.u("ambient"), lights.ambient);
    gl.uniform1i(this.u("directionalCount"), Math.min(4, lights.directional.length));
    lights.directional.slice(0, 4).forEach((d, i) => {
      gl.uniform3fv(this.u(`toLight[${i}]`), d.toLight);
      gl.uniform3fv(this.u(`directionalRadiance[${i}]`), d.radiance);
    });
    gl.uniform1i(this.u("pointCount"), Math.min(4, lights.point.length));
    lights.point.slice(0, 4).forEach((p, i) => {
      gl.uniform3fv(this.u(`pointPosition[${i}]`), p.position);
      gl.uniform3fv(this.u(`pointRadiance[${i}]`), p.radiance);
    });
    gl.uniform1f(this.u("poolTexels"), poolTexels);
    gl.uniform1f(this.u("lodBias"), options.lodBias);
    gl.uniform1i(this.u("showLevels"), options.showLevels ? 1 : 0);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_3D, pool);
    gl.uniform1i(this.u("pool"), 0);
    gl.uniform1i(this.u("indirection"), 1);
    for (const o of objects) {
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_3D, o.indirection);
      gl.uniform1f(this.u("bricks0"), o.bricks0);
      gl.uniform1i(this.u("levels"), o.levels);
      gl.uniform1f(this.u("specular"), o.specular);
      gl.uniform1f(this.u("shininess"), o.shininess);
      gl.uniform1i(this.u("unlit"), o.unlit ? 1 : 0);
      gl.uniformMatrix4fv(this.u("worldToVolume"), false, o.worldToVolume);
      const planes = options.extraClip ? [...o.clipPlanes, options.extraClip] : o.clipPlanes;
      gl.uniform1i(this.u("clipCount"), Math.min(5, planes.length));
      gl.uniform1i(this.u("solid"), o.solid ? 1 : 0);
      planes.slice(0, 5).forEach((p, i) => gl.uniform4fv(this.u(`clipPlanes[${i}]`), p));
      if (o.doubleSided || planes.length > 0) gl.disable(gl.CULL_FACE);
      else gl.enable(gl.CULL_FACE);
      gl.bindVertexArray(o.mesh.vao);
      gl.drawElements(gl.TRIANGLES, o.mesh.count, gl.UNSIGNED_INT, 0);
    }
    gl.bindVertexArray(null);
  }
}
