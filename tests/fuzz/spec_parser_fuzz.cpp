// libFuzzer target for the texture protocol. The input is parsed as a v1::TextureSpec, a
// v1::Volume and a v1::RegisterTextureRequest in turn; each either fails to parse, is refused
// with SpecError, or is a value that is safe to use: the evaluator accepts it, every point and
// grid evaluates to finite samples in [0, 1] without a sanitizer report, sample() agrees with
// evaluate_grid() bit for bit, and the value survives a round trip through to_proto() with the
// same texture id. Requests are read the way soltexd reads them and then evaluated brick by
// brick, so what the server would accept is what gets evaluated here.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/common/texture_spec.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltex/v1/brick_service.pb.h"
#include "soltex/v1/texture.pb.h"

namespace {

namespace v1 = soltex::v1;
using soltex::BrickLayout;
using soltex::Grid;
using soltex::MipMode;
using soltex::MipSettings;
using soltex::SpecError;
using soltex::TextureEvaluator;
using soltex::TextureSpec;
using soltex::Volume;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "spec_parser_fuzz: %s\n", what);
  std::abort();
}

// Ramp interpolation and supersample averaging may land an ulp outside [0, 1].
constexpr float kSampleSlack = 1e-5f;

void check_sample_value(float value) {
  if (!std::isfinite(value) || value < -kSampleSlack || value > 1.0f + kSampleSlack) {
    std::fprintf(stderr, "spec_parser_fuzz: sample %.9g\n", static_cast<double>(value));
    fail("a sample is not finite or not in [0, 1]");
  }
}

// Points across the range a validated volume admits (coordinates up to 1e12), including
// negative, fractional and lattice-aligned ones.
constexpr double kMaxCoordinate = soltex::SpecLimits::kMaxVolumeCoordinate;
const glm::dvec3 kPoints[] = {
    {0.0, 0.0, 0.0},
    {0.5, 0.25, 0.125},
    {-0.3, 1.7, -2.9},
    {255.5, -256.0, 1024.25},
    {1e6, -1e6, 3.3e5},
    {kMaxCoordinate, -kMaxCoordinate, kMaxCoordinate},
    {-kMaxCoordinate, 3.3e11, 7e-9},
    {1e-300, -1e-300, 5e-324},
};

// The planes evaluate_grid writes for one texel, in channel order.
std::vector<float> texel_samples(const TextureSpec& spec, const soltex::Texel& texel) {
  std::vector<float> samples;
  if (spec.channels.colour) {
    samples.insert(samples.end(), {texel.colour.r, texel.colour.g, texel.colour.b});
  }
  for (const auto* range : {spec.channels.opacity ? &spec.opacity : nullptr,
                            spec.channels.specular ? &spec.specular : nullptr}) {
    if (range != nullptr) samples.push_back(range->low + (range->high - range->low) * texel.field);
  }
  return samples;
}

void check_texel(const TextureSpec& spec, const soltex::Texel& texel) {
  check_sample_value(texel.field);
  for (float value : texel_samples(spec, texel)) check_sample_value(value);
}

// Evaluates the grid and compares the points `probe` picks with sample() at the same point
// and filter width, which the evaluator promises to match bit for bit.
void check_grid(const TextureEvaluator& evaluator, const Grid& grid, double filter_width,
                std::span<const float> planes) {
  const std::size_t n = grid.size();
  for (float value : planes) check_sample_value(value);
  const auto probe = [&](int i, int j, int k) {
    const soltex::Texel texel = evaluator.sample(grid.point(i, j, k), filter_width);
    const std::vector<float> expected = texel_samples(evaluator.spec(), texel);
    const std::size_t index =
        static_cast<std::size_t>(i) +
        static_cast<std::size_t>(grid.count.x) *
            (static_cast<std::size_t>(j) +
             static_cast<std::size_t>(grid.count.y) * static_cast<std::size_t>(k));
    for (std::size_t c = 0; c < expected.size(); ++c) {
      if (planes[c * n + index] != expected[c]) {
        std::fprintf(stderr,
                     "spec_parser_fuzz: point (%d, %d, %d) channel %zu: grid %.9g, "
                     "sample() %.9g, filter width %.17g\n",
                     i, j, k, c, static_cast<double>(planes[c * n + index]),
                     static_cast<double>(expected[c]), filter_width);
        fail("evaluate_grid and sample differ");
      }
    }
  };
  const glm::ivec3 last = grid.count - 1;
  for (int corner = 0; corner < 8; ++corner) {
    probe(corner & 1 ? last.x : 0, corner & 2 ? last.y : 0, corner & 4 ? last.z : 0);
  }
  probe(last.x / 2, last.y / 2, last.z / 2);
}

std::vector<float> evaluate(const TextureEvaluator& evaluator, const Grid& grid,
                            double filter_width) {
  std::vector<float> planes(grid.size() *
                            static_cast<std::size_t>(evaluator.spec().channels.sample_count()));
  evaluator.evaluate_grid(grid, filter_width, planes);
  return planes;
}

// Points one by one, then a 3 x 2 x 2 grid at a few origins, spacings and filter widths.
void check_evaluator(const TextureEvaluator& evaluator) {
  for (const glm::dvec3& p : kPoints) {
    for (double filter_width : {0.0, 1e-3, 0.5, 1e9}) {
      check_texel(evaluator.spec(), evaluator.sample(p, filter_width));
    }
  }
  for (const glm::dvec3& origin : {kPoints[1], kPoints[4], kPoints[6]}) {
    for (double step : {1.0 / 64.0, 0.37, 1e8}) {
      Grid grid;
      grid.origin = origin;
      grid.step = glm::dvec3(step, 0.5 * step, 2.0 * step);
      grid.count = {3, 2, 2};
      grid.first = {-1, 5, 1 << 20};
      for (double filter_width : {0.0, step}) {
        check_grid(evaluator, grid, filter_width, evaluate(evaluator, grid, filter_width));
      }
    }
  }
}

// to_proto writes every field; reading it back must give the same value and the same id.
void check_round_trip(const TextureSpec& spec, const Volume& volume, int brick_size,
                      const MipSettings& mip) {
  const v1::TextureSpec spec_message = soltex::to_proto(spec);
  const v1::Volume volume_message = soltex::to_proto(volume);
  const TextureSpec spec_again = soltex::from_proto(spec_message);
  const Volume volume_again = soltex::from_proto(volume_message);
  if (soltex::to_proto(spec_again).SerializeAsString() != spec_message.SerializeAsString() ||
      soltex::to_proto(volume_again).SerializeAsString() != volume_message.SerializeAsString()) {
    fail("to_proto(from_proto(to_proto(x))) differs from to_proto(x)");
  }
  if (soltex::canonical_encoding(spec_again, volume_again, brick_size, mip) !=
      soltex::canonical_encoding(spec, volume, brick_size, mip)) {
    fail("the canonical encoding changed across a to_proto/from_proto round trip");
  }
}

void fuzz_texture_spec(const uint8_t* data, std::size_t size) {
  v1::TextureSpec message;
  if (!message.ParseFromArray(data, static_cast<int>(size))) return;
  TextureSpec spec;
  try {
    spec = soltex::from_proto(message);
  } catch (const SpecError&) {
    return;
  }
  // from_proto validated: from here on a SpecError escapes and is a finding.
  const TextureEvaluator evaluator(spec);
  check_evaluator(evaluator);
  check_round_trip(spec, Volume{}, 16, MipSettings{});
  (void)soltex::texture_id(spec, Volume{}, 16);
}

// Layout arithmetic for every level of a volume the server would accept.
void check_layout(const BrickLayout& layout) {
  for (int level = 0; level <= layout.coarsest_level(); ++level) {
    const double width = layout.filter_width(level);
    if (!(width >= 0.0) || !std::isfinite(width)) fail("a level's filter width is not finite");
    const int n = layout.bricks_per_axis(level);
    if (n < 1 || !layout.contains(level, glm::ivec3(n - 1)) || layout.contains(level, {n, 0, 0})) {
      fail("bricks_per_axis disagrees with contains");
    }
    (void)layout.sample_grid(level, glm::ivec3(n - 1));
    (void)soltex::level_of_detail(layout, width);
  }
}

void fuzz_volume(const uint8_t* data, std::size_t size) {
  v1::Volume message;
  if (!message.ParseFromArray(data, static_cast<int>(size))) return;
  Volume volume;
  try {
    volume = soltex::from_proto(message);
  } catch (const SpecError&) {
    return;
  }
  check_round_trip(soltex::validated(TextureSpec{}), volume, 8, MipSettings{});
  for (int brick_size : {soltex::kMinBrickSize, soltex::kMaxBrickSize}) {
    std::optional<BrickLayout> layout;
    try {
      layout.emplace(volume, brick_size);
    } catch (const SpecError&) {
      continue;  // fewer cells than one brick
    }
    check_layout(*layout);
  }
}

// The MIP settings as soltexd reads them (server/src/brick_service.cpp): nullopt where it
// refuses the request.
std::optional<MipSettings> mip_as_the_server_reads_it(const v1::RegisterTextureRequest& request) {
  MipSettings mip;
  switch (request.mip_mode()) {
    case v1::MIP_MODE_BAND_LIMITED:
      mip.mode = MipMode::band_limited;
      return mip;
    case v1::MIP_MODE_POINT:
      mip.mode = MipMode::point;
      return mip;
    case v1::MIP_MODE_SUPERSAMPLED:
      mip.mode = MipMode::supersampled;
      mip.supersample = request.supersample() == 0 ? 2 : static_cast<int>(request.supersample());
      // The registry refuses other factors.
      if (mip.supersample < 1 || mip.supersample > 4) return std::nullopt;
      return mip;
    default:
      return std::nullopt;
  }
}

// One brick as the server produces it: evaluated, checked and quantized.
void check_brick(const TextureEvaluator& evaluator, const BrickLayout& layout, int level,
                 const glm::ivec3& brick, const MipSettings& mip) {
  const int channels = evaluator.spec().channels.sample_count();
  std::vector<float> planes(static_cast<std::size_t>(layout.samples_per_brick()) *
                            static_cast<std::size_t>(channels));
  soltex::evaluate_brick(evaluator, layout, level, brick, mip, planes);
  const Grid grid = layout.sample_grid(level, brick);
  if (mip.mode == MipMode::supersampled) {
    for (float value : planes) check_sample_value(value);
  } else {
    const double width = mip.mode == MipMode::point ? 0.0 : layout.filter_width(level);
    check_grid(evaluator, grid, width, planes);
  }
  (void)soltex::quantize(planes);
}

void fuzz_register_request(const uint8_t* data, std::size_t size) {
  v1::RegisterTextureRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return;
  TextureSpec spec;
  Volume volume;
  try {
    spec = soltex::from_proto(request.spec());
    volume = soltex::from_proto(request.volume());
  } catch (const SpecError&) {
    return;
  }
  const int brick_size =
      request.brick_size() == 0 ? 16 : static_cast<int>(std::min(request.brick_size(), 1000u));
  const std::optional<MipSettings> mip = mip_as_the_server_reads_it(request);
  if (!mip) return;
  const uint64_t id = soltex::texture_id(spec, volume, brick_size, *mip);
  const TextureEvaluator evaluator(spec);
  std::optional<BrickLayout> layout;
  try {
    layout.emplace(volume, brick_size);
  } catch (const SpecError&) {
    return;  // the server refuses it too
  }
  check_round_trip(spec, volume, brick_size, *mip);
  if (soltex::texture_id(soltex::from_proto(soltex::to_proto(spec)),
                         soltex::from_proto(soltex::to_proto(volume)), brick_size, *mip) != id) {
    fail("the texture id changed across a to_proto/from_proto round trip");
  }
  // The coarsest brick (widest filter) and the far corner brick of the finest level (largest
  // lattice indices, smallest spacing).
  check_brick(evaluator, *layout, layout->coarsest_level(), glm::ivec3(0), *mip);
  check_brick(evaluator, *layout, 0, glm::ivec3(layout->bricks_per_axis(0) - 1), *mip);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  fuzz_texture_spec(data, size);
  fuzz_volume(data, size);
  fuzz_register_request(data, size);
  return 0;
}
