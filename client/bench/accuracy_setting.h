#pragma once

#include <optional>
#include <string>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/render/frame_renderer.h"

namespace soltex::bench {

// A brick codec as soltexd can be configured: the codec and, for zstd, its level. The 3D
// predictor is on for the compressing codecs and off for raw, as soltexd runs it. The default
// is soltexd's (its --zstd-level).
struct CodecChoice {
  Codec codec = Codec::zstd;
  int zstd_level = 1;

  std::string name() const;  // "raw", "lz4", "zstd-1", "zstd-3"
  CodecOptions options() const;
  bool operator==(const CodecChoice&) const = default;
};

// One point of the accuracy sweep: every knob that changes what a frame costs or how close it
// comes to the reference.
struct AccuracySetting {
  int finest_level = 8;  // log2 of the cells per axis at level 0
  int brick_size = 16;
  SampleFilter filter = SampleFilter::trilinear;
  MipMode mip = MipMode::band_limited;
  std::optional<int> octave_cap;  // fractal octave_max capped to this; empty: the scene's own
  CodecChoice codec;
  // Per texture: cached lookups, per-pixel evaluation, or the renderer's rule per pattern kind.
  TextureAccess access = TextureAccess::automatic;
  int antialias = 1;  // sub-pixels per axis for silhouettes and clip edges
  // Taps at most along a grazing footprint's long side (1: one lookup per pixel).
  int anisotropy = RenderOptions{}.anisotropy;

  // The knobs that differ from the default, e.g. "level=7 filter=nearest"; "default" for it.
  std::string label() const;
  // The codec is the only knob that leaves the frame alone: the cache holds decoded bricks,
  // so two settings that differ in it alone draw the same frame from the same cache. (Access
  // changes the frame: an evaluated texture is not read from bricks.)
  bool same_frame_as(const AccuracySetting& other) const;
  bool operator==(const AccuracySetting&) const = default;
};

// "scene" for the scene's own octaves, the cap otherwise.
std::string octaves_name(const std::optional<int>& octave_cap);

}  // namespace soltex::bench
