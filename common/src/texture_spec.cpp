#include "soltex/common/texture_spec.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "soltex/common/overloaded.h"
#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

std::string format_range(double lo, double hi) {
  return "[" + spec_number_text(lo) + ", " + spec_number_text(hi) + "]";
}

// Field paths are built as "marble.turbulence.scale" so a message points at the exact spot.
class FieldChecker {
 public:
  explicit FieldChecker(std::string prefix) : prefix_(std::move(prefix)) {}

  void in_range(const char* field, double v, double lo, double hi) const {
    if (!std::isfinite(v) || v < lo || v > hi) {
      throw SpecError(path(field), spec_number_text(v),
                      "must be finite and in " + format_range(lo, hi));
    }
  }
  // A float field (ramp keys), shown as the float it holds.
  void in_range(const char* field, float v, float lo, float hi) const {
    if (!std::isfinite(v) || v < lo || v > hi) {
      throw SpecError(
          path(field), spec_number_text(v),
          "must be finite and in [" + spec_number_text(lo) + ", " + spec_number_text(hi) + "]");
    }
  }
  void length(const char* field, double v) const {
    in_range(field, v, SpecLimits::kMinLength, SpecLimits::kMaxLength);
  }
  void frequency(const char* field, double v) const {
    in_range(field, v, SpecLimits::kMinFrequency, SpecLimits::kMaxFrequency);
  }
  void offset(const char* field, double v) const {
    in_range(field, v, -SpecLimits::kMaxOffset, SpecLimits::kMaxOffset);
  }
  void angle(const char* field, double v) const {
    in_range(field, v, -SpecLimits::kMaxAngle, SpecLimits::kMaxAngle);
  }
  std::string path(const char* field) const { return prefix_ + "." + field; }
  FieldChecker nested(const char* field) const { return FieldChecker(path(field)); }

 private:
  std::string prefix_;
};

void check_fractal(const FieldChecker& check, const FractalParams& f) {
  check.frequency("scale", f.scale);
  if (f.octave_max < 0 || f.octave_max > SpecLimits::kMaxOctave) {
    throw SpecError(check.path("octave_max"), std::to_string(f.octave_max),
                    "must be in [0, " + std::to_string(SpecLimits::kMaxOctave) + "]");
  }
  if (f.octave_min < 0 || f.octave_min > f.octave_max) {
    throw SpecError(check.path("octave_min"), std::to_string(f.octave_min),
                    "must be in [0, octave_max = " + std::to_string(f.octave_max) + "]");
  }
  if (f.octave_max - f.octave_min + 1 > SpecLimits::kMaxOctaveCount) {
    throw SpecError(check.path("octave_max"), std::to_string(f.octave_max),
                    "at most " + std::to_string(SpecLimits::kMaxOctaveCount) +
                        " octaves: octave_max - octave_min must be < " +
                        std::to_string(SpecLimits::kMaxOctaveCount));
  }
  // The largest frequency must stay where the lattice split is meaningful.
  check.in_range("scale * 2^octave_max", std::ldexp(f.scale, f.octave_max), 0.0,
                 SpecLimits::kMaxFrequency * 1024.0);
  // A field that would change nothing is refused rather than ignored: the texture's id, and
  // so its bricks, would differ from the same texture's without it.
  if (f.signed_octaves && f.basis != NoiseBasis::gradient) {
    throw SpecError(check.path("signed_octaves"), "true",
                    "applies to the gradient basis only: value noise octaves are never folded");
  }
}

void check_pattern(const Pattern& pattern) {
  const FieldChecker check(pattern_name(pattern));
  std::visit(
      Overloaded{
          [&](const StripesParams& p) {
            check.length("width", p.width);
            check.offset("offset", p.offset);
          },
          [&](const CheckerParams& p) {
            check.length("size.x", p.size.x);
            check.length("size.y", p.size.y);
            check.length("size.z", p.size.z);
            check.offset("offset", p.offset);
          },
          [&](const ColourCubeParams& p) { check.length("period", p.period); },
          [&](const RingsParams& p) {
            check.length("thickness", p.thickness);
            check.offset("base", p.base);
            check.offset("amplitude", p.amplitude);
          },
          [&](const WoodParams& p) {
            check.length("ring_spacing", p.ring_spacing);
            check.angle("tilt_y", p.tilt_y);
            check.angle("tilt_z", p.tilt_z);
            check.angle("twist", p.twist);
            check.in_range("jitter", p.jitter, 0.0, 100.0);
            check.frequency("jitter_scale", p.jitter_scale);
            check.in_range("grain_fraction", p.grain_fraction, 0.0, 1.0);
          },
          [&](const NoiseParams& p) { check.frequency("scale", p.scale); },
          [&](const TurbulenceParams& p) { check_fractal(check.nested("fractal"), p.fractal); },
          [&](const MarbleParams& p) {
            check.frequency("frequency", p.frequency);
            check.offset("amplitude", p.amplitude);
            check_fractal(check.nested("turbulence"), p.turbulence);
          },
      },
      pattern);
}

void check_ramp(const ColourRamp& ramp) {
  if (ramp.keys.size() > static_cast<std::size_t>(SpecLimits::kMaxRampKeys)) {
    throw SpecError("ramp.keys", std::to_string(ramp.keys.size()) + " keys",
                    "at most " + std::to_string(SpecLimits::kMaxRampKeys));
  }
  float previous = 0.0f;
  for (std::size_t i = 0; i < ramp.keys.size(); ++i) {
    const RampKey& key = ramp.keys[i];
    const std::string where = "ramp.keys[" + std::to_string(i) + "]";
    const FieldChecker check(where);
    check.in_range("position", key.position, previous, 1.0f);
    check.in_range("colour.r", key.colour.r, 0.0f, 1.0f);
    check.in_range("colour.g", key.colour.g, 0.0f, 1.0f);
    check.in_range("colour.b", key.colour.b, 0.0f, 1.0f);
    previous = key.position;
  }
}

void check_scalar_range(const char* name, const ScalarRange& range) {
  const FieldChecker check(name);
  check.in_range("low", range.low, 0.0f, 1.0f);
  check.in_range("high", range.high, 0.0f, 1.0f);
}

// A graph gives each channel from an output of its own, so each wanted channel needs one.
void check_graph_channels(const GraphField& graph, const TextureSpec& spec) {
  if (!spec.ramp.keys.empty()) {
    throw SpecError("ramp.keys", std::to_string(spec.ramp.keys.size()) + " keys",
                    "must be empty for a graph: graphs colour through ramp nodes");
  }
  const struct {
    bool wanted, present;
    const char* name;
  } channels[] = {{spec.channels.colour, graph.has_colour(), "colour"},
                  {spec.channels.opacity, graph.has_opacity(), "opacity"},
                  {spec.channels.specular, graph.has_specular(), "specular"}};
  for (const auto& c : channels) {
    if (c.wanted && !c.present) {
      throw SpecError(std::string("graph.outputs.") + c.name, "absent",
                      std::string("the spec asks for the ") + c.name +
                          " channel, so the graph needs an output for it");
    }
  }
}

}  // namespace

const char* pattern_name(const Pattern& pattern) {
  static constexpr const char* kNames[] = {"stripes", "checker", "colour_cube", "rings",
                                           "wood",    "noise",   "turbulence",  "marble"};
  static_assert(std::size(kNames) == std::variant_size_v<Pattern>);
  return kNames[pattern.index()];
}

const char* texture_kind_name(const TextureSpec& spec) {
  return spec.graph ? "graph" : pattern_name(spec.pattern);
}

ColourRamp default_ramp(const Pattern& pattern) {
  const glm::vec3 yellow{1.0f, 0.85f, 0.1f}, red{0.8f, 0.1f, 0.05f};
  return std::visit(
      Overloaded{
          [&](const StripesParams&) {
            return ColourRamp{{{0.0f, yellow}, {1.0f, red}}};
          },
          [&](const CheckerParams&) {
            return ColourRamp{{{0.0f, yellow}, {1.0f, red}}};
          },
          [&](const ColourCubeParams&) {
            return ColourRamp{{{0.0f, glm::vec3(0.0f)}, {1.0f, glm::vec3(1.0f)}}};
          },
          [&](const RingsParams&) {
            return ColourRamp{{{0.0f, yellow}, {1.0f, red}}};
          },
          [&](const WoodParams&) {
            return ColourRamp{{{0.0f, {0.78f, 0.56f, 0.32f}}, {1.0f, {0.40f, 0.22f, 0.09f}}}};
          },
          [&](const NoiseParams&) {
            return ColourRamp{{{0.0f, glm::vec3(0.0f)}, {1.0f, glm::vec3(1.0f)}}};
          },
          [&](const TurbulenceParams&) {
            return ColourRamp{{{0.0f, {0.05f, 0.05f, 0.2f}},
                               {0.5f, {0.9f, 0.5f, 0.1f}},
                               {1.0f, {1.0f, 1.0f, 0.8f}}}};
          },
          [&](const MarbleParams&) {
            return ColourRamp{{{0.0f, {0.25f, 0.25f, 0.3f}},
                               {0.25f, {0.6f, 0.6f, 0.65f}},
                               {0.5f, {0.92f, 0.92f, 0.9f}},
                               {1.0f, {0.98f, 0.97f, 0.95f}}}};
          },
      },
      pattern);
}

TextureSpec validated(TextureSpec spec) {
  if (!spec.graph) check_pattern(spec.pattern);
  check_ramp(spec.ramp);
  check_scalar_range("opacity", spec.opacity);
  check_scalar_range("specular", spec.specular);
  if (spec.channels.sample_count() == 0) {
    throw SpecError("channels", "none", "at least one channel must be requested");
  }
  if (spec.graph) {
    check_graph_channels(*spec.graph, spec);
    return spec;
  }
  if (spec.ramp.keys.empty()) spec.ramp = default_ramp(spec.pattern);
  return spec;
}

Volume validated(Volume volume) {
  const char* axes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const FieldChecker check("volume");
    const double lo = volume.min[a], hi = volume.max[a];
    check.in_range((std::string("min.") + axes[a]).c_str(), lo, -SpecLimits::kMaxVolumeCoordinate,
                   SpecLimits::kMaxVolumeCoordinate);
    check.in_range((std::string("max.") + axes[a]).c_str(), hi, -SpecLimits::kMaxVolumeCoordinate,
                   SpecLimits::kMaxVolumeCoordinate);
    if (!(hi > lo)) {
      throw SpecError(
          std::string("volume.max.") + axes[a], spec_number_text(hi),
          "must be greater than volume.min." + std::string(axes[a]) + " = " + spec_number_text(lo));
    }
  }
  if (volume.finest_level_log2 < 0 || volume.finest_level_log2 > SpecLimits::kMaxFinestLevelLog2) {
    throw SpecError("volume.finest_level_log2", std::to_string(volume.finest_level_log2),
                    "must be in [0, " + std::to_string(SpecLimits::kMaxFinestLevelLog2) + "]");
  }
  return volume;
}

}  // namespace soltex
