#include "soltex/render/frame_renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <memory>
#include <thread>
#include <unordered_map>

#include "soltex/common/texture_evaluator.h"
#include "soltex/render/shading.h"

namespace soltex {
namespace {

// Counts the pixels that missed each brick. Neighbouring pixels miss the same few bricks, so a
// handful of recent keys absorb nearly every count before the hash map sees one: a cold frame
// misses at every pixel.
class MissTally {
 public:
  void add(const BrickKey& key) {
    for (Slot& slot : recent_) {
      if (slot.pixels > 0 && slot.key == key) {
        ++slot.pixels;
        return;
      }
    }
    Slot& victim = recent_[next_++ % recent_.size()];
    if (victim.pixels > 0) counts_[victim.key] += victim.pixels;
    victim = {key, 1};
  }
  template <typename Visit>
  void for_each(Visit visit) {
    for (Slot& slot : recent_) {
      if (slot.pixels > 0) counts_[slot.key] += slot.pixels;
      slot.pixels = 0;
    }
    for (const auto& [key, pixels] : counts_) visit(key, pixels);
  }

 private:
  struct Slot {
    BrickKey key{};
    uint32_t pixels = 0;
  };
  std::array<Slot, 8> recent_{};
  unsigned next_ = 0;
  std::unordered_map<BrickKey, uint32_t, BrickKeyHash> counts_;
};

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr glm::vec3 kBackground{0.12f, 0.12f, 0.14f};

// Distinct colours for levels 0.. in false-colour mode.
glm::vec3 level_colour(int level) {
  static constexpr glm::vec3 kPalette[] = {
      {0.90f, 0.10f, 0.10f}, {0.95f, 0.55f, 0.10f}, {0.95f, 0.90f, 0.15f}, {0.30f, 0.80f, 0.20f},
      {0.15f, 0.70f, 0.85f}, {0.20f, 0.35f, 0.95f}, {0.60f, 0.25f, 0.90f}, {0.85f, 0.85f, 0.85f}};
  if (level < 0) return glm::vec3(0.0f);
  return kPalette[std::min<std::size_t>(static_cast<std::size_t>(level), std::size(kPalette) - 1)];
}

// Pixels per side of the tiles the shading pass hands to threads.
constexpr int kShadeTile = 32;

// A shading tile's row of background pixels, as Image::set() writes them: each row of a tile is
// copied from it first, and only covered pixels are written after (most of a frame can be
// background).
const std::array<uint8_t, 3 * kShadeTile>& background_row() {
  static const std::array<uint8_t, 3 * kShadeTile> row = [] {
    Image one(1, 1);
    one.set(0, 0, kBackground.r, kBackground.g, kBackground.b);
    std::array<uint8_t, 3 * kShadeTile> r{};
    for (std::size_t p = 0; p < r.size(); p += 3) std::copy_n(one.rgb.begin(), 3, r.begin() + p);
    return r;
  }();
  return row;
}
// Rows per block of the reference renderer's pass.
constexpr int kReferenceRows = 8;

bool key_less(const BrickKey& a, const BrickKey& b) {
  if (a.texture != b.texture) return a.texture < b.texture;
  if (a.level != b.level) return a.level < b.level;
  if (a.brick.z != b.brick.z) return a.brick.z < b.brick.z;
  if (a.brick.y != b.brick.y) return a.brick.y < b.brick.y;
  return a.brick.x < b.brick.x;
}

// Frames are drawn relative to the eye: the float matrices the rasterizer gets then carry only
// offsets from the camera, so objects far from the origin (1e6, 1e9) keep their precision.
struct EyeRelative {
  std::vector<RasterObject> objects;
  std::vector<glm::dvec4> clip_planes;
  glm::dmat4 view_projection;
};

EyeRelative eye_relative(const PreparedScene& scene, const Camera& camera, int width, int height) {
  const glm::dvec3& eye = camera.position;
  const glm::dmat4 from_world = glm::translate(glm::dmat4(1.0), -eye);
  EyeRelative r;
  r.objects.reserve(scene.objects.size());
  for (const PreparedObject& o : scene.objects) {
    RasterObject object = o.raster;
    object.model = glm::mat4(from_world * o.world_from_object);
    r.objects.push_back(object);
  }
  for (const glm::dvec4& plane : scene.clip_planes) {
    // a.(p + eye) + d >= 0  <=>  a.p + (d + a.eye) >= 0
    r.clip_planes.emplace_back(glm::dvec3(plane), plane.w + glm::dot(glm::dvec3(plane), eye));
  }
  Camera at_origin = camera;
  at_origin.target = camera.target - eye;
  at_origin.position = glm::dvec3(0.0);
  r.view_projection = view_projection(at_origin, width, height);
  return r;
}

// What a pixel's texture values give its lighting.
struct SurfaceInputs {
  glm::vec3 albedo;
  float opacity;
  float specular;
};

// Where a texture's sampled channels go: albedo (three channels, or one grey), opacity and
// specular (their index in the samples, or -1 for none).
struct MaterialInputs {
  bool colour = true;
  int opacity = -1;
  int specular = -1;
  float material_specular = 0.0f;
  float shininess = 0.0f;
  bool unlit = false;
  // Lit, three channels (colour only), drawn with a nearest or trilinear lookup at a tabled
  // level: the shading pass's fast path (TextureSampler::locate_rgb()).
  bool rgb_fast_path = false;

  // `values`: the texture's channels in order, as sampled or evaluated.
  SurfaceInputs read(const float* values) const {
    return {colour ? glm::vec3(values[0], values[1], values[2]) : glm::vec3(values[0]),
            opacity >= 0 ? values[opacity] : 1.0f,
            specular >= 0 ? values[specular] : material_specular};
  }
};

MaterialInputs material_inputs(const PreparedObject& object) {
  const ChannelSet& channels = object.texture.channels;
  const Material& material = object.object->material;
  MaterialInputs m;
  m.colour = channels.colour;
  int next = channels.colour ? 3 : 0;
  if (channels.opacity) m.opacity = next++;
  if (channels.specular) m.specular = next++;
  m.material_specular = material.specular;
  m.shininess = material.shininess;
  m.unlit = material.unlit;
  return m;
}

// A shaded colour seen through the texture's opacity: blended towards the background.
glm::vec3 over_background(const glm::vec3& colour, float opacity) {
  return opacity < 1.0f ? kBackground + opacity * (colour - kBackground) : colour;
}

void set_pixel(Image& image, int x, int y, const glm::vec3& colour, float opacity) {
  const glm::vec3 seen = over_background(colour, opacity);
  image.set(x, y, seen.r, seen.g, seen.b);
}

// The lit pixels of a tile waiting to be shaded together: where they are, their texture
// values, and the batch that shade_batch() lights.
struct LitPixels {
  ShadeBatch batch;
  ShadeBatch::Lanes<int> x, y;
  ShadeBatch::Lanes<std::size_t> index;  // in the G-buffer
  ShadeBatch::Lanes<float> opacity;

  void add(int lane, int px, int py, std::size_t i, const SurfaceInputs& surface, float shininess) {
    const auto l = static_cast<std::size_t>(lane);
    x[l] = px;
    y[l] = py;
    index[l] = i;
    opacity[l] = surface.opacity;
    batch.albedo_r[l] = surface.albedo.r;
    batch.albedo_g[l] = surface.albedo.g;
    batch.albedo_b[l] = surface.albedo.b;
    batch.specular[l] = surface.specular;
    batch.shininess[l] = shininess;
    cell[l] = nullptr;
  }

  // A lane whose albedo is still to be read from a brick cell (located, and prefetched).
  ShadeBatch::Lanes<const uint8_t*> cell;  // nullptr: the albedo is in the batch already
  ShadeBatch::Lanes<glm::vec3> fraction;
  ShadeBatch::Lanes<const TextureSampler*> sampler;

  void add_cell(int lane, int px, int py, std::size_t i, const uint8_t* first_sample,
                const glm::vec3& frac, const TextureSampler& texture, float specular,
                float shininess) {
    const auto l = static_cast<std::size_t>(lane);
    x[l] = px;
    y[l] = py;
    index[l] = i;
    opacity[l] = 1.0f;
    cell[l] = first_sample;
    fraction[l] = frac;
    sampler[l] = &texture;
    batch.specular[l] = specular;
    batch.shininess[l] = shininess;
    const int y_stride = texture.y_stride(), z_stride = texture.z_stride();
    __builtin_prefetch(first_sample);
    __builtin_prefetch(first_sample + y_stride);
    __builtin_prefetch(first_sample + z_stride);
    __builtin_prefetch(first_sample + y_stride + z_stride);
  }

  // The located cells' lookups, by now (one batch after their prefetch) in cache.
  void read_cells(bool nearest) {
    for (std::size_t l = 0; l < static_cast<std::size_t>(batch.count); ++l) {
      if (cell[l] == nullptr) continue;
      alignas(16) float rgb[4];
      if (nearest) {
        sampler[l]->nearest_rgb(cell[l], fraction[l], rgb);
      } else {
        sampler[l]->trilinear_rgb(cell[l], fraction[l], rgb);
      }
      batch.albedo_r[l] = rgb[0];
      batch.albedo_g[l] = rgb[1];
      batch.albedo_b[l] = rgb[2];
    }
  }

  void write(Image& image) const {
    for (std::size_t l = 0; l < static_cast<std::size_t>(batch.count); ++l) {
      set_pixel(image, x[l], y[l], {batch.colour_r[l], batch.colour_g[l], batch.colour_b[l]},
                opacity[l]);
    }
  }
};

// The lighting inputs of a batch's pixels: the world position unprojected from depth (relative
// to the eye through `inverse_vp`, the eye added back in double), the direction to the viewer,
// and the unit normal turned to face the viewer (seen from inside: flipped).
struct SurfaceUnprojection {
  glm::dmat4 inverse_vp;
  glm::dvec3 eye;
  int width;
  int height;

  void fill(const GBuffer& g, LitPixels& lit) const {
    ShadeBatch& b = lit.batch;
    const auto count = static_cast<std::size_t>(b.count);
    // Gathered first, so that the arithmetic below runs over plain arrays.
    alignas(64) ShadeBatch::Lanes<float> depth, nx, ny, nz;
    alignas(64) ShadeBatch::Lanes<uint8_t> back;
    for (std::size_t l = 0; l < count; ++l) {
      const std::size_t i = lit.index[l];
      depth[l] = g.depth[i];
      nx[l] = g.normal[i].x;
      ny[l] = g.normal[i].y;
      nz[l] = g.normal[i].z;
      back[l] = g.back_face(i) ? 1 : 0;
    }
    const glm::dmat4& m = inverse_vp;
    const double w = width, h = height;
    for (std::size_t l = 0; l < count; ++l) {
      const double ndc_x = (lit.x[l] + 0.5) / w * 2.0 - 1.0;
      const double ndc_y = 1.0 - (lit.y[l] + 0.5) / h * 2.0;
      const double ndc_z = static_cast<double>(depth[l]) * 2.0 - 1.0;
      // glm's matrix-vector product: (m0 x + m1 y) + (m2 z + m3 w), with w = 1.
      const double hx = (m[0].x * ndc_x + m[1].x * ndc_y) + (m[2].x * ndc_z + m[3].x * 1.0);
      const double hy = (m[0].y * ndc_x + m[1].y * ndc_y) + (m[2].y * ndc_z + m[3].y * 1.0);
      const double hz = (m[0].z * ndc_x + m[1].z * ndc_y) + (m[2].z * ndc_z + m[3].z * 1.0);
      const double hw = (m[0].w * ndc_x + m[1].w * ndc_y) + (m[2].w * ndc_z + m[3].w * 1.0);
      const double rx = hx / hw, ry = hy / hw, rz = hz / hw;
      b.position_x[l] = eye.x + rx;
      b.position_y[l] = eye.y + ry;
      b.position_z[l] = eye.z + rz;
      const auto vx = static_cast<float>(-rx);
      const auto vy = static_cast<float>(-ry);
      const auto vz = static_cast<float>(-rz);
      const float length = std::sqrt((vx * vx + vy * vy) + vz * vz);
      // Quotients first, selected after: a division under a condition would keep the loop
      // scalar (it might trap), a selection does not.
      const float qx = vx / length, qy = vy / length, qz = vz / length;
      const bool has_length = length > 0.0f;
      const float tx = has_length ? qx : 0.0f;
      const float ty = has_length ? qy : 0.0f;
      const float tz = has_length ? qz : 1.0f;
      const float n_length = std::sqrt((nx[l] * nx[l] + ny[l] * ny[l]) + nz[l] * nz[l]);
      const float mx = nx[l] / n_length, my = ny[l] / n_length, mz = nz[l] / n_length;
      const bool has_normal = n_length > 0.0f;
      const float ux = has_normal ? mx : tx;
      const float uy = has_normal ? my : ty;
      const float uz = has_normal ? mz : tz;
      const bool flip = back[l] != 0 || ((ux * tx + uy * ty) + uz * tz) < 0.0f;
      b.normal_x[l] = flip ? -ux : ux;
      b.normal_y[l] = flip ? -uy : uy;
      b.normal_z[l] = flip ? -uz : uz;
      b.to_viewer_x[l] = tx;
      b.to_viewer_y[l] = ty;
      b.to_viewer_z[l] = tz;
    }
  }
};

}  // namespace

glm::dmat4 view_projection(const Camera& camera, int width, int height) {
  const double aspect = static_cast<double>(width) / static_cast<double>(std::max(height, 1));
  const glm::dmat4 projection =
      glm::perspective(glm::radians(camera.fov_y_degrees), aspect, camera.near, camera.far);
  return projection * glm::lookAt(camera.position, camera.target, camera.up);
}

FrameRenderer::FrameRenderer(BrickCache& cache, RenderOptions options)
    : cache_(cache), options_(options), rasterizer_(RasterOptions{options.threads, false}) {}

Frame FrameRenderer::render(const PreparedScene& scene, const Camera& camera, int width,
                            int height) {
  Frame frame;
  frame.image = Image(width, height);
  const auto start = Clock::now();
  const EyeRelative relative = eye_relative(scene, camera, width, height);
  const glm::dmat4& vp = relative.view_projection;
  RasterView view;
  view.width = width;
  view.height = height;
  view.view_projection = glm::mat4(vp);
  view.clip_planes = relative.clip_planes;

  cache_.begin_frame();
  const glm::dmat4 inverse_vp = glm::inverse(vp);
  const PreparedLights lights = prepare_lights(*scene.scene);
  const auto threads = static_cast<std::size_t>(rasterizer_.thread_count());
  // Samplers (and their microcaches) live across frames, one set per render thread.
  std::vector<uint64_t> texture_ids;
  for (const PreparedObject& o : scene.objects) texture_ids.push_back(o.texture_id);
  if (samplers_.size() != threads || sampler_textures_ != texture_ids) {
    samplers_.clear();
    samplers_.resize(threads);
    for (auto& worker_samplers : samplers_) {
      for (const PreparedObject& o : scene.objects) {
        worker_samplers.push_back(
            std::make_unique<TextureSampler>(cache_, o.texture_id, o.layout, o.channels));
      }
    }
    sampler_textures_ = std::move(texture_ids);
  }
  // Per object: the level each footprint asks for, by table (quadrilinear needs the fraction
  // and keeps the continuous level of detail).
  const bool by_table = options_.filter != SampleFilter::quadrilinear;
  std::vector<NearestLevelTable> level_tables;
  if (by_table) {
    level_tables.reserve(scene.objects.size());
    for (const PreparedObject& o : scene.objects) {
      level_tables.emplace_back(o.layout, options_.level_bias);
    }
  }
  // Per object: how the texture's channels become albedo, opacity and specular.
  std::vector<MaterialInputs> materials;
  materials.reserve(scene.objects.size());
  for (const PreparedObject& o : scene.objects) {
    MaterialInputs m = material_inputs(o);
    m.rgb_fast_path = by_table && !options_.false_colour_levels && !m.unlit && o.channels == 3;
    materials.push_back(m);
  }
  struct Worker {
    MissTally misses;
    std::size_t covered = 0, fallback = 0, empty = 0, shaded = 0;
    Clock::duration shading{0};
  };
  std::vector<Worker> workers(threads);
  const SurfaceUnprojection unprojection{inverse_vp, camera.position, width, height};
  const std::size_t object_count = scene.objects.size();
  // Shades the frame's pixels [x0, x1) x [y0, y1) on render thread `worker_index`, from `g`,
  // which holds the frame's pixel (x, y) at g.index(x - origin_x, y - origin_y).
  const auto shade_tile = [&](const GBuffer& g, int origin_x, int origin_y, int x0, int y0, int x1,
                              int y1, int worker_index) {
    Worker& worker = workers[static_cast<std::size_t>(worker_index)];
    auto& samplers = samplers_[static_cast<std::size_t>(worker_index)];
    LitPixels lit;  // about 40 KB of stack, uninitialised but for the count
    const auto flush = [&] {
      lit.read_cells(options_.filter == SampleFilter::nearest);
      unprojection.fill(g, lit);
      shade_batch(lights, lit.batch);
      lit.write(frame.image);
      lit.batch.count = 0;
    };
    MissedBricks missed;
    const std::array<uint8_t, 3 * kShadeTile>& background = background_row();
    assert(x1 - x0 <= kShadeTile);
    for (int y = y0; y < y1; ++y) {
      std::copy_n(
          background.begin(), 3 * (x1 - x0),
          frame.image.rgb.begin() + 3 * (static_cast<std::ptrdiff_t>(y) * frame.image.width + x0));
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = g.index(x - origin_x, y - origin_y);
        if (!g.covered(i)) continue;  // the background is there already
        const uint32_t id = g.object_id[i];
        if (id >= object_count) continue;
        ++worker.covered;
        TextureSampler& sampler = *samplers[id];
        const MaterialInputs& m = materials[id];
        SampleResult result;
        if (m.rgb_fast_path) {
          // The common case in two steps: locate and prefetch now, read at the flush.
          const int level = level_tables[id].level(g.footprint[i]);
          glm::vec3 frac;
          if (const uint8_t* cell = sampler.locate_rgb(g.texture_position[i], level, frac)) {
            ++worker.shaded;
            lit.add_cell(lit.batch.count++, x, y, i, cell, frac, sampler, m.material_specular,
                         m.shininess);
            if (lit.batch.count == ShadeBatch::kCapacity) flush();
            continue;
          }
          result =
              sampler.sample_after_miss(g.texture_position[i], level, options_.filter, &missed);
        } else {
          const double lod = by_table
                                 ? static_cast<double>(level_tables[id].level(g.footprint[i]))
                                 : sampler.level_of_detail(g.footprint[i]) + options_.level_bias;
          result = sampler.sample(g.texture_position[i], lod, options_.filter, &missed);
        }
        for (const BrickKey& key : missed.view()) worker.misses.add(key);
        if (!result.complete) ++worker.fallback;
        if (result.level < 0) ++worker.empty;
        if (options_.false_colour_levels) {
          const glm::vec3 colour = level_colour(result.level);
          frame.image.set(x, y, colour.r, colour.g, colour.b);
          continue;
        }
        const SurfaceInputs surface = m.read(result.values.data());
        if (m.unlit) {
          set_pixel(frame.image, x, y, surface.albedo, surface.opacity);
          continue;
        }
        ++worker.shaded;
        lit.add(lit.batch.count++, x, y, i, surface, m.shininess);
        if (lit.batch.count == ShadeBatch::kCapacity) flush();
      }
    }
    if (lit.batch.count > 0) flush();
  };
  // Each raster tile is shaded by the thread that resolved it, right after, while its
  // G-buffer is still in that core's cache (a tile no triangle reached comes as the shared
  // empty buffer); in square pieces, whose pixels read few bricks.
  const auto shade_raster_tile = [&](const GBuffer& g, int origin_x, int origin_y, int x0, int y0,
                                     int x1, int y1, int worker_index) {
    const auto shade_start = Clock::now();
    for (int ty = y0; ty < y1; ty += kShadeTile) {
      for (int tx = x0; tx < x1; tx += kShadeTile) {
        shade_tile(g, origin_x, origin_y, tx, ty, std::min(x1, tx + kShadeTile),
                   std::min(y1, ty + kShadeTile), worker_index);
      }
    }
    workers[static_cast<std::size_t>(worker_index)].shading += Clock::now() - shade_start;
  };
  if (options_.keep_gbuffer) {
    frame.stats.raster = rasterizer_.render(
        view, relative.objects, gbuffer_, [&](int x0, int y0, int x1, int y1, int worker_index) {
          shade_raster_tile(gbuffer_, 0, 0, x0, y0, x1, y1, worker_index);
        });
  } else {
    frame.stats.raster = rasterizer_.render_tiles(
        view, relative.objects,
        [&](const GBuffer& tile, int x0, int y0, int x1, int y1, int worker_index) {
          shade_raster_tile(tile, x0, y0, x0, y0, x1, y1, worker_index);
        });
  }
  for (auto& worker_samplers : samplers_) {
    for (auto& sampler : worker_samplers) sampler->flush_statistics();
  }
  std::unordered_map<BrickKey, uint32_t, BrickKeyHash> misses;
  for (Worker& worker : workers) {
    worker.misses.for_each([&](const BrickKey& key, uint32_t pixels) { misses[key] += pixels; });
    frame.stats.covered_pixels += worker.covered;
    frame.stats.fallback_pixels += worker.fallback;
    frame.stats.empty_pixels += worker.empty;
    frame.stats.shaded_pixels += worker.shaded;
  }
  frame.misses.reserve(misses.size());
  for (const auto& [key, pixels] : misses) frame.misses.push_back({key, pixels});
  // Which thread drew which tile varies from frame to frame; the list does not.
  std::sort(
      frame.misses.begin(), frame.misses.end(),
      [](const net::BrickWant& a, const net::BrickWant& b) { return key_less(a.key, b.key); });
  // One pass now does both: split its wall time by the share of render-thread time spent
  // shading (an estimate; the threads are busy throughout the pass).
  Clock::duration shading{0};
  for (const Worker& worker : workers) shading += worker.shading;
  const double total_ms = ms_since(start);
  const double shading_ms =
      std::chrono::duration<double, std::milli>(shading).count() / static_cast<double>(threads);
  frame.stats.shade_ms = std::min(total_ms, shading_ms);
  frame.stats.raster_ms = total_ms - frame.stats.shade_ms;
  return frame;
}

Image FrameRenderer::render_reference(const PreparedScene& scene, const Camera& camera, int width,
                                      int height, int supersample) {
  const int k = std::clamp(supersample, 1, 8);
  const int w = width * k, h = height * k;
  const EyeRelative relative = eye_relative(scene, camera, w, h);
  const glm::dmat4& vp = relative.view_projection;
  RasterView view;
  view.width = w;
  view.height = h;
  view.view_projection = glm::mat4(vp);
  view.clip_planes = relative.clip_planes;
  GBuffer& g = reference_gbuffer_;
  rasterizer_.render(view, relative.objects, g);
  std::vector<TextureEvaluator> evaluators;
  for (const PreparedObject& o : scene.objects) evaluators.emplace_back(o.texture);
  const glm::dmat4 inverse_vp = glm::inverse(vp);
  const PreparedLights lights = prepare_lights(*scene.scene);
  std::vector<glm::vec3>& colours = reference_colours_;
  colours.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  const int row_blocks = (h + kReferenceRows - 1) / kReferenceRows;
  std::vector<MaterialInputs> materials;
  materials.reserve(scene.objects.size());
  for (const PreparedObject& o : scene.objects) materials.push_back(material_inputs(o));
  const SurfaceUnprojection unprojection{inverse_vp, camera.position, w, h};
  rasterizer_.parallel_for(static_cast<std::size_t>(row_blocks), [&](std::size_t block, int) {
    // Lit the way render() lights, in batches (the same lighting, bit for bit, as per pixel):
    // the comparison is then between evaluating and looking up, not between two lighting loops.
    LitPixels lit;
    const auto flush = [&] {
      unprojection.fill(g, lit);
      shade_batch(lights, lit.batch);
      for (std::size_t l = 0; l < static_cast<std::size_t>(lit.batch.count); ++l) {
        colours[lit.index[l]] = over_background(
            {lit.batch.colour_r[l], lit.batch.colour_g[l], lit.batch.colour_b[l]}, lit.opacity[l]);
      }
      lit.batch.count = 0;
    };
    const int first = static_cast<int>(block) * kReferenceRows;
    const int end = std::min(h, first + kReferenceRows);
    for (int y = first; y < end; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = g.index(x, y);
        if (!g.covered(i) || g.object_id[i] >= scene.objects.size()) {
          colours[i] = kBackground;
          continue;
        }
        const PreparedObject& object = scene.objects[g.object_id[i]];
        // The footprint as the cached path sees it, so both band-limit alike.
        const Texel texel =
            evaluators[g.object_id[i]].sample(g.texture_position[i], g.footprint[i]);
        float values[5] = {texel.colour.r, texel.colour.g, texel.colour.b, 0.0f, 0.0f};
        const ChannelSet& c = object.texture.channels;
        int next = c.colour ? 3 : 0;
        if (!c.colour) values[0] = texel.field;
        const auto scalar = [&](const ScalarRange& r) {
          return r.low + (r.high - r.low) * texel.field;
        };
        if (c.opacity) values[next++] = scalar(object.texture.opacity);
        if (c.specular) values[next++] = scalar(object.texture.specular);
        const MaterialInputs& m = materials[g.object_id[i]];
        const SurfaceInputs surface = m.read(values);
        if (m.unlit) {
          colours[i] = over_background(surface.albedo, surface.opacity);
          continue;
        }
        lit.add(lit.batch.count++, x, y, i, surface, m.shininess);
        if (lit.batch.count == ShadeBatch::kCapacity) flush();
      }
    }
    if (lit.batch.count > 0) flush();
  });
  Image image(width, height);
  const float weight = 1.0f / static_cast<float>(k * k);
  const int image_blocks = (height + kReferenceRows - 1) / kReferenceRows;
  rasterizer_.parallel_for(static_cast<std::size_t>(image_blocks), [&](std::size_t block, int) {
    const int first = static_cast<int>(block) * kReferenceRows;
    const int end = std::min(height, first + kReferenceRows);
    for (int y = first; y < end; ++y) {
      for (int x = 0; x < width; ++x) {
        glm::vec3 sum(0.0f);
        for (int sy = 0; sy < k; ++sy)
          for (int sx = 0; sx < k; ++sx) sum += colours[g.index(x * k + sx, y * k + sy)];
        sum *= weight;
        image.set(x, y, sum.r, sum.g, sum.b);
      }
    }
  });
  if (k > 1) {
    // Kept only at 1x: a supersampled reference is k^2 frames of memory, and a one-off.
    reference_gbuffer_ = GBuffer{};
    std::vector<glm::vec3>().swap(reference_colours_);
  }
  return image;
}

}  // namespace soltex
