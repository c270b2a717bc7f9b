// libFuzzer target for MaterialX documents (soltex::materialx::compile_nodegraph). Every input
// either throws MaterialxError or gives a compiled graph that evaluates to finite colours in
// [0, 1] at points near and far, the point and grid forms agreeing bit for bit.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "soltex/common/texture_evaluator.h"
#include "soltex/materialx/materialx_reader.h"

namespace {

// The names the seed documents use for their nodegraphs.
const char* const kNodegraphs[] = {"g", "granite", "veined_marble", "cells", "stripes_and_cells"};

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "materialx_reader_fuzz: %s\n", what);
  std::abort();
}

void check(const soltex::TextureEvaluator& evaluator) {
  soltex::Grid grid;
  grid.origin = glm::dvec3(-0.7, 3.1, 1e9);
  grid.step = glm::dvec3(0.05);
  grid.count = {4, 2, 2};
  std::vector<float> planes(grid.size() * 3);
  for (double width : {0.0, 0.05, 1e6}) {
    evaluator.evaluate_grid(grid, width, planes);
    for (float v : planes) {
      if (!(v >= 0.0f && v <= 1.0f)) fail("a sample is not finite or not in [0, 1]");
    }
    const soltex::Texel t = evaluator.sample(grid.point(3, 1, 1), width);
    const std::size_t last = grid.size() - 1;
    if (t.colour.r != planes[last] || t.colour.g != planes[grid.size() + last] ||
        t.colour.b != planes[2 * grid.size() + last]) {
      fail("sample() and evaluate_grid() differ");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const char* nodegraph : kNodegraphs) {
    soltex::TextureSpec spec;
    try {
      spec.graph = soltex::materialx::compile_nodegraph({text, "fuzz.mtlx", nodegraph, "out"});
    } catch (const soltex::materialx::MaterialxError&) {
      continue;
    }
    check(soltex::TextureEvaluator(spec));
  }
  return 0;
}
