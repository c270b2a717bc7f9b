#include "soltex/capability/capability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/spec_error.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/texture_volume.h"

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
    message << "--capability " << item << "=" << value << ": must be a number in ["
            << spec_number_text(lo) << ", " << spec_number_text(hi) << "]";
    throw std::invalid_argument(message.str());
  }
  return v;
}

}  // namespace

CapabilityOverride parse_override(const std::string& text) {
  CapabilityOverride o;
  std::stringstream items(text);
  std::string item;
  std::set<std::string> seen;
  while (std::getline(items, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument("--capability item '" + item + "' must be NAME=VALUE");
    }
    const std::string name = item.substr(0, eq), value = item.substr(eq + 1);
    // Which of two values was meant is not for the reader to guess.
    if (!seen.insert(name).second) {
      throw std::invalid_argument("--capability: item '" + name + "' is given twice");
    }
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

Capability measure_memory() {
  Capability c;
  c.available_memory_mb = available_memory_mb();
  return c;
}

Capability measure_machine() {
  Capability c = measure_memory();
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
  sphere.material.texture = validated(TextureSpec{ColourCubeParams{0.5}, {}, {}, {}, {}, {}});
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

void fit_link(const LinkTiming& small, const LinkTiming& large, Capability& capability) {
  if (large.bricks <= 0.0 || large.bytes <= 0.0) return;  // nothing moved: in-process
  capability.bytes_per_brick = large.bytes / large.bricks;
  const double extra_bytes = large.bytes - small.bytes;
  const double extra_seconds = large.seconds - small.seconds;
  if (extra_bytes <= 0.0 || extra_seconds <= 0.0) {
    // The larger burst came as fast as the small one: the bandwidth did not limit either.
    capability.bandwidth_mb_per_s = 0.0;
    capability.brick_latency_ms = std::max(0.0, small.seconds) * 1e3;
    return;
  }
  const double bytes_per_second = extra_bytes / extra_seconds;
  capability.bandwidth_mb_per_s = bytes_per_second / 1e6;
  capability.brick_latency_ms = std::max(0.0, small.seconds - small.bytes / bytes_per_second) * 1e3;
}

namespace {

// Asks for `keys` at once and waits until all are in.
LinkTiming burst(net::BrickSource& source, std::vector<net::BrickWant> wants,
                 const ProbeClock& clock) {
  const net::SourceStats before = source.stats();
  const auto start = clock();
  source.want(std::move(wants));
  source.wait_idle(std::chrono::seconds(20));
  LinkTiming timing;
  timing.seconds = std::chrono::duration<double>(clock() - start).count();
  const net::SourceStats after = source.stats();
  timing.bytes = static_cast<double>(after.bytes - before.bytes);
  timing.bricks = static_cast<double>(after.received - before.received);
  return timing;
}

// Every brick of one level of the probe volume: 8^(3 - level) of them.
std::vector<net::BrickWant> probe_level(uint64_t id, int level) {
  const int per_axis = 1 << (3 - level);
  std::vector<net::BrickWant> wants;
  for (int z = 0; z < per_axis; ++z)
    for (int y = 0; y < per_axis; ++y)
      for (int x = 0; x < per_axis; ++x) wants.push_back({{id, level, {x, y, z}}, 1});
  return wants;
}

}  // namespace

Codec codec_for_link(double bandwidth_mb_per_s, double zstd_ratio, double zstd_decode_ns_per_byte) {
  if (bandwidth_mb_per_s <= 0.0 || zstd_ratio <= 1.0) return Codec::zstd;
  // Per decoded byte: zstd saves (1 - 1 / ratio) bytes on the link and costs this much CPU.
  const double saved_link_ns = (1.0 - 1.0 / zstd_ratio) / bandwidth_mb_per_s * 1e3;
  const double extra_cpu_ns = kZstdExtraCpuPerDecode * zstd_decode_ns_per_byte;
  return saved_link_ns < extra_cpu_ns ? Codec::raw : Codec::zstd;
}

namespace {

// The link's bandwidth alone: the same number of colour-cube bricks (which the server makes in
// microseconds) once in zstd, which shrinks them to a few hundred bytes, and once raw; the
// extra time of the raw burst is its extra bytes on the link, as the server's work per brick
// is nearly the same. Bursts of 8 first, and of 64 only where those leave the choice open,
// so that a thin link pays for about 120 kB of probe, not a megabyte. 0: the raw bursts were
// no slower (the link is faster than the probe can tell).
double raw_link_mb_per_s(net::BrickSource& source, const Volume& volume, double zstd_ratio,
                         double decode_ns, const ProbeClock& clock) {
  const TextureSpec cube = validated(TextureSpec{ColourCubeParams{0.5}, {}, {}, {}, {}, {}});
  const MipSettings point{MipMode::point, 1};
  const auto shifted = [&](double by) {
    Volume v = volume;
    v.min += by;
    v.max += by;
    return v;
  };
  const uint64_t packed = source.register_texture(cube, shifted(4.0), 16, point);
  const uint64_t raw = source.register_texture(cube, shifted(8.0), 16, point);
  const auto extra_bandwidth = [&](int level) {
    source.set_codec(Codec::zstd);
    const LinkTiming small = burst(source, probe_level(packed, level), clock);
    source.set_codec(Codec::raw);
    const LinkTiming large = burst(source, probe_level(raw, level), clock);
    const double extra_seconds = large.seconds - small.seconds;
    return extra_seconds > 0.0 ? (large.bytes - small.bytes) / extra_seconds / 1e6 : 0.0;
  };
  double mb_per_s = extra_bandwidth(2);
  if (mb_per_s <= 0.0 || codec_for_link(2.0 * mb_per_s, zstd_ratio, decode_ns) == Codec::raw) {
    mb_per_s = extra_bandwidth(1);
  }
  source.set_codec(Codec::zstd);
  return mb_per_s;
}

}  // namespace

void measure_link(net::BrickSource& source, const TextureSpec& texture, Capability& capability,
                  bool choose_codec, const ProbeClock& clock) {
  Volume probe;
  probe.min = glm::dvec3(-1.0);
  probe.max = glm::dvec3(1.0);
  probe.finest_level_log2 = 7;  // 16^3-cell bricks: levels 3, 2, 1 hold 1, 8 and 64 of them
  source.set_codec(Codec::zstd);
  const uint64_t id = source.register_texture(texture, probe, 16, {});
  burst(source, probe_level(id, 3), clock);  // opens the stream: no part of the link
  const LinkTiming small = burst(source, probe_level(id, 2), clock);
  const LinkTiming large = burst(source, probe_level(id, 1), clock);
  fit_link(small, large, capability);
  if (!choose_codec || large.bytes <= 0.0) return;
  const net::SourceStats stats = source.stats();
  const auto zstd = static_cast<std::size_t>(Codec::zstd);
  if (stats.decoded_bytes[zstd] == 0) return;
  capability.zstd_decode_ns_per_byte =
      stats.decode_seconds[zstd] * 1e9 / static_cast<double>(stats.decoded_bytes[zstd]);
  const double ratio = kRawBrickBytes / capability.bytes_per_brick;
  capability.raw_link_mb_per_s =
      raw_link_mb_per_s(source, probe, ratio, capability.zstd_decode_ns_per_byte, clock);
  capability.codec =
      capability.raw_link_mb_per_s > 0.0
          ? codec_for_link(capability.raw_link_mb_per_s, ratio, capability.zstd_decode_ns_per_byte)
          : Codec::raw;
}

namespace {

// Shrinks the frame (keeping the aspect) until one fits the time target; a headless frame
// keeps the size asked for.
void choose_frame(const Capability& capability, int width, int height, const ChoiceLimits& limits,
                  Choice& choice, std::ostringstream& why) {
  choice.width = width;
  choice.height = height;
  if (!limits.scale_frame) {
    why << "frame " << width << "x" << height << ": the size asked for\n";
    return;
  }
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
}

// The camera's distance to the nearest point of the object's bounds in the world (0 inside).
double nearest_distance(const SceneObject& object, const Camera& camera) {
  const BoundingBox& bounds = object.mesh->bounds;
  const glm::dmat4 to_world = object.transform.matrix();
  glm::dvec3 low(std::numeric_limits<double>::infinity());
  glm::dvec3 high(-std::numeric_limits<double>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 model((corner & 1) ? bounds.max.x : bounds.min.x,
                           (corner & 2) ? bounds.max.y : bounds.min.y,
                           (corner & 4) ? bounds.max.z : bounds.min.z);
    const glm::dvec3 world(to_world * glm::dvec4(model, 1.0));
    low = glm::min(low, world);
    high = glm::max(high, world);
  }
  return glm::length(glm::max(glm::max(low - camera.position, camera.position - high), 0.0));
}

// The finest level at which one texel of the object's texture is no larger than a pixel where
// the object comes nearest the camera, `distance` away (at least the near plane, if the camera
// is inside its bounds); level 0 when the object's material fixes its own level or it has no
// mesh.
struct ObjectNeed {
  int level = 0;
  double distance = 0.0;
};

ObjectNeed object_screen_level(const SceneObject& object, const Camera& camera, int frame_height) {
  if (!object.mesh || object.mesh->bounds.empty() || object.material.volume.finest_level_log2) {
    return {};
  }
  const Volume volume = texture_volume(object, 8);
  const double side = std::max(
      {volume.max.x - volume.min.x, volume.max.y - volume.min.y, volume.max.z - volume.min.z});
  // A texture-space unit in the world: the transform's largest scale for object space.
  const glm::dvec3& scale = object.transform.scale;
  const double world_per_unit =
      object.material.space == TextureSpace::object ? std::max({scale.x, scale.y, scale.z}) : 1.0;
  const double distance = std::max(nearest_distance(object, camera), camera.near);
  const double pixel = 2.0 * distance * std::tan(glm::radians(camera.fov_y_degrees) * 0.5) /
                       static_cast<double>(frame_height);
  const double texels = side * world_per_unit / pixel;
  if (!(texels > 1.0)) return {0, distance};
  return {static_cast<int>(std::ceil(std::log2(std::min(texels, 0x1p30)))), distance};
}

// Bricks a frame reads with the finest level at L (16^3-cell bricks): the visible half of each
// object's surface, about 3 faces * (2^L / 16)^2, but never more than the frame's pixels hold,
// since each pixel reads about one texel at the level it draws from. A brick's face of 16^2
// texels covers about 256 pixels face-on; `screen` is the frame's pixels over 128, which allows
// for surfaces crossing bricks at a slant and the coarser level trilinear filtering blends in.
struct FrameBricks {
  double objects = 1.0;
  double screen = 0.0;
  double operator()(int level) const {
    const double per_axis = std::ldexp(1.0, level - 4);
    return std::min(objects * 3.0 * per_axis * per_axis, screen);
  }
};

// Finest level: one texel per pixel where an object comes nearest the camera, no finer than
// the cache can hold. The link does not enter: it only sets where to start.
void choose_finest_level(const Scene& scene, const ChoiceLimits& limits,
                         const FrameBricks& frame_bricks, Choice& choice, std::ostringstream& why) {
  int screen_level = 4;
  const SceneObject* nearest = nullptr;
  double nearest_at = 0.0;
  for (const SceneObject& object : scene.objects) {
    const ObjectNeed need = object_screen_level(object, scene.camera, choice.height);
    if (need.level > screen_level) {
      screen_level = need.level;
      nearest = &object;
      nearest_at = need.distance;
    }
  }
  const double decoded_brick_bytes = 17.0 * 17.0 * 17.0 * 3.0 + 64.0;
  const int chosen = std::min(screen_level, limits.max_level_log2);
  const int wanted = limits.finest_level_log2 > 0 ? limits.finest_level_log2 : chosen;
  int level = wanted;
  while (level > 4 && frame_bricks(level) * decoded_brick_bytes > 0.5 * choice.cache_budget_bytes) {
    --level;
  }
  // The estimate bounds a frame's bricks from above, often far above (every object's whole
  // surface at the level, or the frame's pixels at one brick per 128): where it exceeds the
  // budget the run starts no finer than the level it fits, and refines while the cache holds
  // what the next level needs, as the frames' misses tell.
  choice.finest_level_log2 = wanted;
  choice.start_level_log2 = level;
  why << "finest level 2^" << wanted << ": ";
  if (limits.finest_level_log2 > 0) {
    why << "--finest-level (this machine's choice: 2^" << chosen << ")";
  } else if (nearest == nullptr) {
    why << "no object needs finer than 2^4";
  } else {
    why << "a texel per pixel at 2^" << screen_level << " where "
        << (nearest->name.empty() ? std::string("an object") : "\"" + nearest->name + "\"")
        << " comes nearest, " << static_cast<float>(nearest_at) << " from the camera";
  }
  if (limits.finest_level_log2 == 0 && wanted < screen_level) why << "; at most 2^" << wanted;
  if (level < wanted) {
    why << "; a frame at 2^" << level << " surely fits the cache: it starts there at the "
        << "finest and refines while the cache holds the next level";
  }
  why << "\n";
}

}  // namespace

Choice choose(const Capability& capability, const Scene& scene, int width, int height,
              const ChoiceLimits& limits) {
  Choice choice;
  std::ostringstream why;
  choose_frame(capability, width, height, limits, choice, why);

  // Cache: an eighth of the available memory, within [32 MiB, 1 GiB].
  const std::size_t eighth_mb = capability.available_memory_mb / 8;
  const std::size_t budget_mb = std::clamp<std::size_t>(eighth_mb, 32, 1024);
  choice.cache_budget_bytes = budget_mb << 20;
  why << "cache " << budget_mb << " MiB: 1/8 of " << capability.available_memory_mb
      << " MiB available";
  if (budget_mb != eighth_mb) {
    why << (budget_mb > eighth_mb ? ", raised to 32 MiB" : ", at most 1 GiB");
  }
  why << "\n";

  const FrameBricks frame_bricks{
      static_cast<double>(std::max<std::size_t>(scene.objects.size(), 1)),
      static_cast<double>(choice.width) * choice.height * limits.texels_per_pixel / 128.0};
  choose_finest_level(scene, limits, frame_bricks, choice, why);

  // Start: the finest level whose frame bricks arrive within fetch_seconds: a round of
  // requests costs the latency once, their bytes cost the bandwidth.
  const auto fetch_seconds = [&](int l) {
    const double bricks = frame_bricks(l);
    const double rounds = 1.0 + std::ceil(bricks / static_cast<double>(limits.in_flight_bricks));
    const double transfer =
        capability.bandwidth_mb_per_s > 0.0
            ? bricks * capability.bytes_per_brick / (capability.bandwidth_mb_per_s * 1e6)
            : 0.0;
    return rounds * capability.brick_latency_ms / 1e3 + transfer;
  };
  int start = choice.start_level_log2;  // no finer than the cache surely holds
  while (start > 4 && fetch_seconds(start) > limits.fetch_seconds) --start;
  choice.start_level_log2 = start;
  why << "start at 2^" << start << ", refine when idle: about "
      << static_cast<long>(frame_bricks(start) * capability.bytes_per_brick / 1e3)
      << " kB of bricks in " << static_cast<long>(fetch_seconds(start) * 1e3) << " ms over ";
  if (capability.bandwidth_mb_per_s > 0.0) {
    why << "a " << capability.bandwidth_mb_per_s << " MB/s link";
  } else {
    why << "a link of unlimited bandwidth";  // 0: in-process, loopback, or too fast to tell
  }
  why << " with " << capability.brick_latency_ms << " ms latency (budget "
      << limits.fetch_seconds * 1e3 << " ms)";
  choice.reason = why.str();
  return choice;
}

}  // namespace soltex::capability
