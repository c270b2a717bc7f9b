// Fetches wanted bricks over HTTP: coarsest level first (a coarse brick stands in for the fine
// ones under it while they load), then nearest; at most `maxInFlight` requests at once; a
// request whose brick the view no longer wants is aborted. A fetch that fails for a reason
// that passes (the network, a 5xx, 408, 429) goes back in the queue, and the whole queue
// waits a backoff that doubles up to 4 s (or the Retry-After asked for) and starts over with
// the next brick that arrives: the page recovers by itself when the server comes back, and a
// server that is down gets a few requests per backoff rather than every queued brick's. Any
// other answer (a 4xx) fails the brick for good. A brick whose samples do not match their
// checksum is asked for again past the browser's cache, up to kMaxRefetches times, as
// soltex-view refetches a corrupt brick.
import { BrickChecksumError, decodeBrick, type DecodedBrick } from "./brick_decoder";
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
  errors: number; // failed fetches, retried or not
  failed: number; // bricks given up on: an answer that asking again would not change
  corrupt: number; // answers whose samples failed their checksum (asked for again)
  decodeMs: number; // main-thread time decoding bricks
  uploadMs: number; // and handing them to the GPU
}

export const kInitialBackoffMs = 100;
export const kMaxBackoffMs = 4000;
export const kMaxRefetches = 3;

// A fetch that failed with an answer: whether asking again may get the brick (a 5xx, 408, 429)
// or not (any other 4xx, bytes that do not decode), and the wait the server asked for. A
// fetch that got no answer at all (the network) throws the browser's own error: it may pass.
class FetchError extends Error {
  constructor(message: string, readonly passes: boolean, readonly retryAfterMs = 0) {
    super(message);
  }
}

function retryAfterMs(response: Response): number {
  const seconds = Number(response.headers.get("retry-after") ?? "");
  return Number.isFinite(seconds) && seconds > 0 ? Math.min(seconds, 60) * 1000 : 0;
}

// Whether a status may pass: the server overloaded, restarting or too slow.
function transient(status: number): boolean {
  return status >= 500 || status === 408 || status === 429;
}

export class BrickLoader {
  readonly stats: LoaderStats = {
    requested: 0, received: 0, bytes: 0, cacheHits: 0, cancelled: 0, errors: 0, failed: 0,
    corrupt: 0, decodeMs: 0, uploadMs: 0,
  };
  private queue: Want[] = [];
  private readonly inFlight = new Map<string, AbortController>();
  private wanted = new Map<string, Want>(); // the view's latest wants
  private readonly failedForGood = new Set<string>();
  private readonly refetches = new Map<string, number>(); // corrupt answers so far, per brick
  private backoffMs = kInitialBackoffMs;
  private pausedUntil = 0; // performance.now() before which no fetch starts
  private resumeTimer: ReturnType<typeof setTimeout> | undefined;

  constructor(
    private readonly urlOf: (key: BrickKey) => string,
    private readonly maxInFlight: number,
    private readonly onBrick: (key: BrickKey, brick: DecodedBrick) => void,
  ) {}

  // Bricks asked for and not yet answered, those waiting to be asked again included.
  get pending(): number {
    return this.queue.length + this.inFlight.size;
  }

  // The view's wants replace the previous ones.
  want(wants: Want[], isResident: (key: BrickKey) => boolean): void {
    this.wanted = new Map();
    this.queue = [];
    for (const w of wants) {
      const id = keyString(w.key);
      this.wanted.set(id, w);
      if (isResident(w.key) || this.inFlight.has(id) || this.failedForGood.has(id)) continue;
      this.queue.push(w);
    }
    for (const [id, controller] of this.inFlight) {
      if (!this.wanted.has(id)) {
        controller.abort();
        this.inFlight.delete(id);
        ++this.stats.cancelled;
      }
    }
    this.sortQueue();
    this.pump();
  }

  private sortQueue(): void {
    this.queue.sort((a, b) => b.key.level - a.key.level || a.distance - b.distance);
  }

  private pump(): void {
    const wait = this.pausedUntil - performance.now();
    if (wait > 0) {
      this.resumeTimer ??= setTimeout(() => {
        this.resumeTimer = undefined;
        this.pump();
      }, wait);
      return;
    }
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
      // After a corrupt answer, not from the browser's cache: it would give the same bytes.
      const cache: RequestCache = this.refetches.has(id) ? "reload" : "default";
      const response = await fetch(this.urlOf(key), { signal: controller.signal, cache });
      if (!response.ok) {
        const message = `HTTP ${response.status}: ${await response.text()}`;
        throw new FetchError(message, transient(response.status), retryAfterMs(response));
      }
      const bytes = new Uint8Array(await response.arrayBuffer());
      if (response.headers.get("x-cache-status") === "HIT") ++this.stats.cacheHits;
      this.stats.bytes += bytes.length;
      ++this.stats.received;
      if (this.inFlight.get(id) === controller) this.accept(key, id, bytes);
      this.backoffMs = kInitialBackoffMs;
    } catch (e) {
      if (!controller.signal.aborted) this.failed(id, e as Error);
    } finally {
      if (this.inFlight.get(id) === controller) this.inFlight.delete(id);
      this.pump();
    }
  }

  // A whole answer, decoded, checked and handed on. One that does not decode is refused for
  // good: the same URL gives the same bytes, so asking again would fail again. One that fails
  // its checksum was damaged on the way and is asked for again, a few times.
  private accept(key: BrickKey, id: string, bytes: Uint8Array): void {
    const t0 = performance.now();
    let brick: DecodedBrick;
    try {
      brick = decodeBrick(bytes);
    } catch (e) {
      if (e instanceof BrickChecksumError) {
        ++this.stats.corrupt;
        const refetches = (this.refetches.get(id) ?? 0) + 1;
        this.refetches.set(id, refetches);
        throw new FetchError(e.message, refetches <= kMaxRefetches);
      }
      throw new FetchError(`undecodable brick: ${(e as Error).message}`, false);
    }
    this.refetches.delete(id);
    const t1 = performance.now();
    this.onBrick(key, brick);
    this.stats.decodeMs += t1 - t0;
    this.stats.uploadMs += performance.now() - t1;
  }

  private failed(id: string, error: Error & Partial<FetchError>): void {
    ++this.stats.errors;
    console.warn(`brick ${id}: ${error.message}`);
    if (error.passes === false) {
      this.failedForGood.add(id);
      ++this.stats.failed;
      return;
    }
    const asked = error.retryAfterMs ?? 0;
    this.pausedUntil = Math.max(this.pausedUntil, performance.now() + Math.max(this.backoffMs, asked));
    this.backoffMs = Math.min(2 * this.backoffMs, kMaxBackoffMs);
    const want = this.wanted.get(id);
    if (want !== undefined && !this.queue.some((w) => keyString(w.key) === id)) {
      this.queue.push(want);
      this.sortQueue();
    }
  }
}
