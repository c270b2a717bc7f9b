// The web viewer in a real headless Chromium (WebGL2 on SwiftShader) against a real soltexd:
// the page is served from one origin and fetches bricks from soltexd's --http-listen on
// another (CORS), draws the default scene until every brick it wants is resident, and its
// canvas must match soltex-view's picture of the same scene and camera within PSNR_FLOOR dB.
// Environment: SOLTEXD_BINARY, SCENE_EXPORT_BINARY, SOLTEX_VIEW_BINARY (build outputs),
// CHROMIUM (default /usr/bin/chromium). Run after `vite build` (dist/).
import { execFileSync, spawn } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { createServer } from "node:http";
import { tmpdir } from "node:os";
import { extname, join, normalize } from "node:path";

import { chromium } from "playwright-core";

// Measured 36.0 dB at 640x360 (docs/PERFORMANCE.md, web viewer); the floor leaves room for
// SwiftShader's and a GPU's filtering differences.
const PSNR_FLOOR = 30;
const WIDTH = 640;
const HEIGHT = 360;

const need = (name) => {
  const value = process.env[name];
  if (!value || !existsSync(value)) throw new Error(`${name} must name a built binary (got '${value}')`);
  return value;
};
const soltexd = need("SOLTEXD_BINARY");
const sceneExport = need("SCENE_EXPORT_BINARY");
const soltexView = need("SOLTEX_VIEW_BINARY");
const chromiumPath = process.env.CHROMIUM ?? "/usr/bin/chromium";
const dist = new URL("../../dist/", import.meta.url).pathname;
if (!existsSync(join(dist, "index.html"))) throw new Error(`${dist}index.html missing: run vite build first`);

const work = mkdtempSync(join(tmpdir(), "soltex-web-browser-"));
let server;
let context;
try {
  // soltexd with HTTP bricks on a free port.
  const ready = join(work, "ready");
  server = spawn(soltexd, ["--listen", "127.0.0.1:0", "--metrics-listen", "127.0.0.1:0", "--http-listen",
    "127.0.0.1:0", "--ready-file", ready, "--log-level", "warn"], { stdio: "inherit" });
  let http = 0;
  for (let i = 0; i < 400 && !http; ++i) {
    if (existsSync(ready)) http = Number(/^http=(\d+)$/m.exec(readFileSync(ready, "utf8"))?.[1] ?? 0);
    if (!http) await new Promise((r) => setTimeout(r, 50));
  }
  if (!http) throw new Error("soltexd did not start");

  // The page and the scene from another origin.
  const scene = join(work, "default.json");
  execFileSync(sceneExport, ["--out", scene]);
  const types = { ".html": "text/html", ".js": "text/javascript", ".json": "application/json", ".css": "text/css" };
  const site = createServer((request, response) => {
    const path = new URL(request.url, "http://x").pathname;
    const file = path === "/scenes/default.json" ? scene : join(dist, normalize(path === "/" ? "/index.html" : path));
    if (!file.startsWith(dist) && file !== scene) return response.writeHead(403).end();
    if (!existsSync(file)) return response.writeHead(404).end();
    response.writeHead(200, { "Content-Type": types[extname(file)] ?? "application/octet-stream" });
    response.end(readFileSync(file));
  });
  await new Promise((r) => site.listen(0, "127.0.0.1", r));
  const url = `http://127.0.0.1:${site.address().port}/?scene=scenes/default.json` +
    `&server=http://127.0.0.1:${http}&width=${WIDTH}&height=${HEIGHT}`;

  context = await chromium.launchPersistentContext(join(work, "profile"), {
    executablePath: chromiumPath,
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
      "--disable-component-update", "--disable-sync", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
  });
  const page = await context.newPage();
  page.on("pageerror", (e) => console.error(`page error: ${e.message}`));
  const started = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.soltex && (window.soltex.converged || window.soltex.error), null,
    { timeout: 90000, polling: 250 });
  const status = await page.evaluate(() => window.soltex);
  if (status.error) throw new Error(`the page failed: ${status.error}`);
  console.log(`converged in ${Date.now() - started} ms: ${status.resident} of ${status.wanted} bricks wanted resident, ` +
    `${status.stats.received} fetched (${status.stats.bytes} bytes), ${status.stats.errors} errors`);
  if (status.stats.errors !== 0) throw new Error(`${status.stats.errors} brick requests failed`);
  if (status.resident !== status.wanted) throw new Error("converged with wanted bricks missing (pool full)");
  const png = await page.evaluate(() => document.getElementById("view").toDataURL("image/png"));
  const web = join(work, "web.png");
  writeFileSync(web, Buffer.from(png.split(",")[1], "base64"));

  const reference = join(work, "soltex-view.png");
  execFileSync(soltexView, ["--headless", "--local", "--width", String(WIDTH), "--height", String(HEIGHT),
    "--out", reference, "--log-level", "warn"], { stdio: "ignore" });
  // ImageMagick prints the PSNR on stderr and exits 1 when the pictures differ at all.
  let text = "";
  try {
    execFileSync("compare", ["-metric", "PSNR", web, reference, "null:"], { stdio: ["ignore", "ignore", "pipe"] });
  } catch (e) {
    text = e.stderr.toString();
  }
  const psnr = text === "" ? Infinity : Number.parseFloat(text);
  console.log(`web viewer vs soltex-view at ${WIDTH}x${HEIGHT}: PSNR ${psnr.toFixed(2)} dB (floor ${PSNR_FLOOR} dB)`);
  if (!(psnr >= PSNR_FLOOR)) {
    const kept = join(tmpdir(), "soltex-web-browser-failed.png");
    writeFileSync(kept, readFileSync(web));
    throw new Error(`PSNR ${psnr} dB is below the floor of ${PSNR_FLOOR} dB (the page's picture: ${kept})`);
  }
  // Switching to a preset texture and back, twice: the second round registers nothing new
  // (each texture id keeps its indirection and its bricks).
  const settle = () => page.waitForFunction(() => window.soltex.converged || window.soltex.error, null,
    { timeout: 90000, polling: 250 });
  const texturesBefore = status.textures;
  for (const key of ["1", "0", "1", "0"]) {
    await page.keyboard.press(key);
    await page.waitForTimeout(300);
    await settle();
  }
  const switched = await page.evaluate(() => window.soltex);
  if (switched.error) throw new Error(`the page failed switching textures: ${switched.error}`);
  console.log(`textures after switching twice: ${switched.textures} (${texturesBefore} before)`);
  if (!(switched.textures > texturesBefore && switched.textures <= 2 * texturesBefore)) {
    throw new Error(`switching to a preset and back twice made ${switched.textures} textures from ` +
      `${texturesBefore}: each switch registers anew`);
  }
  site.close();
} finally {
  await context?.close();
  server?.kill("SIGKILL");
  rmSync(work, { recursive: true, force: true });
}
