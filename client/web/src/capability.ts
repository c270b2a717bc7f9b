// What this machine is asked to do: the canvas resolution, the brick pool's size and the
// requests in flight, from what the browser says about its cores and memory. A URL's width
// and height override the resolution (tests compare pictures at a fixed size).
export interface Capability {
  width: number;
  height: number;
  poolSlotsPerAxis: number; // the pool holds this cubed bricks
  maxInFlight: number;
  lodBias: number;
}

export function chooseCapability(image: { width: number; height: number }, params: URLSearchParams): Capability {
  const cores = navigator.hardwareConcurrency || 2;
  const memoryGiB = (navigator as { deviceMemory?: number }).deviceMemory ?? 4;
  // Fewer pixels on small machines: the fragment shader's work scales with them.
  const fraction = cores >= 8 && memoryGiB >= 8 ? 1 : cores >= 4 ? 0.75 : 0.5;
  const fit = Math.min(1, (window.innerWidth || image.width) / image.width, (window.innerHeight || image.height) / image.height);
  const width = Number(params.get("width")) || Math.round(image.width * Math.min(fraction, fit));
  const height = Number(params.get("height")) || Math.round((width * image.height) / image.width);
  return {
    width,
    height,
    // 1,728 or 1,000 bricks of 17^3 RGBA: 34 or 20 MB.
    poolSlotsPerAxis: Number(params.get("pool")) || (memoryGiB >= 8 ? 12 : 10),
    maxInFlight: Math.max(8, Math.min(16, cores * 2)),
    lodBias: Number(params.get("lod_bias") ?? 0),
  };
}
