// The TypeScript decoder against bricks soltexd's C++ encoder wrote, fetched over HTTP: every
// codec decodes to the same samples, whose XXH64 is the checksum the server declared.
import { beforeAll, describe, expect, inject, it } from "vitest";

import { BrickDecodeError, decodeBrick, readHeader } from "../src/brick_decoder";
import { xxh64 } from "../src/xxh64";

const base = inject("soltexdHttp");
let bricks = "";

async function fetchBrick(level: number, x: number, y: number, z: number, codec: string) {
  const url = `${base}${bricks.replace("{level}/{x}/{y}/{z}", `${level}/${x}/${y}/${z}`)}&codec=${codec}`;
  const response = await fetch(url);
  expect(response.status).toBe(200);
  return {
    bytes: new Uint8Array(await response.arrayBuffer()),
    checksum: BigInt(`0x${response.headers.get("x-soltex-checksum")}`),
  };
}

beforeAll(async () => {
  // Every channel, so all five planes go through the predictor (lz4, zstd).
  const response = await fetch(`${base}/v1/textures`, {
    method: "POST",
    body: JSON.stringify({
      texture: { marble: {}, channels: ["colour", "opacity", "specular"] },
      volume: { min: [-1, -1, -1], max: [1, 1, 1], finest_level_log2: 6 },
      brick_size: 16,
    }),
  });
  expect(response.status).toBe(200);
  bricks = (await response.json()).bricks;
});

describe("decodeBrick", () => {
  it("decodes raw, lz4 and zstd bricks to the same checked samples", async () => {
    for (const [level, x, y, z] of [[2, 0, 0, 0], [1, 1, 0, 1], [0, 3, 2, 1]]) {
      const decoded = [];
      for (const codec of ["raw", "lz4", "zstd"]) {
        const { bytes, checksum } = await fetchBrick(level, x, y, z, codec);
        const brick = decodeBrick(bytes);
        expect(brick.codec).toBe(codec);
        expect(brick.brickSize).toBe(16);
        expect(brick.channels).toBe(5);
        // The 3D predictor before a compressor; raw bricks go without it.
        expect(brick.predictor).toBe(codec === "raw" ? 0 : 3);
        expect(brick.checksum).toBe(checksum);
        expect(brick.samples.length).toBe(17 ** 3 * 5);
        decoded.push(brick.samples);
      }
      expect(decoded[1]).toEqual(decoded[0]);
      expect(decoded[2]).toEqual(decoded[0]);
      // A finest-level brick is far from one flat value: the predictor was really undone.
      if (level === 0) expect(new Set(decoded[0].subarray(0, 17 ** 3)).size).toBeGreaterThan(10);
    }
  });

  it("refuses corrupt and malformed bricks, naming what is wrong", async () => {
    const { bytes } = await fetchBrick(1, 0, 0, 0, "lz4");
    const flipped = bytes.slice();
    flipped[bytes.length - 1] ^= 0x40;
    expect(() => decodeBrick(flipped)).toThrow(BrickDecodeError);
    expect(() => decodeBrick(bytes.subarray(0, 20))).toThrow(/less than its 28-byte header/);
    expect(() => decodeBrick(bytes.subarray(0, bytes.length - 1))).toThrow(/payload size/);
    const magic = bytes.slice();
    magic[0] = 0x41;
    expect(() => readHeader(magic)).toThrow(/magic/);
    const size = bytes.slice();
    size[5] = 12;
    expect(() => readHeader(size)).toThrow(/brick size 12/);
    const codec = bytes.slice();
    codec[7] = 9;
    expect(() => readHeader(codec)).toThrow(/codec id 9/);
    const { bytes: raw } = await fetchBrick(1, 0, 0, 0, "raw");
    const corrupt = raw.slice();
    corrupt[100] ^= 1;
    expect(() => decodeBrick(corrupt)).toThrow(/checksum/);
  });
});

describe("xxh64", () => {
  it("matches the reference values", () => {
    // Values from the xxHash reference implementation.
    expect(xxh64(new Uint8Array(0))).toBe(0xef46db3751d8e999n);
    expect(xxh64(new TextEncoder().encode("a"))).toBe(0xd24ec4f1a98c6e5bn);
    expect(xxh64(new TextEncoder().encode("abc"))).toBe(0x44bc2cf5ad770999n);
  });
});
