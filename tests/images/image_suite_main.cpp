// image_suite: every scene of the suite drawn through the brick cache until converged and
// compared with its supersampled per-pixel reference (4 x 4, or as the case says). Prints one line
// per scene and "N passed, N failed"; --table writes the markdown table of docs/IMAGES.md. Exit 0
// when every scene meets its floors, 1 otherwise, 2 on bad usage.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <set>

#include "headless_session.h"
#include "image_case.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::images {
namespace {

struct Outcome {
  const ImageCase* scene = nullptr;
  double psnr = 0.0;
  double share_off = 0.0;
  double flatness = -1.0;         // pixel_roughness(), when the case checks it
  double smooth_flatness = -1.0;  // the same on the smooth texture
  bool passed = false;
  std::string error;
};

// Draws until every brick a frame wants is resident (bricks are made in this process, exactly
// as soltexd makes them), as soltex-view --headless does.
struct Drawn {
  Image cached;
  Image reference;
};

Drawn draw(const ImageCase& c, const std::filesystem::path& scratch, bool with_reference) {
  const Scene scene = parse_scene(c.scene_json, c.name, scratch);
  BrickCache cache(std::size_t{1} << 30);
  net::LocalBrickSource source(cache);
  const TextureResolution resolution{c.finest_level_log2, 16, MipSettings{}};
  PreparedScene prepared = prepare_scene(scene, resolution, source);
  RenderOptions options;
  options.antialias = c.antialias;
  options.access = c.access;
  FrameRenderer renderer(cache, options);
  const int width = scene.image.width, height = scene.image.height;
  // The loop soltex-view --headless runs.
  view::HeadlessOptions converge;
  converge.max_time = std::chrono::seconds(120);
  view::HeadlessResult result = view::render_until_converged(renderer, prepared, scene.camera,
                                                             width, height, source, converge);
  if (result.converged_ms < 0.0) throw std::runtime_error("did not converge in 120 s");
  Drawn drawn;
  drawn.cached = std::move(result.image);
  if (with_reference) {
    drawn.reference =
        renderer.render_reference(prepared, scene.camera, width, height, c.reference_supersample);
  }
  return drawn;
}

double share_off(const Image& a, const Image& b, int steps) {
  std::size_t off = 0;
  for (std::size_t p = 0; p < a.rgb.size(); p += 3) {
    for (std::size_t c = 0; c < 3; ++c) {
      if (std::abs(int(a.rgb[p + c]) - int(b.rgb[p + c])) > steps) {
        ++off;
        break;
      }
    }
  }
  return static_cast<double>(off) / static_cast<double>(a.rgb.size() / 3);
}

// Mean |p(x - 1) - 2 p(x) + p(x + 1)| along rows where all three pixels show an object (not
// the background's colour), over the three channels: what a pattern adds from pixel to pixel.
// Smooth shading and smooth textures add little; moire and aliasing add a lot.
double pixel_roughness(const Image& image) {
  Image background(1, 1);
  background.set(0, 0, 0.12f, 0.12f, 0.14f);
  const auto is_background = [&](const uint8_t* p) {
    return p[0] == background.rgb[0] && p[1] == background.rgb[1] && p[2] == background.rgb[2];
  };
  double sum = 0.0;
  std::size_t count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      const uint8_t* a = image.pixel(x - 1, y);
      const uint8_t* b = image.pixel(x, y);
      const uint8_t* c = image.pixel(x + 1, y);
      if (is_background(a) || is_background(b) || is_background(c)) continue;
      for (int k = 0; k < 3; ++k) sum += std::abs(int(a[k]) - 2 * int(b[k]) + int(c[k]));
      count += 3;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

Outcome measure(const ImageCase& c, const std::filesystem::path& scratch,
                std::map<std::string, Image>& cached_images, const std::filesystem::path& out) {
  Outcome o;
  o.scene = &c;
  const bool against_reference = c.same_as.empty();
  const Drawn drawn = draw(c, scratch, against_reference);
  const Image& truth = against_reference ? drawn.reference : cached_images.at(c.same_as);
  o.psnr = psnr(drawn.cached, truth);
  o.share_off = share_off(drawn.cached, truth, 16);
  o.passed = o.psnr >= c.psnr_floor && o.share_off <= c.max_share_off;
  if (!c.smooth_json.empty()) {
    ImageCase smooth = c;
    smooth.scene_json = c.smooth_json;
    o.flatness = pixel_roughness(drawn.cached);
    o.smooth_flatness = pixel_roughness(draw(smooth, scratch, false).cached);
    // "About as smooth": within twice the smooth texture's roughness, which is mostly the
    // shading's 8-bit steps (moire is many times rougher).
    o.passed = o.passed && o.flatness <= 2.0 * o.smooth_flatness;
  }
  cached_images[c.name] = drawn.cached;
  if (!out.empty()) {
    std::string file = c.group + "-" + c.name;
    for (char& ch : file) {
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '.') ch = '_';
    }
    write_png(out / (file + ".png"), drawn.cached);
    if (against_reference) write_png(out / (file + "-reference.png"), drawn.reference);
  }
  return o;
}

void print(const Outcome& o) {
  const ImageCase& c = *o.scene;
  if (!o.error.empty()) {
    std::printf("FAIL  [%s] %s: %s\n", c.group.c_str(), c.name.c_str(), o.error.c_str());
    return;
  }
  std::printf("%s  [%s] %s: %.2f dB (floor %.1f), %.2f %% off by > 16 (bound %.1f %%)",
              o.passed ? "ok  " : "FAIL", c.group.c_str(), c.name.c_str(), o.psnr, c.psnr_floor,
              100.0 * o.share_off, 100.0 * c.max_share_off);
  if (o.flatness >= 0.0) {
    std::printf(", roughness %.2f (smooth noise: %.2f)", o.flatness, o.smooth_flatness);
  }
  std::printf("\n");
  std::fflush(stdout);
}

// The worst case of each pattern per group (the targets and models one by one): what a user
// reads first.
void write_summary(std::ofstream& out, const std::vector<Outcome>& outcomes) {
  struct Worst {
    double psnr = std::numeric_limits<double>::infinity();
    double share_off = 0.0;
    int cases = 0, passed = 0;
  };
  std::vector<std::pair<std::string, Worst>> rows;
  for (const Outcome& o : outcomes) {
    const ImageCase& c = *o.scene;
    const bool one_by_one = c.group == "targets" || c.group == "models";
    const std::string kind = one_by_one ? c.name : c.name.substr(0, c.name.find_first_of(" ,"));
    const std::string key = c.group + " | " + kind;
    auto row =
        std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == key; });
    if (row == rows.end()) row = rows.insert(rows.end(), {key, Worst{}});
    row->second.psnr = std::min(row->second.psnr, o.psnr);
    row->second.share_off = std::max(row->second.share_off, o.share_off);
    row->second.cases += 1;
    row->second.passed += o.passed ? 1 : 0;
  }
  out << "| group | pattern or scene | scenes | lowest PSNR (dB) | most pixels off by > 16 | "
         "passed |\n|---|---|---:|---:|---:|---:|\n";
  for (const auto& [key, worst] : rows) {
    char row[512];
    std::snprintf(row, sizeof row, "| %s | %d | %.2f | %.2f %% | %d of %d |\n", key.c_str(),
                  worst.cases, worst.psnr, 100.0 * worst.share_off, worst.passed, worst.cases);
    out << row;
  }
}

void write_table(const std::filesystem::path& path, const std::vector<Outcome>& outcomes) {
  std::ofstream out(path);
  write_summary(out, outcomes);
  out << "\nEvery scene:\n\n"
         "| group | scene | PSNR (dB) | floor | pixels off by > 16 | bound | |\n"
         "|---|---|---:|---:|---:|---:|---|\n";
  for (const Outcome& o : outcomes) {
    const ImageCase& c = *o.scene;
    char row[512];
    std::snprintf(row, sizeof row, "| %s | %s | %.2f | %.1f | %.2f %% | %.1f %% | %s |\n",
                  c.group.c_str(), c.name.c_str(), o.psnr, c.psnr_floor, 100.0 * o.share_off,
                  100.0 * c.max_share_off, o.passed ? "ok" : "**below**");
    out << row;
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace
}  // namespace soltex::images

int main(int argc, char** argv) {
  using namespace soltex::images;
  CLI::App app{"image_suite: the cached picture against its supersampled reference"};
  std::filesystem::path models = SOLTEX_MODELS_DIR, scratch = "image-suite-scratch", table, out;
  std::set<std::string> groups;
  std::string only;
  app.add_option("--models", models, "folder of the OBJ test models")->capture_default_str();
  app.add_option("--group", groups,
                 "run these groups only (targets, patterns, clip planes, "
                 "offsets, models)");
  app.add_option("--only", only, "run the scenes whose name contains this text");
  app.add_option("--scratch", scratch, "folder for the OBJ files the suite writes");
  app.add_option("--table", table, "write the results as a markdown table");
  app.add_option("--images", out, "write every cached image and its reference as PNG");
  CLI11_PARSE(app, argc, argv);
  if (!std::filesystem::is_directory(models)) {
    std::printf("models: %s is absent; the models group is skipped\n", models.c_str());
  }
  if (!out.empty()) std::filesystem::create_directories(out);
  const std::vector<ImageCase> cases = image_cases(models, scratch);
  std::vector<Outcome> outcomes;
  std::map<std::string, soltex::Image> cached_images;
  int passed = 0, failed = 0;
  for (const ImageCase& c : cases) {
    if (!groups.empty() && !groups.count(c.group)) continue;
    if (!only.empty() && c.name.find(only) == std::string::npos) continue;
    Outcome o;
    try {
      o = measure(c, scratch, cached_images, out);
    } catch (const std::exception& e) {
      o.scene = &c;
      o.error = e.what();
    }
    print(o);
    (o.passed ? passed : failed) += 1;
    outcomes.push_back(o);
  }
  if (!table.empty()) write_table(table, outcomes);
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
