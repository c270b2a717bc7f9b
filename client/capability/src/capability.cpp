#include "soltex/capability/capability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <sstream>
#include <stdexcept>

#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::capability {
namespace {

std::size_t available_memory_mb() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::size_t kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit) {
    if (key == "MemAvailable:") return kb / 1024;
  }
  return 1024;  // unknown: assume a modest machine
}

double parse_number(const std::string& item, const std::string& value, double lo, double hi) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || !std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream message;
    message << "--capability " << item << "=" << value << ": must be a number in [" << lo << ", "
            << hi << "]";
    throw std::invalid_argument(message.str());
  }
  return v;
}

}  // namespace

CapabilityOverride parse_override(const std::string& text) {
  CapabilityOverride o;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument("--capability item '" + item + "' must be NAME=VALUE");
    }
    const std::string name = item.substr(0, eq), value = item.substr(eq + 1);
    if (name == "cpu") {
      o.cpu_factor = parse_number(name, value, 1e-3, 1e3);
    } else if (name == "mem") {
      o.memory_mb = static_cast<std::size_t>(parse_number(name, value, 16, 1 << 24));
    } else if (name == "bandwidth") {
      o.bandwidth_mb_per_s = parse_number(name, value, 1e-3, 1e6);
    } else {
      throw std::invalid_argument("--capability: unknown item '" + name +
                                  "' (expected cpu, mem or bandwidth)");
    }
  }
  return o;
}

Capability apply(Capability measured, const CapabilityOverride& o) {
  if (o.cpu_factor) measured.pixels_per_second *= *o.cpu_factor;
  if (o.memory_mb) measured.available_memory_mb = *o.memory_mb;
  if (o.bandwidth_mb_per_s) measured.bandwidth_mb_per_s = *o.bandwidth_mb_per_s;
  return measured;
}

Capability measure_machine() {
  Capability c;
  c.available_memory_mb = available_memory_mb();
  // The probe: a lit sphere carved from the colour cube, 320 x 180, drawn from an
  // in-process cache that already holds what the frame needs.
  Scene scene;
  scene.name = "capability probe";
  scene.camera.position = {0.0, 0.0, 3.0};
  scene.lights.push_back(DirectionalLight{{-0.3, -0.5, -1.0}, glm::vec3(1.0f), 1.0f});
  SceneObject sphere;
  sphere.name = "probe";
  sphere.source = SphereShape{};
  sphere.mesh = std::make_shared<const Mesh>(make_sphere(SphereShape{1.0, 48, 24}));
  sphere.material.texture = validated(TextureSpec{ColourCubeParams{0.5}, {}, {}, {}, {}});
  scene.objects.push_back(std::move(sphere));

  BrickCache cache(32u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{});
  const int width = 320, height = 180;
  for (int i = 0; i < 20; ++i) {  // fill the cache first: the probe measures drawing
    Frame frame = renderer.render(prepared, scene.camera, width, height);
    if (frame.complete()) break;
    source.want(std::move(frame.misses));
    source.wait_idle(std::chrono::seconds(2));
  }
  const auto start = std::chrono::steady_clock::now();
  int frames = 0;
  double elapsed = 0.0;
  while (frames < 3 || elapsed < 0.05) {
    renderer.render(prepared, scene.camera, width, height);
    ++frames;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  c.pixels_per_second = static_cast<double>(width) * height * frames / elapsed;
  return c;
}

void measure_link(net::BrickSource& source, const TextureSpec& texture, Capability& capability) {
  Volume probe;
  probe.min = glm::dvec3(-1.0);
  probe.max = glm::dvec3(1.0);
  probe.finest_level_log2 = 7;  // 16^3-cell bricks: level 1 holds 4^3 = 64 of them
  const uint64_t id = source.register_texture(texture, probe, 16, {});
  std::vector<net::BrickWant> wants;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) wants.push_back({{id, 1, {x, y, z}}, 1});
  const net::SourceStats before = source.stats();
  const auto start = std::chrono::steady_clock::now();
  source.want(std::move(wants));
  source.wait_idle(std::chrono::seconds(20));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const net::SourceStats after = source.stats();
  const double bytes = static_cast<double>(after.bytes - before.bytes);
  const double bricks = static_cast<double>(after.received - before.received);
  if (bytes > 0.0 && bricks > 0.0 && seconds > 0.0) {
    capability.bandwidth_mb_per_s = bytes / seconds / 1e6;
    capability.bytes_per_brick = bytes / bricks;
  }
}

Choice choose(const Capability& capability, const Scene& scene, int width, int height,
              const ChoiceLimits& limits) {
  Choice choice;
  std::ostringstream why;

  // Frame size: shrink (keeping the aspect) until a frame fits the time target.
  const double pixels = static_cast<double>(width) * height;
  const double affordable = capability.pixels_per_second * limits.target_frame_seconds;
  double scale = 1.0;
  if (affordable > 0.0 && pixels > affordable) scale = std::sqrt(affordable / pixels);
  scale = std::max(scale, 0.125);
  choice.width = std::max(16, static_cast<int>(width * scale));
  choice.height = std::max(16, static_cast<int>(height * scale));
  why << "frame " << choice.width << "x" << choice.height << ": this machine draws "
      << static_cast<long>(capability.pixels_per_second / 1e6 * 10) / 10.0
      << " Mpixel/s, a frame must fit " << limits.target_frame_seconds * 1000 << " ms\n";

  // Cache: an eighth of the available memory, within [32 MiB, 1 GiB].
  const std::size_t budget_mb =
      std::clamp<std::size_t>(capability.available_memory_mb / 8, 32, 1024);
  choice.cache_budget_bytes = budget_mb << 20;
  why << "cache " << budget_mb << " MiB: 1/8 of " << capability.available_memory_mb
      << " MiB available\n";

  // Finest level: fine enough for the largest object on screen (one texel per pixel), no
  // finer than the link can deliver in fetch_seconds or the cache can hold.
  double largest_pixels = 64.0;
  const double tan_half = std::tan(glm::radians(scene.camera.fov_y_degrees) * 0.5);
  for (const SceneObject& object : scene.objects) {
    const glm::dvec3 size = glm::dvec3(object.mesh->bounds.size()) * object.transform.scale;
    const double radius = 0.5 * glm::length(size);
    const double distance =
        std::max(glm::length(object.transform.translate - scene.camera.position), 1e-6);
    largest_pixels = std::max(largest_pixels, radius / (distance * tan_half) * choice.height);
  }
  const int screen_level =
      std::clamp(static_cast<int>(std::ceil(std::log2(largest_pixels))), 4, limits.max_level_log2);
  const double objects = static_cast<double>(std::max<std::size_t>(scene.objects.size(), 1));
  // Bricks on the visible half of an object's surface at level L with 16^3-cell bricks:
  // about 3 faces * (2^L / 16)^2.
  const auto surface_bricks = [&](int level) {
    const double per_axis = std::ldexp(1.0, level - 4);
    return objects * 3.0 * per_axis * per_axis;
  };
  const double byte_budget = capability.bandwidth_mb_per_s * 1e6 * limits.fetch_seconds;
  int level = screen_level;
  while (level > 4 && capability.bandwidth_mb_per_s > 0.0 &&
         surface_bricks(level) * capability.bytes_per_brick > byte_budget) {
    --level;
  }
  const double decoded_brick_bytes = 17.0 * 17.0 * 17.0 * 3.0 + 64.0;
  while (level > 4 &&
         surface_bricks(level) * decoded_brick_bytes > 0.5 * choice.cache_budget_bytes) {
    --level;
  }
  choice.finest_level_log2 = level;
  why << "finest level 2^" << level << ": objects span up to " << static_cast<int>(largest_pixels)
      << " pixels (2^" << screen_level << "); about "
      << static_cast<long>(surface_bricks(level) * capability.bytes_per_brick / 1e3)
      << " kB of bricks over a " << capability.bandwidth_mb_per_s << " MB/s link (budget "
      << static_cast<long>(byte_budget / 1e3) << " kB)";
  choice.reason = why.str();
  return choice;
}

}  // namespace soltex::capability
