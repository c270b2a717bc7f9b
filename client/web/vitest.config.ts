import { defineConfig } from "vitest/config";

export default defineConfig({
  test: {
    globalSetup: ["test/soltexd.ts"],
    include: ["test/**/*.test.ts"],
    testTimeout: 20000,
  },
});
