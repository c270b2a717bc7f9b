#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <variant>
#include <vector>

#include "soltex/common/graph_field.h"

// The validated C++ form of a texture: one pattern with its parameters, a colour ramp and
// the channels a client wants. Defaults are the lecture slides' values where they give one.
// Build a spec however you like, then pass it through validated(): it checks every field
// against the bounds in SpecLimits and throws SpecError naming the field, value and bound.
namespace soltex {

enum class Axis : uint8_t { x, y, z };
enum class NoiseBasis : uint8_t { value, gradient };
enum class Ripple : uint8_t { axis, product };

// sum_{k = octave_min}^{octave_max} (1/2)^k * basis(2^k * scale * p); with the gradient
// basis each octave is |noise| unless signed_octaves.
struct FractalParams {
  double scale = 4.0;
  int octave_min = 0;
  int octave_max = 5;
  NoiseBasis basis = NoiseBasis::value;
  bool signed_octaves = false;
};

struct StripesParams {
  double width = 1.0;
  double offset = 0.0;
  Axis axis = Axis::x;
};

struct CheckerParams {
  glm::dvec3 size{1.0, 1.0, 1.0};
  double offset = 0.0;
  bool three_d = false;
};

struct ColourCubeParams {
  double period = 1.0;
};

// t = base + amplitude * (floor(r / thickness) mod 2), r = sqrt(x^2 + y^2).
struct RingsParams {
  double thickness = 0.1;
  double base = 0.0;
  double amplitude = 1.0;
};

struct WoodParams {
  double ring_spacing = 0.1;
  double tilt_y = 0.3;
  double tilt_z = 0.15;
  double twist = 0.5;
  double jitter = 0.6;
  double jitter_scale = 4.0;
  double grain_fraction = 0.2;
};

struct NoiseParams {
  double scale = 4.0;
  NoiseBasis basis = NoiseBasis::value;
};

struct TurbulenceParams {
  FractalParams fractal;
};

struct MarbleParams {
  double frequency = 2.0;
  double amplitude = 4.0;
  Ripple ripple = Ripple::axis;
  Axis axis = Axis::x;
  FractalParams turbulence;
};

using Pattern = std::variant<StripesParams, CheckerParams, ColourCubeParams, RingsParams,
                             WoodParams, NoiseParams, TurbulenceParams, MarbleParams>;

// Stable lower-case names ("stripes", "checker", ...), used in messages and file names.
const char* pattern_name(const Pattern& pattern);

struct TextureSpec;
// What a spec is, in messages: "graph" for a graph, else its pattern's name.
const char* texture_kind_name(const TextureSpec& spec);

struct RampKey {
  float position = 0.0f;
  glm::vec3 colour{0.0f};
};

// Piecewise-linear map from the scalar field t in [0, 1] to colour; constant beyond the end
// keys. An empty ramp in a spec means "the pattern's default ramp".
// Inline, so that the pattern kernels compile it for the CPU's target along with the fields.
struct ColourRamp {
  std::vector<RampKey> keys;

  glm::vec3 at(float t) const noexcept {
    if (keys.empty()) return glm::vec3(std::clamp(std::isnan(t) ? 0.0f : t, 0.0f, 1.0f));
    if (!(t > keys.front().position)) return keys.front().colour;  // also NaN
    // Keys are hit exactly: a two-colour pattern gives its two colours, not a rounding of them.
    for (std::size_t i = 1; i < keys.size(); ++i) {
      const RampKey& hi = keys[i];
      if (t == hi.position) return hi.colour;
      if (t < hi.position) {
        const RampKey& lo = keys[i - 1];
        const float u = (t - lo.position) / (hi.position - lo.position);
        return lo.colour + u * (hi.colour - lo.colour);
      }
    }
    return keys.back().colour;
  }

  // The ramp averaged over a field spread evenly across [t - spread, t + spread]: the colour of
  // a box over which the field varies, where at(t) would colour only the field's mean. A
  // nonlinear ramp makes the two differ: marble finer than a box is not the ramp's mid colour.
  // spread <= 0 (or NaN) is at(t).
  glm::vec3 average(float t, float spread) const noexcept {
    if (!(spread > 0.0f) || std::isnan(t)) return at(t);
    const RampBox box(t, spread);
    if (keys.empty()) return glm::vec3(box.step_share(0.0f, 1.0f, 1.0f));
    if (t - spread >= keys.back().position) return keys.back().colour;
    glm::vec3 colour = keys.front().colour;
    for (std::size_t i = 1; i < keys.size(); ++i) {
      const RampKey& lo = keys[i - 1];
      const RampKey& hi = keys[i];
      const float length = hi.position - lo.position;
      colour += (hi.colour - lo.colour) * box.step_share(lo.position, length, 1.0f / length);
    }
    return unit_clamped(colour);
  }

  // The steps' changes, summed in float, can miss the colours' range by an ulp; the average of
  // colours in [0, 1] is in it. (A comparison for each bound, as the lanes make them.)
  static glm::vec3 unit_clamped(glm::vec3 c) noexcept {
    for (int i = 0; i < 3; ++i) c[i] = c[i] < 0.0f ? 0.0f : (1.0f < c[i] ? 1.0f : c[i]);
    return c;
  }

  // The box average() takes, and the share of one key step (a linear rise from 0 at `start` to
  // 1 over `length`, a jump if the length is 0) that it averages to. That is the integral of
  // the box's and the rise's convolution, a trapezoid of width 2 spread + length with sides as
  // wide as the narrower of the two: quadratic on the sides, linear between, divided only by
  // reciprocals (of the box, once per box, and of the length, once per key), so a length of 0
  // is never a divisor that is reached. RampStepShareLanes repeats it operation for operation.
  struct RampBox {
    float t, spread, width, inverse_width;
    RampBox(float t_, float spread_)
        : t(t_), spread(spread_), width(2.0f * spread_), inverse_width(1.0f / width) {}

    float step_share(float start, float length, float inverse_length) const noexcept {
      const bool length_narrower = length < width;
      const float narrow = length_narrower ? length : width;
      const float wide = length_narrower ? width : length;
      const float inverse_wide = length_narrower ? inverse_width : inverse_length;
      const float whole = narrow + wide;
      const float e = (t - start) + spread;  // from where the trapezoid begins
      if (!(e > 0.0f)) return 0.0f;
      if (!(e < whole)) return 1.0f;
      // 1 / (2 narrow wide), and narrow * wide is width * length either way.
      const float inverse_curve = 0.5f * inverse_width * inverse_length;
      if (e < narrow) return e * e * inverse_curve;
      if (e > wide) {
        const float rest = whole - e;
        return 1.0f - rest * rest * inverse_curve;
      }
      return (e - 0.5f * narrow) * inverse_wide;
    }
  };
};

ColourRamp default_ramp(const Pattern& pattern);

enum class Channel : uint8_t { colour, opacity, specular };

// Which channels a brick carries, in this fixed order: R, G, B (colour), opacity, specular.
struct ChannelSet {
  bool colour = true;
  bool opacity = false;
  bool specular = false;

  int sample_count() const { return (colour ? 3 : 0) + (opacity ? 1 : 0) + (specular ? 1 : 0); }
  bool operator==(const ChannelSet&) const = default;
};

struct ScalarRange {
  float low = 0.0f;
  float high = 1.0f;
};

struct TextureSpec {
  Pattern pattern;
  // When set, the texture is this node graph (compiled and validated by
  // soltex::graph::compile()) and `pattern` is unused: the graph's outputs give the channels
  // and the ramp must be empty (graphs colour through ramp nodes). Kept beside the pattern
  // rather than in the variant so that Pattern stays trivially copyable.
  std::shared_ptr<const GraphField> graph;
  ColourRamp ramp;
  ChannelSet channels;
  ScalarRange opacity;
  ScalarRange specular;
};

// The cache cube: a box in texture space, 2^finest_level_log2 cells per axis at level 0.
struct Volume {
  glm::dvec3 min{0.0};
  glm::dvec3 max{1.0};
  int finest_level_log2 = 8;
};

// Every bound a spec or volume must keep. Sizes and scales are bounded so that a request
// cannot ask for unbounded work or for values whose products overflow.
struct SpecLimits {
  static constexpr double kMinLength = 1e-6;  // widths, sizes, periods, spacings
  static constexpr double kMaxLength = 1e6;
  static constexpr double kMaxOffset = 1e6;      // offsets, amplitudes, ring base
  static constexpr double kMinFrequency = 1e-6;  // scales and frequencies
  static constexpr double kMaxFrequency = 1e4;
  static constexpr double kMaxAngle = 1e3;    // radians, and radians per unit of twist
  static constexpr int kMaxOctave = 24;       // octave_max; 2^24 * scale stays exact
  static constexpr int kMaxOctaveCount = 16;  // octave_max - octave_min + 1
  static constexpr int kMaxRampKeys = 16;
  static constexpr int kMaxFinestLevelLog2 = 14;  // 16384 cells per axis
  static constexpr double kMaxVolumeCoordinate = 1e12;
};

// Checks every field and returns the spec with defaults filled in (the pattern's default
// ramp when the ramp is empty). Throws SpecError on the first violation.
TextureSpec validated(TextureSpec spec);
Volume validated(Volume volume);

}  // namespace soltex
