// Fetches wanted bricks over HTTP: coarsest level first (a coarse brick stands in for the fine
// ones under it while they load), then nearest; at most `maxInFlight` requests at once; a
// request whose brick the view no longer wants is aborted.
import { decodeBrick, type DecodedBrick } from "./brick_decoder";
import { keyString, type BrickKey } from "./brick_pool";

export interface Want {
  key: BrickKey;
  distance: number;
}

export interface LoaderStats {
  requested: number;
  received: number;
  bytes: number;
  cacheHits: number; // X-Cache-Status: HIT (a cache in front answered)
  cancelled: number;
  errors: number;
  decodeMs: number; // main-thread time decoding bricks
  uploadMs: number; // and handing them to the GPU
}

export class BrickLoader {
  readonly stats: LoaderStats = { requested: 0, received: 0, bytes: 0, cacheHits: 0, cancelled: 0, errors: 0, decodeMs: 0, uploadMs: 0 };
  private queue: Want[] = [];
  private readonly inFlight = new Map<string, AbortController>();

  constructor(
    private readonly urlOf: (key: BrickKey) => string,
    private readonly maxInFlight: number,
    private readonly onBrick: (key: BrickKey, brick: DecodedBrick) => void,
  ) {}

  get pending(): number {
    return this.queue.length + this.inFlight.size;
  }

  // The view's wants replace the previous ones.
  want(wants: Want[], isResident: (key: BrickKey) => boolean): void {
    const wanted = new Set<string>();
    this.queue = [];
    for (const w of wants) {
      const id = keyString(w.key);
      wanted.add(id);
      if (!isResident(w.key) && !this.inFlight.has(id)) this.queue.push(w);
    }
    for (const [id, controller] of this.inFlight) {
      if (!wanted.has(id)) {
        controller.abort();
        this.inFlight.delete(id);
        ++this.stats.cancelled;
      }
    }
    this.queue.sort((a, b) => b.key.level - a.key.level || a.distance - b.distance);
    this.pump();
  }

  private pump(): void {
    while (this.inFlight.size < this.maxInFlight && this.queue.length > 0) {
      const { key } = this.queue.shift()!;
      const id = keyString(key);
      const controller = new AbortController();
      this.inFlight.set(id, controller);
      ++this.stats.requested;
      this.fetchOne(key, id, controller);
    }
  }

  private async fetchOne(key: BrickKey, id: string, controller: AbortController): Promise<void> {
    try {
      const response = await fetch(this.urlOf(key), { signal: controller.signal });
      if (!response.ok) throw new Error(`HTTP ${response.status}: ${await response.text()}`);
      const bytes = new Uint8Array(await response.arrayBuffer());
      if (response.headers.get("x-cache-status") === "HIT") ++this.stats.cacheHits;
      this.stats.bytes += bytes.length;
      ++this.stats.received;
      if (this.inFlight.get(id) === controller) {
        const t0 = performance.now();
        const brick = decodeBrick(bytes, { verify: false });
        const t1 = performance.now();
        this.onBrick(key, brick);
        this.stats.decodeMs += t1 - t0;
        this.stats.uploadMs += performance.now() - t1;
      }
    } catch (e) {
      if (!controller.signal.aborted) {
        ++this.stats.errors;
        console.warn(`brick ${id}: ${(e as Error).message}`);
      }
    } finally {
      if (this.inFlight.get(id) === controller) this.inFlight.delete(id);
      this.pump();
    }
  }
}
