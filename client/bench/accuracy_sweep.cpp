#include "accuracy_sweep.h"

#include <algorithm>
#include <optional>

#include "octave_cap.h"

namespace soltex::bench {
namespace {

constexpr int kLevels[] = {6, 7, 8, 9};
constexpr SampleFilter kFilters[] = {SampleFilter::nearest, SampleFilter::trilinear,
                                     SampleFilter::quadrilinear};
constexpr MipMode kMipModes[] = {MipMode::point, MipMode::band_limited, MipMode::supersampled};
constexpr int kOctaveCaps[] = {2, 4, 6};
// Beside the default (automatic): every texture cached, every texture evaluated per pixel.
constexpr TextureAccess kAccesses[] = {TextureAccess::cached, TextureAccess::evaluated};
// Sub-pixels per axis beside the default 1.
constexpr int kAntialias[] = {2, 4};
// Anisotropic taps at most beside the default 8: one lookup per pixel, and 4.
constexpr int kAnisotropy[] = {1, 4};
constexpr CodecChoice kCodecs[] = {
    {Codec::raw, 0}, {Codec::lz4, 0}, {Codec::zstd, 1}, {Codec::zstd, 3}};

void add_once(std::vector<AccuracySetting>& sweep, const AccuracySetting& setting) {
  if (std::find(sweep.begin(), sweep.end(), setting) == sweep.end()) sweep.push_back(setting);
}

}  // namespace

std::vector<AccuracySetting> accuracy_sweep(const Scene& scene, bool quick) {
  const AccuracySetting base;
  const std::optional<int> scene_octaves = max_fractal_octave(scene);
  std::vector<AccuracySetting> sweep{base};
  const auto vary = [&](auto change) {
    AccuracySetting setting = base;
    change(setting);
    add_once(sweep, setting);
  };
  if (quick) {
    vary([](AccuracySetting& s) { s.finest_level = 6; });
    vary([](AccuracySetting& s) { s.filter = SampleFilter::nearest; });
    vary([](AccuracySetting& s) { s.codec = {Codec::lz4, 0}; });
    if (scene_octaves && *scene_octaves > 2) vary([](AccuracySetting& s) { s.octave_cap = 2; });
    for (TextureAccess access : kAccesses) vary([&](AccuracySetting& s) { s.access = access; });
    vary([](AccuracySetting& s) { s.antialias = 2; });
    vary([](AccuracySetting& s) { s.anisotropy = 1; });
    return sweep;
  }
  for (int level : kLevels) vary([&](AccuracySetting& s) { s.finest_level = level; });
  vary([](AccuracySetting& s) { s.brick_size = 8; });
  for (SampleFilter filter : kFilters) vary([&](AccuracySetting& s) { s.filter = filter; });
  for (MipMode mip : kMipModes) vary([&](AccuracySetting& s) { s.mip = mip; });
  for (int cap : kOctaveCaps) {
    if (scene_octaves && cap < *scene_octaves)
      vary([&](AccuracySetting& s) { s.octave_cap = cap; });
  }
  for (const CodecChoice& codec : kCodecs) vary([&](AccuracySetting& s) { s.codec = codec; });
  for (TextureAccess access : kAccesses) vary([&](AccuracySetting& s) { s.access = access; });
  for (int k : kAntialias) vary([&](AccuracySetting& s) { s.antialias = k; });
  for (int n : kAnisotropy) vary([&](AccuracySetting& s) { s.anisotropy = n; });
  for (int level : kLevels) {
    for (SampleFilter filter : kFilters) {
      vary([&](AccuracySetting& s) {
        s.finest_level = level;
        s.filter = filter;
      });
    }
  }
  return sweep;
}

}  // namespace soltex::bench
