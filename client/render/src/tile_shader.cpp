#include "tile_shader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>

#include "soltex/common/check.h"
#include "soltex/render/anisotropic_taps.h"
#include "soltex/render/shading.h"

namespace soltex::render {
namespace {

// Distinct colours for levels 0.. in false-colour mode; pixels evaluated per pixel are white.
glm::vec3 level_colour(int level) {
  static constexpr glm::vec3 kPalette[] = {
      {0.90f, 0.10f, 0.10f}, {0.95f, 0.55f, 0.10f}, {0.95f, 0.90f, 0.15f}, {0.30f, 0.80f, 0.20f},
      {0.15f, 0.70f, 0.85f}, {0.20f, 0.35f, 0.95f}, {0.60f, 0.25f, 0.90f}, {0.85f, 0.85f, 0.85f}};
  if (level < 0) return glm::vec3(0.0f);
  return kPalette[std::min<std::size_t>(static_cast<std::size_t>(level), std::size(kPalette) - 1)];
}
constexpr glm::vec3 kEvaluatedColour{1.0f, 1.0f, 1.0f};

// A tile's row of background pixels, as Image::set() writes them: each row of a tile is copied
// from it first, and only covered pixels are written after (most of a frame can be background).
const std::array<uint8_t, 3 * TileShader::kTile>& background_row() {
  static const std::array<uint8_t, 3 * TileShader::kTile> row = [] {
    Image one(1, 1);
    one.set(0, 0, kBackground.r, kBackground.g, kBackground.b);
    std::array<uint8_t, 3 * TileShader::kTile> r{};
    for (std::size_t p = 0; p < r.size(); p += 3) std::copy_n(one.rgb.begin(), 3, r.begin() + p);
    return r;
  }();
  return row;
}

}  // namespace

inline void TileShader::use_cached_object(const ObjectShading& object, TextureSampler& sampler,
                                          Image& image) {
  if (cached_.pending != 0 && cached_.object != &object) look_up_all(image);
  cached_.object = &object;
  cached_.sampler = &sampler;
}

// Inline: shade() calls it for most pixels of a frame.
inline void TileShader::add_cached(Pixel pixel, const glm::dvec3& p, int level,
                                   const ObjectShading& object, TextureSampler& sampler,
                                   Image& image) {
  use_cached_object(object, sampler, image);
  const auto l = static_cast<std::size_t>(level);
  SOLTEX_DCHECK(l < CachedPixels::kLevels);
  CachedPixels::Group& group = cached_.groups[l];
  std::size_t count = group.count;
  const uint32_t slot = slot_of(pixel);
  const bool full = group.push(count, slot, p);
  group.count = count;
  // In a tile, what the pixel shares with its object now; its albedo when looked up.
  if (by_tile_) {
    const MaterialInputs& m = object.material;
    tile_.add_shared(slot, 1, m.material_specular, m.shininess);
  }
  cached_.pending |= 1u << l;
  if (full) look_up(level, image);
}

// The fast path's pixels [x_begin, x_end) of row y, all of `object`, pixel x_begin at `first`
// in the G-buffer and its level at levels[0]: add_cached() for each, the object settled once
// and the group of the level in hand kept (with its count) while the level stays the same, as
// it mostly does from one pixel to the next.
void TileShader::add_cached_run(const GBuffer& g, int x_begin, int x_end, int y, std::size_t first,
                                const RowLevels& row, const ObjectShading& object,
                                TextureSampler& sampler, Image& image) {
  SOLTEX_DCHECK(by_tile_);
  use_cached_object(object, sampler, image);
  const auto first_slot = static_cast<uint32_t>(tile_.slot(x_begin, y));
  // What the run's pixels share now, in contiguous stores; their albedo when looked up.
  const MaterialInputs& m = object.material;
  tile_.add_shared(first_slot, static_cast<std::size_t>(x_end - x_begin), m.material_specular,
                   m.shininess);
  CachedPixels::Group* group = nullptr;
  int level = -1;
  std::size_t count = 0;
  for (int x = x_begin; x < x_end; ++x) {
    const std::size_t i = first + static_cast<std::size_t>(x - x_begin);
    const int l = row.levels[x - x_begin];
    if (const int n = row.taps[x - x_begin]; n > 1) {
      if (group != nullptr) group->count = count;
      group = nullptr;
      level = -1;
      add_taps(g, i, first_slot + static_cast<uint32_t>(x - x_begin), n, l, image);
      continue;
    }
    if (l != level) {
      if (group != nullptr) group->count = count;
      level = l;
      SOLTEX_DCHECK(static_cast<std::size_t>(l) < CachedPixels::kLevels);
      group = &cached_.groups[static_cast<std::size_t>(l)];
      count = group->count;
      cached_.pending |= 1u << l;
    }
    const uint32_t slot = first_slot + static_cast<uint32_t>(x - x_begin);
    if (group->push(count, slot, g.texture_position[i])) {
      group->count = count;
      look_up(level, image);
      group = nullptr;
      level = -1;
    }
  }
  if (group != nullptr) group->count = count;
}

int TileShader::tap_count_at(const GBuffer& g, std::size_t i) const {
  const int most = frame_.options.anisotropy;
  return most > 1 ? tap_count(g.footprint[i], g.footprint_minor[i], most) : 1;
}

void TileShader::make_row_levels(const GBuffer& g, std::size_t row, std::size_t count,
                                 const ObjectShading& object, RowLevelArrays& out) const {
  SOLTEX_DCHECK(count <= out.levels.size());
  const float* footprint = &g.footprint[row];
  const int most = frame_.options.anisotropy;
  if (most <= 1) {
    std::fill_n(out.taps.begin(), count, uint8_t{1});
    object.level_table.levels({footprint, count}, out.levels.data());
    return;
  }
  // A pixel of n taps is looked up at the level of its taps' share (as tapped_lookup() takes
  // it), one lookup at its footprint's.
  const float* minor = &g.footprint_minor[row];
  alignas(64) std::array<float, kTile> share;
  for (std::size_t j = 0; j < count; ++j) {
    const int n = tap_count(footprint[j], minor[j], most);
    out.taps[j] = static_cast<uint8_t>(n);
    share[j] = tap_share(footprint[j], n);
  }
  object.level_table.levels({share.data(), count}, out.levels.data());
}

glm::dvec3 TileShader::lookup_point(const GBuffer& g, std::size_t i, const ObjectShading& object,
                                    double lod) const {
  const glm::dvec3& p = g.texture_position[i];
  if (object.cached_inset <= 0.0) return p;
  // The coarser of the levels a lookup may read sets the step (quadrilinear reads two).
  const double spacing = std::ldexp(object.level0_spacing, static_cast<int>(std::ceil(lod)));
  return axis_face_inset(p, object.surface.normal(g.normal[i]), object.cached_inset * spacing);
}

TileShader::TapsResult TileShader::tapped_lookup(const GBuffer& g, std::size_t i, int n,
                                                 const ObjectShading& object,
                                                 TextureSampler& sampler) {
  // Each tap covers its share of the long side.
  const double lod = lod_of(object, sampler, tap_share(g.footprint[i], n));
  const TapsResult taps =
      look_up_taps(g.footprint_axis[i], lookup_point(g, i, object, lod), n, lod, sampler);
  count_tapped_result(taps.incomplete, taps.found);
  return taps;
}

double TileShader::lod_of(const ObjectShading& object, const TextureSampler& sampler,
                          float footprint) const {
  return frame_.by_table() ? static_cast<double>(object.level_table.level(footprint))
                           : sampler.level_of_detail(footprint) + frame_.options.level_bias;
}

void TileShader::add_taps(const GBuffer& g, std::size_t i, uint32_t slot, int n, int level,
                          Image& image) {
  SOLTEX_DCHECK(by_tile_ && slot < LitTile::kPixels && n > 1);
  SOLTEX_DCHECK(level == cached_.object->level_table.level(tap_share(g.footprint[i], n)));
  taps_.sum[slot] = glm::vec3(0.0f);
  taps_.weight[slot] = tap_weight(n);
  taps_.incomplete[slot] = 0;
  taps_.found[slot] = 0;
  taps_.slots.push_back(slot);
  count_tapped_pixel(n);
  const auto l = static_cast<std::size_t>(level);
  CachedPixels::Group& group = cached_.groups[l];
  // A pixel's taps are looked up together, never split over two lookups of the group: its
  // misses are tallied once per brick as they come (tile_tap_misses_).
  if (group.count + static_cast<std::size_t>(n) > CachedPixels::kCapacity) look_up(level, image);
  const glm::dvec3& p = g.texture_position[i];
  const glm::vec3& axis = g.footprint_axis[i];
  std::size_t count = group.count;
  for (int k = 0; k < n; ++k) group.push(count, slot | kTapSlot, tap_position(p, axis, k, n));
  group.count = count;
  cached_.pending |= 1u << l;
  if (count == CachedPixels::kCapacity) look_up(level, image);
}

TileShader::TapsResult TileShader::look_up_taps(const glm::vec3& axis, const glm::dvec3& p, int n,
                                                double lod, TextureSampler& sampler) {
  const RenderOptions& options = frame_.options;
  TapsResult taps;
  taps.average.fill(0.0f);
  begin_tapped_lookups(n);
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 q = tap_position(p, axis, k, n);
    const SampleResult r = options.misses_only
                               ? sampler.find_misses(q, lod, options.filter, &missed_)
                               : sampler.sample(q, lod, options.filter, &missed_);
    count_tap_misses(pixel_tap_misses_);
    taps.incomplete |= !r.complete;
    taps.found |= r.level >= 0;
    taps.coarsest = std::max(taps.coarsest, r.level);
    for (std::size_t c = 0; c < taps.average.size(); ++c) taps.average[c] += r.values[c];
  }
  // As finish_taps() averages the fast path's taps: the sum, then times one tap's weight.
  const float weight = tap_weight(n);
  for (float& value : taps.average) value *= weight;
  return taps;
}

void TileShader::count_tapped_pixel(int n) {
  ++counts_.tapped;
  counts_.taps += static_cast<std::size_t>(n);
}

void TileShader::begin_tapped_lookups(int n) {
  count_tapped_pixel(n);
  pixel_tap_misses_.keys.clear();
}

void TileShader::count_tapped_result(bool incomplete, bool found) {
  counts_.fallback += incomplete ? 1 : 0;
  counts_.empty += found ? 0 : 1;
}

void TileShader::count_tap_misses(PixelMisses& pixel) {
  for (const BrickKey& key : missed_.view()) {
    if (pixel.first_time(key)) misses_.add(key);
  }
}

void TileShader::finish_taps() {
  for (const uint32_t slot : taps_.slots) {
    const glm::vec3 average = taps_.sum[slot] * taps_.weight[slot];
    const float rgb[3] = {average.r, average.g, average.b};
    tile_.add_albedo(slot, rgb);
    count_tapped_result(taps_.incomplete[slot] != 0, taps_.found[slot] != 0);
    ++counts_.shaded;
  }
  taps_.slots.clear();
  tile_tap_misses_.begin(PixelMisses::kNone);  // slots are numbered afresh in the next tile
}

void TileShader::shade(const GBuffer& g, int origin_x, int origin_y, int x0, int y0, int x1, int y1,
                       Image& image) {
  assert(x1 - x0 <= kTile);
  SOLTEX_DCHECK(y1 - y0 <= kTile);
  gbuffer_ = &g;
  by_tile_ = true;
  tile_.x0 = x0;
  tile_.y0 = y0;
  tile_.width = x1 - x0;
  tile_.height = y1 - y0;
  tile_.first = g.index(x0 - origin_x, y0 - origin_y);
  tile_.row_stride = static_cast<std::size_t>(g.width);
  const auto& background = background_row();
  const std::size_t object_count = frame_.objects.size();
  // Counted in a register and added once: an increment in memory per pixel chains each pixel
  // to the one before through a store and a load.
  std::size_t covered = 0;
  // The fast path's levels and taps of the row's pixels, by the table of `levels_object`: made
  // for the whole row at once (whole vectors, one call) when a run first needs them, again only
  // where the row's runs see another object.
  RowLevelArrays row_levels;
  for (int y = y0; y < y1; ++y) {
    std::copy_n(background.begin(), 3 * (x1 - x0),
                image.rgb.begin() + 3 * (static_cast<std::ptrdiff_t>(y) * image.width + x0));
    const std::size_t row = g.index(x0 - origin_x, y - origin_y);  // pixel (x0, y)
    const ObjectShading* levels_object = nullptr;
    for (int x = x0; x < x1;) {
      const std::size_t i = row + static_cast<std::size_t>(x - x0);
      const uint32_t id = g.object_id[i];
      // An uncovered pixel keeps the background that is there already.
      if (!g.covered(i) || id >= object_count) {
        ++x;
        continue;
      }
      // The run of pixels that see the same object, taken together.
      int end = x + 1;
      for (std::size_t j = i + 1; end < x1 && g.covered(j) && g.object_id[j] == id; ++j) ++end;
      covered += static_cast<std::size_t>(end - x);
      const ObjectShading& object = frame_.objects[id];
      const bool misses_run =
          object.evaluator == nullptr && frame_.options.misses_only && frame_.by_table();
      if (misses_run ||
          (object.evaluator == nullptr && object.rgb_fast_path && object.cached_inset == 0.0)) {
        // shade_cached()'s fast path without its calls: the level from the table (the fast
        // path has one), the point where the surface was drawn.
        if (levels_object != &object) {
          // The row's uncovered pixels too: their footprints are written (0) with the rest of
          // the G-buffer, and their levels are made and never read.
          make_row_levels(g, row, static_cast<std::size_t>(x1 - x0), object, row_levels);
          levels_object = &object;
        }
        const RowLevels run = row_levels.from(static_cast<std::size_t>(x - x0));
        if (misses_run) {
          find_run_misses(g, i, static_cast<std::size_t>(end - x), run, object, *samplers_[id]);
        } else {
          add_cached_run(g, x, end, y, i, run, object, *samplers_[id], image);
        }
        x = end;
        continue;
      }
      for (; x < end; ++x) {
        const Pixel pixel{x, y, row + static_cast<std::size_t>(x - x0)};
        if (object.evaluator != nullptr) {
          shade_evaluated(g, pixel, object, image);
        } else {
          shade_cached(g, pixel, object, *samplers_[id], image);
        }
      }
    }
  }
  counts_.covered += covered;
  if (cached_.pending != 0) look_up_all(image);
  if (!taps_.slots.empty()) finish_taps();
  if (evaluated_.count > 0) evaluate(image);
  SOLTEX_DCHECK(lit_.batch.count == 0);
  tile_.light(frame_.unprojection, frame_.lights, g, lit_.batch, image);
  by_tile_ = false;
}

void TileShader::shade_pixels(const GBuffer& g, int origin_x, int origin_y,
                              std::span<const glm::ivec2> pixels, Image& image) {
  gbuffer_ = &g;
  list_ = pixels;
  list_origin_x_ = origin_x;
  list_origin_y_ = origin_y;
  list_at_ = 0;
  for (; list_at_ < pixels.size(); ++list_at_) {
    const glm::ivec2 at = pixels[list_at_];
    const Pixel pixel{at.x, at.y, g.index(at.x - origin_x, at.y - origin_y)};
    const uint32_t id = g.object_id[pixel.index];
    if (!g.covered(pixel.index) || id >= frame_.objects.size()) continue;
    ++counts_.covered;
    const ObjectShading& object = frame_.objects[id];
    if (object.evaluator != nullptr) {
      shade_evaluated(g, pixel, object, image);
    } else {
      shade_cached(g, pixel, object, *samplers_[id], image);
    }
  }
  if (cached_.pending != 0) look_up_all(image);
  if (evaluated_.count > 0) evaluate(image);
  if (lit_.batch.count > 0) flush(image);
}

void TileShader::shade_evaluated(const GBuffer& g, Pixel pixel, const ObjectShading& object,
                                 Image& image) {
  ++counts_.evaluated;
  // Taps along a grazing footprint's long side, each evaluated over its share of it, as the
  // cached lookups take them; counted in every kind of frame alike.
  const int taps = tap_count_at(g, pixel.index);
  if (taps > 1) count_tapped_pixel(taps);
  if (frame_.options.misses_only) return;  // evaluated textures miss no brick
  if (frame_.options.false_colour_levels) {
    image.set(pixel.x, pixel.y, kEvaluatedColour.r, kEvaluatedColour.g, kEvaluatedColour.b);
    return;
  }
  if (evaluated_.count > 0 && evaluated_.object != &object) evaluate(image);
  if (evaluated_.count + static_cast<std::size_t>(taps) > EvaluatedPixels::kCapacity) {
    evaluate(image);
  }
  evaluated_.object = &object;
  // The point and box are made for the whole batch at once (evaluated_inputs()).
  EvaluatedLanes& e = evaluated_.lanes;
  const glm::dvec3& p = g.texture_position[pixel.index];
  const glm::vec3& n = g.normal[pixel.index];
  const float footprint = tap_share(g.footprint[pixel.index], taps);
  for (int k = 0; k < taps; ++k) {
    const std::size_t i = evaluated_.count++;
    evaluated_.pixels[i] = pixel;
    evaluated_.taps[i] = static_cast<uint8_t>(k == 0 ? taps : 0);
    const glm::dvec3 q = taps == 1 ? p : tap_position(p, g.footprint_axis[pixel.index], k, taps);
    e.position_x[i] = q.x;
    e.position_y[i] = q.y;
    e.position_z[i] = q.z;
    e.normal_x[i] = n.x;
    e.normal_y[i] = n.y;
    e.normal_z[i] = n.z;
    e.footprint[i] = footprint;
  }
  if (evaluated_.count == EvaluatedPixels::kCapacity) evaluate(image);
}

void TileShader::evaluate(Image& image) {
  const std::size_t n = evaluated_.count;
  const ObjectShading& object = *evaluated_.object;
  EvaluatedLanes& e = evaluated_.lanes;
  evaluated_inputs(object.surface.normal_from_world(), e, n);
  object.evaluator->sample({e.points.data(), n}, {e.footprints.data(), n},
                           {evaluated_.texels.data(), n});
  evaluated_.count = 0;
  const TextureSpec& spec = object.evaluator->spec();
  const auto channels = static_cast<std::size_t>(spec.channels.sample_count());
  for (std::size_t i = 0; i < n;) {
    float values[CachedBrick::kMaxChannels];
    texel_channels(spec, evaluated_.texels[i], values);
    const std::size_t taps = evaluated_.taps[i];
    SOLTEX_DCHECK(taps >= 1 && i + taps <= n);
    if (taps > 1) {
      // The taps' average: their sum, then times one tap's weight (as cached taps are).
      for (std::size_t k = 1; k < taps; ++k) {
        float more[CachedBrick::kMaxChannels];
        texel_channels(spec, evaluated_.texels[i + k], more);
        for (std::size_t c = 0; c < channels; ++c) values[c] += more[c];
      }
      const float weight = tap_weight(static_cast<int>(taps));
      for (std::size_t c = 0; c < channels; ++c) values[c] *= weight;
    }
    shade_values(evaluated_.pixels[i], object.material, values, image);
    i += taps;
  }
}

void TileShader::shade_cached(const GBuffer& g, Pixel pixel, const ObjectShading& object,
                              TextureSampler& sampler, Image& image) {
  const RenderOptions& options = frame_.options;
  if (const int n = tap_count_at(g, pixel.index); n > 1) {
    const TapsResult taps = tapped_lookup(g, pixel.index, n, object, sampler);
    if (options.misses_only) return;
    if (options.false_colour_levels) {
      const glm::vec3 colour = level_colour(taps.coarsest);
      image.set(pixel.x, pixel.y, colour.r, colour.g, colour.b);
      return;
    }
    shade_values(pixel, object.material, taps.average.data(), image);
    return;
  }
  const double lod = lod_of(object, sampler, g.footprint[pixel.index]);
  const glm::dvec3 p = lookup_point(g, pixel.index, object, lod);
  if (object.rgb_fast_path) {
    add_cached(pixel, p, static_cast<int>(lod), object, sampler, image);
    return;
  }
  if (options.misses_only) {
    count_lookup(sampler.find_misses(p, lod, options.filter, &missed_));
    return;
  }
  const SampleResult result = sampler.sample(p, lod, options.filter, &missed_);
  count_lookup(result);
  if (options.false_colour_levels) {
    const glm::vec3 colour = level_colour(result.level);
    image.set(pixel.x, pixel.y, colour.r, colour.g, colour.b);
    return;
  }
  shade_values(pixel, object.material, result.values.data(), image);
}

void TileShader::count_lookup(const SampleResult& result, uint32_t pixels) {
  if (pixels == 0) return;
  for (const BrickKey& key : missed_.view()) misses_.add(key, pixels);
  if (!result.complete) counts_.fallback += pixels;
  if (result.level < 0) counts_.empty += pixels;
}

void TileShader::find_run_misses(const GBuffer& g, std::size_t first, std::size_t count,
                                 const RowLevels& row, const ObjectShading& object,
                                 TextureSampler& sampler) {
  const SampleFilter filter = frame_.options.filter;
  SampleResult result{};
  int level = -1;
  glm::ivec3 brick{0};
  uint32_t pixels = 0;  // the pixels that miss what the last lookup missed
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = first + k;
    const int l = row.levels[k];
    if (const int n = row.taps[k]; n > 1) {
      // The pixel counted once, each brick its taps miss once for it: the run so far is
      // tallied, and the taps go on from its lookup (missed_ holds what `result` missed).
      count_lookup(result, pixels);
      pixels = 0;
      begin_tapped_lookups(n);
      const glm::dvec3 p = lookup_point(g, i, object, static_cast<double>(l));
      bool incomplete = false, found = false;
      for (int t = 0; t < n; ++t) {
        const glm::dvec3 q = tap_position(p, g.footprint_axis[i], t, n);
        const glm::ivec3 b = sampler.brick_of(q, l);
        if (l != level || b != brick) {
          result = sampler.find_misses(q, static_cast<double>(l), filter, &missed_);
          level = l;
          brick = b;
        }
        count_tap_misses(pixel_tap_misses_);
        incomplete |= !result.complete;
        found |= result.level >= 0;
      }
      count_tapped_result(incomplete, found);
      continue;
    }
    const glm::dvec3 p = lookup_point(g, i, object, static_cast<double>(l));
    const glm::ivec3 b = sampler.brick_of(p, l);
    if (l == level && b == brick) {
      ++pixels;
      continue;
    }
    count_lookup(result, pixels);
    result = sampler.find_misses(p, static_cast<double>(l), filter, &missed_);
    level = l;
    brick = b;
    pixels = 1;
  }
  count_lookup(result, pixels);
}

void TileShader::look_up(int level, Image& image) {
  const auto l = static_cast<std::size_t>(level);
  CachedPixels::Group& group = cached_.groups[l];
  const std::size_t n = group.count;
  group.count = 0;
  cached_.pending &= ~(1u << l);
  const ObjectShading& object = *cached_.object;
  TextureSampler& sampler = *cached_.sampler;
  const SampleFilter filter = frame_.options.filter;
  sampler.sample({group.points.data(), n}, static_cast<double>(level), filter,
                 {cached_.results.data(), n});
  // shade_values() for each pixel, inline: the fast path's material is lit, so every pixel
  // joins the lit batch; the batch's count stays in a register (a store of a pixel's int lane
  // may alias it in memory) and is written back before a flush reads it.
  const MaterialInputs& m = object.material;
  SOLTEX_DCHECK(!m.unlit && m.colour_only());  // three channels: the colour alone
  int lit = lit_.batch.count;
  const bool by_tile = by_tile_;
  std::size_t tap_points = 0;  // counted as pixels by finish_taps()
  for (std::size_t i = 0; i < n; ++i) {
    const SampleResult* result = &cached_.results[i];
    const uint32_t slot = group.slots[i];
    SampleResult again;
    if (!result->complete) {
      // A miss (rare once warm): the single lookup again, for the bricks it names.
      again = sampler.sample_after_miss(group.points[i], level, filter, &missed_);
      if ((slot & kTapSlot) == 0) {
        for (const BrickKey& key : missed_.view()) misses_.add(key);
        if (!again.complete) ++counts_.fallback;
        if (again.level < 0) ++counts_.empty;
      } else {
        // A pixel's taps come one after another (add_taps() pushes them together).
        tile_tap_misses_.begin(slot & ~kTapSlot);
        count_tap_misses(tile_tap_misses_);
      }
      result = &again;
    }
    if (by_tile) {
      if ((slot & kTapSlot) != 0) {
        const uint32_t s = slot & ~kTapSlot;
        const float* v = result->values.data();
        taps_.sum[s] += glm::vec3(v[0], v[1], v[2]);
        taps_.incomplete[s] |= result->complete ? 0 : 1;
        taps_.found[s] |= result->level >= 0 ? 1 : 0;
        ++tap_points;
        continue;
      }
      // The rest of the pixel's inputs came with it (add_shared()).
      tile_.add_albedo(slot, result->values.data());
      continue;
    }
    const glm::ivec2 at = list_[slot];
    lit_.add(lit, at.x, at.y, gbuffer_->index(at.x - list_origin_x_, at.y - list_origin_y_),
             m.read(result->values.data()), m.shininess);
    if (++lit == ShadeBatch::kCapacity) {
      lit_.batch.count = lit;
      flush(image);
      lit = 0;
    }
  }
  lit_.batch.count = lit;
  counts_.shaded += n - tap_points;
}

void TileShader::look_up_all(Image& image) {
  while (cached_.pending != 0) look_up(std::countr_zero(cached_.pending), image);
}

void TileShader::shade_values(Pixel pixel, const MaterialInputs& m, const float* values,
                              Image& image) {
  const SurfaceInputs surface = m.read(values);
  if (m.unlit) {
    set_pixel(image, pixel.x, pixel.y, surface.albedo, surface.opacity);
    return;
  }
  ++counts_.shaded;
  if (by_tile_) {
    tile_.add(tile_.slot(pixel.x, pixel.y), surface, m.shininess);
    return;
  }
  lit_.add(lit_.batch.count++, pixel.x, pixel.y, pixel.index, surface, m.shininess);
  if (lit_.batch.count == ShadeBatch::kCapacity) flush(image);
}

void TileShader::flush(Image& image) {
  frame_.unprojection.fill(*gbuffer_, lit_);
  shade_batch(frame_.lights, lit_.batch);
  lit_.write(image);
  lit_.batch.count = 0;
}

}  // namespace soltex::render
