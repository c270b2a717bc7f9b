// soltex-gallery: renders every texture as a slice through the solid and on a lit sphere,
// one PNG per texture, and prints where they are.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/geometric.hpp>
#include <vector>

#include "gallery_scenes.h"
#include "soltex/cli/tool_cli.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/render/image.h"

namespace {

using soltex::Grid;
using soltex::Image;
using soltex::TextureEvaluator;

// Left half: the plane z = 0.3 over [-1, 1]^2 (negative coordinates included), evaluated as
// one batch grid band-limited to the pixel spacing.
void draw_slice(const TextureEvaluator& texture, Image& image, int size) {
  const double spacing = 2.0 / size;
  Grid grid;
  grid.origin = {-1.0 + 0.5 * spacing, -1.0 + 0.5 * spacing, 0.3};
  grid.step = {spacing, spacing, 0.0};
  grid.count = {size, size, 1};
  const int channels = texture.spec().channels.sample_count();
  std::vector<float> planes(grid.size() * static_cast<std::size_t>(channels));
  texture.evaluate_grid(grid, spacing, planes);
  const std::size_t n = grid.size();
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const std::size_t i = static_cast<std::size_t>(size - 1 - y) * size + x;  // y up
      image.set(x, y, planes[i], planes[n + i], planes[2 * n + i]);
    }
  }
}

// Right half: a unit sphere carved out of the solid texture, Lambert shading.
void draw_sphere(const TextureEvaluator& texture, Image& image, int size) {
  const glm::dvec3 light = glm::normalize(glm::dvec3(-0.5, 0.7, 1.0));
  const double pixel = 2.4 / size;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = -1.2 + (x + 0.5) * pixel;
      const double v = 1.2 - (y + 0.5) * pixel;
      const double r2 = u * u + v * v;
      if (r2 >= 1.0) {
        image.set(size + x, y, 0.12f, 0.12f, 0.14f);
        continue;
      }
      const glm::dvec3 p(u, v, std::sqrt(1.0 - r2));  // orthographic view along -z
      // Footprint grows towards the silhouette, where the surface turns away.
      const double footprint = pixel / std::max(p.z, 0.05);
      const soltex::Texel texel = texture.sample(p, footprint);
      const float shade = static_cast<float>(0.15 + 0.85 * std::max(0.0, glm::dot(p, light)));
      image.set(size + x, y, texel.colour.r * shade, texel.colour.g * shade,
                texel.colour.b * shade);
    }
  }
}

// Every texture as one PNG in `out_dir`; throws when a file cannot be written.
void write_gallery(const std::filesystem::path& out_dir, int size) {
  std::filesystem::create_directories(out_dir);
  std::printf("soltex-gallery: %d x %d slice + sphere per texture -> %s\n", size, size,
              std::filesystem::absolute(out_dir).c_str());
  for (const auto& entry : soltex::gallery::gallery_textures()) {
    const auto start = std::chrono::steady_clock::now();
    const TextureEvaluator texture(entry.spec);
    Image image(2 * size, size);
    draw_slice(texture, image, size);
    draw_sphere(texture, image, size);
    const auto path = out_dir / (entry.name + ".png");
    soltex::write_png(path, image);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("  %-20s %7.1f ms  %s  (%s)\n", entry.name.c_str(), ms, path.c_str(),
                entry.description.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = soltex::cli;
  CLI::App app{"soltex-gallery: every solid texture as a slice and on a sphere, as PNG files"};
  std::filesystem::path out_dir = "gallery";
  int size = 256;
  std::string log_level = "info";
  cli::add_common_options(app, "soltex-gallery", log_level);
  // --out-dir as in soltex-bench, since it names a folder; --out is the old name.
  app.add_option("--out-dir,--out", out_dir, "folder for the PNG files")->capture_default_str();
  app.add_option("--size", size, "pixels per side of each half")
      ->check(soltex::cli::IntegerIn(16, 4096))
      ->capture_default_str();
  if (const auto exit_code = cli::parse(app, "soltex-gallery", argc, argv)) return *exit_code;
  cli::start_logging("soltex-gallery", log_level);
  try {
    write_gallery(out_dir, size);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-gallery: %s\n", e.what());
    return cli::kExitFailure;
  }
  return cli::kExitOk;
}
