// The loader against the real soltexd behind a proxy that fails each brick's first request
// (a 503, or the connection closed with no answer), as a restarting server or a dropped link
// would: every brick must still arrive, and a brick the server refuses must not be asked again.
import { createServer, type Server } from "node:http";
import type { AddressInfo } from "node:net";
import { afterAll, beforeAll, describe, expect, inject, it } from "vitest";

import type { DecodedBrick } from "../src/brick_decoder";
import { BrickLoader, kMaxRefetches, type Want } from "../src/brick_loader";
import type { BrickKey } from "../src/brick_pool";

const base = inject("soltexdHttp");
let bricks = "";
let proxy: Server;
let proxyBase = "";
const seen = new Map<string, number>(); // requests per URL through the proxy

beforeAll(async () => {
  const response = await fetch(`${base}/v1/textures`, {
    method: "POST",
    body: JSON.stringify({
      texture: { marble: {} },
      volume: { min: [-1, -1, -1], max: [1, 1, 1], finest_level_log2: 5 },
      brick_size: 16,
    }),
  });
  expect(response.status).toBe(200);
  bricks = (await response.json()).bricks;
  let failures = 0;
  proxy = createServer(async (request, reply) => {
    const url = request.url ?? "/";
    const count = (seen.get(url) ?? 0) + 1;
    seen.set(url, count);
    if (count === 1) {
      // Each brick's first request fails, alternately as an error answer and as no answer.
      if (failures++ % 2 === 0) {
        reply.writeHead(503, { "content-type": "text/plain" }).end("restarting\n");
      } else {
        request.socket.destroy();
      }
      return;
    }
    const upstream = await fetch(`${base}${url}`);
    reply.writeHead(upstream.status, { "content-type": upstream.headers.get("content-type") ?? "" });
    reply.end(new Uint8Array(await upstream.arrayBuffer()));
  });
  await new Promise<void>((resolve) => proxy.listen(0, "127.0.0.1", resolve));
  proxyBase = `http://127.0.0.1:${(proxy.address() as AddressInfo).port}`;
});

afterAll(() => {
  proxy.close();
});

function urlOf(key: BrickKey): string {
  return `${proxyBase}${bricks.replace("{level}/{x}/{y}/{z}", `${key.level}/${key.x}/${key.y}/${key.z}`)}&codec=zstd`;
}

async function settled(loader: BrickLoader): Promise<void> {
  const deadline = Date.now() + 30000;
  while (loader.pending > 0 && Date.now() < deadline) await new Promise((r) => setTimeout(r, 20));
}

describe("BrickLoader", () => {
  it("asks again after a 5xx or a dropped connection until every brick arrives", async () => {
    const arrived: DecodedBrick[] = [];
    const loader = new BrickLoader(urlOf, 4, (_key, brick) => arrived.push(brick));
    const wants: Want[] = [];
    for (let z = 0; z < 2; ++z)
      for (let y = 0; y < 2; ++y)
        for (let x = 0; x < 2; ++x) wants.push({ key: { texture: 0, level: 0, x, y, z }, distance: x + y + z });
    loader.want(wants, () => false);
    await settled(loader);
    expect(loader.pending).toBe(0);
    expect(arrived.length).toBe(8);
    expect(loader.stats.received).toBe(8);
    expect(loader.stats.errors).toBe(8);
    expect(loader.stats.failed).toBe(0);
  }, 40000); // each failure doubles the queue's pause, up to 4 s

  it("does not ask again for a brick that does not decode", async () => {
    // A server whose answers are all 200 and not bricks: the same URL would give the same bytes.
    let asked = 0;
    const garbage = createServer((_request, reply) => {
      ++asked;
      reply.writeHead(200, { "content-type": "application/octet-stream" }).end("not a brick");
    });
    await new Promise<void>((resolve) => garbage.listen(0, "127.0.0.1", resolve));
    const port = (garbage.address() as AddressInfo).port;
    const loader = new BrickLoader(() => `http://127.0.0.1:${port}/brick`, 4, () => {});
    loader.want([{ key: { texture: 0, level: 0, x: 0, y: 0, z: 0 }, distance: 0 }], () => false);
    await settled(loader);
    await new Promise((r) => setTimeout(r, 300)); // time for a retry, were there one
    garbage.close();
    expect(loader.pending).toBe(0);
    expect(loader.stats.failed).toBe(1);
    expect(asked).toBe(1);
  });

  it("asks again, past the cache, for a brick whose samples fail their checksum", async () => {
    // A real brick, served with one sample byte flipped until `corruptFor` answers have gone.
    const real = new Uint8Array(
      await (await fetch(`${base}${bricks.replace("{level}/{x}/{y}/{z}", "0/0/0/0")}&codec=raw`)).arrayBuffer(),
    );
    const serve = (corruptFor: number) => {
      let answers = 0;
      const server = createServer((request, reply) => {
        const bytes = real.slice();
        if (answers++ < corruptFor) bytes[bytes.length - 7] ^= 0x40;
        reply.writeHead(200, { "content-type": "application/vnd.soltex.brick" }).end(bytes);
      });
      return { server, answers: () => answers };
    };
    const run = async (corruptFor: number) => {
      const { server, answers } = serve(corruptFor);
      await new Promise<void>((resolve) => server.listen(0, "127.0.0.1", resolve));
      const port = (server.address() as AddressInfo).port;
      const arrived: DecodedBrick[] = [];
      const loader = new BrickLoader(() => `http://127.0.0.1:${port}/brick`, 4, (_k, b) => arrived.push(b));
      loader.want([{ key: { texture: 0, level: 0, x: 0, y: 0, z: 0 }, distance: 0 }], () => false);
      await settled(loader);
      server.close();
      return { loader, arrived: arrived.length, answers: answers() };
    };
    const once = await run(1);
    expect(once.arrived).toBe(1);
    expect(once.loader.stats.corrupt).toBe(1);
    expect(once.loader.stats.failed).toBe(0);
    expect(once.answers).toBe(2);
    // Corrupt every time: asked for 1 + kMaxRefetches times, then given up on.
    const always = await run(1000);
    expect(always.arrived).toBe(0);
    expect(always.loader.stats.failed).toBe(1);
    expect(always.answers).toBe(1 + kMaxRefetches);
  }, 40000);

  it("does not ask again for a brick the server refuses", async () => {
    const loader = new BrickLoader(urlOf, 4, () => {});
    // Level 9 of a texture with 2 levels: a 4xx, which asking again would not change.
    const refused: BrickKey = { texture: 0, level: 9, x: 0, y: 0, z: 0 };
    loader.want([{ key: refused, distance: 0 }], () => false);
    await settled(loader);
    // The proxy fails the first request itself; the second reaches soltexd and is refused.
    const requests = seen.get(new URL(urlOf(refused)).pathname + new URL(urlOf(refused)).search);
    expect(loader.pending).toBe(0);
    expect(loader.stats.failed).toBe(1);
    expect(requests).toBe(2);
    // Wanting it again does not ask again.
    loader.want([{ key: refused, distance: 0 }], () => false);
    expect(loader.pending).toBe(0);
  });
});
