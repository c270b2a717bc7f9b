// A real soltexd with --http-listen on loopback, started once for the test run (vitest
// globalSetup); the tests fetch bricks the C++ encoder wrote from it.
import { spawn, type ChildProcess } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";

import type { TestProject } from "vitest/node";

let server: ChildProcess | undefined;
let directory = "";

export function soltexdBinary(): string {
  const binary = process.env.SOLTEXD_BINARY ?? resolve(__dirname, "../../../build/server/soltexd");
  if (!existsSync(binary)) {
    throw new Error(`soltexd not found at ${binary}: build it first or set SOLTEXD_BINARY`);
  }
  return binary;
}

export default async function setup(project: TestProject): Promise<() => void> {
  directory = mkdtempSync(join(tmpdir(), "soltex-web-test-"));
  const ready = join(directory, "ready");
  server = spawn(
    soltexdBinary(),
    ["--listen", "127.0.0.1:0", "--metrics-listen", "127.0.0.1:0", "--http-listen", "127.0.0.1:0",
     "--ready-file", ready, "--threads", "2", "--log-level", "warn"],
    { stdio: "inherit" },
  );
  const deadline = Date.now() + 20000;
  let port = 0;
  while (Date.now() < deadline && port === 0) {
    if (existsSync(ready)) {
      const match = /^http=(\d+)$/m.exec(readFileSync(ready, "utf8"));
      if (match) port = Number(match[1]);
    }
    if (port === 0) await new Promise((r) => setTimeout(r, 20));
  }
  if (port === 0) throw new Error("soltexd did not write its ready file within 20 s");
  project.provide("soltexdHttp", `http://127.0.0.1:${port}`);
  return () => {
    server?.kill("SIGKILL");
    rmSync(directory, { recursive: true, force: true });
  };
}

declare module "vitest" {
  export interface ProvidedContext {
    soltexdHttp: string;
  }
}
