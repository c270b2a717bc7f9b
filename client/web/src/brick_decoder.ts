// Decodes an encoded brick (docs/PROTOCOL.md section 7): the 28-byte header, the codec (raw,
// an LZ4 block, or one zstd frame), the predictor's running sums, and the XXH64 checksum.
import { decompress as zstdDecompress } from "fzstd";

import { xxh64 } from "./xxh64";

export const HEADER_BYTES = 28;
export const CODECS = ["raw", "lz4", "zstd"] as const;
export type CodecName = (typeof CODECS)[number];

export interface BrickHeader {
  brickSize: number; // B: 8 or 16
  channels: number; // C: planes of (B + 1)^3 bytes
  codec: CodecName;
  predictor: number; // 0 none .. 3 gradient-3d
  decodedSize: number;
  payloadSize: number;
  checksum: bigint;
}

export interface DecodedBrick extends BrickHeader {
  samples: Uint8Array; // C planes, x fastest, each (B + 1)^3 bytes
}

export class BrickDecodeError extends Error {}
// Samples that decoded but do not match the header's checksum: the bytes were damaged on the
// way (docs/PROTOCOL.md section 7), so asking again, past any cache, may get them whole.
export class BrickChecksumError extends BrickDecodeError {}

function fail(message: string): never {
  throw new BrickDecodeError(message);
}

// Every check a decoder should make before it allocates or decompresses anything.
export function readHeader(bytes: Uint8Array): BrickHeader {
  if (bytes.length < HEADER_BYTES) fail(`brick is ${bytes.length} bytes, less than its 28-byte header`);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const magic = String.fromCharCode(bytes[0], bytes[1], bytes[2], bytes[3]);
  if (magic !== "SLTX") fail(`magic is '${magic}', not 'SLTX'`);
  if (bytes[4] !== 1) fail(`format version ${bytes[4]}, only 1 is known`);
  const brickSize = bytes[5];
  if (brickSize !== 8 && brickSize !== 16) fail(`brick size ${brickSize}: must be 8 or 16`);
  const channels = bytes[6];
  if (channels < 1 || channels > 5) fail(`channel count ${channels}: must be in [1, 5]`);
  const codec = CODECS[bytes[7]];
  if (codec === undefined) fail(`codec id ${bytes[7]}: must be 0 (raw), 1 (lz4) or 2 (zstd)`);
  const predictor = bytes[8];
  if (predictor > 3) fail(`predictor id ${predictor}: must be in [0, 3]`);
  if (bytes[9] !== 0 || bytes[10] !== 0 || bytes[11] !== 0) fail("reserved header bytes are not zero");
  const decodedSize = view.getUint32(12, true);
  const expected = (brickSize + 1) ** 3 * channels;
  if (decodedSize !== expected) fail(`decoded size ${decodedSize}, expected (B + 1)^3 * C = ${expected}`);
  const payloadSize = view.getUint32(16, true);
  if (payloadSize !== bytes.length - HEADER_BYTES) {
    fail(`payload size ${payloadSize}, but ${bytes.length - HEADER_BYTES} bytes follow the header`);
  }
  const checksum = view.getBigUint64(20, true);
  return { brickSize, channels, codec, predictor, decodedSize, payloadSize, checksum };
}

// One bare LZ4 block (no frame), decompressed to exactly `size` bytes.
export function lz4BlockDecompress(input: Uint8Array, size: number): Uint8Array {
  const out = new Uint8Array(size);
  let i = 0;
  let o = 0;
  const length = (start: number): number => {
    let n = start;
    if (n === 15) {
      let b: number;
      do {
        if (i >= input.length) fail("lz4: length runs past the end of the block");
        b = input[i++];
        n += b;
      } while (b === 255);
    }
    return n;
  };
  while (i < input.length) {
    const token = input[i++];
    const literals = length(token >> 4);
    if (i + literals > input.length || o + literals > size) fail("lz4: literals run past the end");
    out.set(input.subarray(i, i + literals), o);
    i += literals;
    o += literals;
    if (i === input.length) break; // the last sequence has literals only
    if (i + 2 > input.length) fail("lz4: offset runs past the end of the block");
    const offset = input[i] | (input[i + 1] << 8);
    i += 2;
    if (offset === 0 || offset > o) fail(`lz4: match offset ${offset} outside the ${o} bytes written`);
    const match = length(token & 15) + 4;
    if (o + match > size) fail("lz4: match runs past the decoded size");
    for (let k = 0; k < match; ++k, ++o) out[o] = out[o - offset];
  }
  if (o !== size) fail(`lz4: decompressed ${o} bytes, the header says ${size}`);
  return out;
}

// Running sums modulo 256 along the axes the predictor named, plane by plane.
export function undoPredictor(data: Uint8Array, brickSize: number, channels: number, predictor: number): void {
  const s = brickSize + 1;
  const plane = s * s * s;
  for (let c = 0; c < channels; ++c) {
    const base = c * plane;
    if (predictor >= 1) {
      for (let row = 0; row < s * s; ++row) {
        const r = base + row * s;
        for (let x = 1; x < s; ++x) data[r + x] = (data[r + x] + data[r + x - 1]) & 255;
      }
    }
    if (predictor >= 2) {
      for (let z = 0; z < s; ++z) {
        for (let y = 1; y < s; ++y) {
          const r = base + (z * s + y) * s;
          for (let x = 0; x < s; ++x) data[r + x] = (data[r + x] + data[r + x - s]) & 255;
        }
      }
    }
    if (predictor >= 3) {
      for (let z = 1; z < s; ++z) {
        const r = base + z * s * s;
        for (let k = 0; k < s * s; ++k) data[r + k] = (data[r + k] + data[r + k - s * s]) & 255;
      }
    }
  }
}

export function decodeBrick(bytes: Uint8Array, options: { verify?: boolean } = {}): DecodedBrick {
  const header = readHeader(bytes);
  const body = bytes.subarray(HEADER_BYTES);
  let samples: Uint8Array;
  if (header.codec === "raw") {
    if (body.length !== header.decodedSize) fail(`raw payload is ${body.length} bytes, not ${header.decodedSize}`);
    samples = body.slice();
  } else if (header.codec === "lz4") {
    samples = lz4BlockDecompress(body, header.decodedSize);
  } else {
    try {
      samples = zstdDecompress(body);
    } catch (e) {
      fail(`zstd: ${(e as Error).message}`);
    }
    if (samples.length !== header.decodedSize) {
      fail(`zstd: decompressed ${samples.length} bytes, the header says ${header.decodedSize}`);
    }
  }
  undoPredictor(samples, header.brickSize, header.channels, header.predictor);
  if (options.verify !== false) {
    const sum = xxh64(samples);
    if (sum !== header.checksum) {
      throw new BrickChecksumError(
        `checksum ${sum.toString(16)} differs from the header's ${header.checksum.toString(16)}: corrupt brick`,
      );
    }
  }
  return { ...header, samples };
}
