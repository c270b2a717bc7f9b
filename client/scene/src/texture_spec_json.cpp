#include "soltex/scene/texture_spec_json.h"

#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "graph_json.h"
#include "json_reader.h"
#include "soltex/common/overloaded.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/text_file.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/materialx/materialx_reader.h"
#include "soltex/scene/scene_error.h"

namespace soltex {
namespace {

using nlohmann::json;

// Numbers are read as any finite value here; validated() then applies the documented bound
// and names it, so each bound has one home.
constexpr double kAnyLow = std::numeric_limits<double>::lowest();
constexpr double kAnyHigh = std::numeric_limits<double>::max();
constexpr int kAnyIntLow = std::numeric_limits<int>::min();
constexpr int kAnyIntHigh = std::numeric_limits<int>::max();

constexpr const char* kPatternNames[] = {"stripes", "checker",    "colour_cube", "rings", "wood",
                                         "noise",   "turbulence", "marble",      "graph"};
constexpr std::size_t kGraphChoice = 8;
constexpr std::size_t kMaterialxChoice = 9;

// {"path": "granite.mtlx", "nodegraph": "granite", "output": "out"}; the path is relative to the
// scene file's folder.
std::shared_ptr<const GraphField> read_materialx(const JsonValue& value) {
  JsonObject object(value);
  materialx::MaterialxSource source;
  const JsonValue path = object.get("path");
  const std::filesystem::path relative(path.string());
  const std::filesystem::path resolved =
      relative.is_absolute() ? relative
                             : std::filesystem::path(value.file()).parent_path() / relative;
  source.document = resolved.string();
  source.nodegraph = object.get("nodegraph").string();
  source.output = object.get("output").string();
  object.reject_unknown_keys();
  try {
    source.text = read_text_file(source.document, "MaterialX");
  } catch (const std::runtime_error& error) {
    path.fail(error.what());
  }
  try {
    return materialx::compile_nodegraph(source);
  } catch (const materialx::MaterialxError& error) {
    value.fail(error.what());
  }
}

Axis read_axis(JsonObject& object, Axis fallback) {
  const auto found = object.find("axis");
  return found ? found->choice<Axis>({{"x", Axis::x}, {"y", Axis::y}, {"z", Axis::z}}) : fallback;
}

NoiseBasis read_basis(JsonObject& object, NoiseBasis fallback) {
  const auto found = object.find("basis");
  return found ? found->choice<NoiseBasis>(
                     {{"value", NoiseBasis::value}, {"gradient", NoiseBasis::gradient}})
               : fallback;
}

// An octave number: any int goes on to validated(), which names the bound; one past an int's
// range cannot be carried there, and is refused here with that same bound.
int read_octave(JsonObject& object, const char* key, int fallback) {
  const std::optional<JsonValue> found = object.find(key);
  if (!found) return fallback;
  const double value = found->number(kAnyLow, kAnyHigh);
  if (value < kAnyIntLow || value > kAnyIntHigh) {
    found->fail(format_number(value) + " is out of range: must be in [0, " +
                std::to_string(SpecLimits::kMaxOctave) + "]");
  }
  return found->integer(kAnyIntLow, kAnyIntHigh);
}

FractalParams read_fractal(const std::optional<JsonValue>& value) {
  FractalParams f;
  if (!value) return f;
  JsonObject object(*value);
  f.scale = object.number("scale", f.scale, kAnyLow, kAnyHigh);
  f.octave_min = read_octave(object, "octave_min", f.octave_min);
  f.octave_max = read_octave(object, "octave_max", f.octave_max);
  f.basis = read_basis(object, f.basis);
  f.signed_octaves = object.boolean("signed_octaves", f.signed_octaves);
  object.reject_unknown_keys();
  return f;
}

Pattern read_pattern(std::size_t which, JsonObject object) {
  switch (which) {
    case 0: {
      StripesParams p;
      p.width = object.number("width", p.width, kAnyLow, kAnyHigh);
      p.offset = object.number("offset", p.offset, kAnyLow, kAnyHigh);
      p.axis = read_axis(object, p.axis);
      object.reject_unknown_keys();
      return p;
    }
    case 1: {
      CheckerParams p;
      p.size = object.vec3("size", p.size, kAnyLow, kAnyHigh);
      p.offset = object.number("offset", p.offset, kAnyLow, kAnyHigh);
      p.three_d = object.boolean("three_d", p.three_d);
      object.reject_unknown_keys();
      return p;
    }
    case 2: {
      ColourCubeParams p;
      p.period = object.number("period", p.period, kAnyLow, kAnyHigh);
      object.reject_unknown_keys();
      return p;
    }
    case 3: {
      RingsParams p;
      p.thickness = object.number("thickness", p.thickness, kAnyLow, kAnyHigh);
      p.base = object.number("base", p.base, kAnyLow, kAnyHigh);
      p.amplitude = object.number("amplitude", p.amplitude, kAnyLow, kAnyHigh);
      object.reject_unknown_keys();
      return p;
    }
    case 4: {
      WoodParams p;
      p.ring_spacing = object.number("ring_spacing", p.ring_spacing, kAnyLow, kAnyHigh);
      p.tilt_y = object.number("tilt_y", p.tilt_y, kAnyLow, kAnyHigh);
      p.tilt_z = object.number("tilt_z", p.tilt_z, kAnyLow, kAnyHigh);
      p.twist = object.number("twist", p.twist, kAnyLow, kAnyHigh);
      p.jitter = object.number("jitter", p.jitter, kAnyLow, kAnyHigh);
      p.jitter_scale = object.number("jitter_scale", p.jitter_scale, kAnyLow, kAnyHigh);
      p.grain_fraction = object.number("grain_fraction", p.grain_fraction, kAnyLow, kAnyHigh);
      object.reject_unknown_keys();
      return p;
    }
    case 5: {
      NoiseParams p;
      p.scale = object.number("scale", p.scale, kAnyLow, kAnyHigh);
      p.basis = read_basis(object, p.basis);
      object.reject_unknown_keys();
      return p;
    }
    case 6: {
      TurbulenceParams p;
      p.fractal = read_fractal(object.find("fractal"));
      object.reject_unknown_keys();
      return p;
    }
    default: {
      MarbleParams p;
      p.frequency = object.number("frequency", p.frequency, kAnyLow, kAnyHigh);
      p.amplitude = object.number("amplitude", p.amplitude, kAnyLow, kAnyHigh);
      if (const auto ripple = object.find("ripple")) {
        p.ripple = ripple->choice<Ripple>({{"axis", Ripple::axis}, {"product", Ripple::product}});
      }
      p.axis = read_axis(object, p.axis);
      p.turbulence = read_fractal(object.find("turbulence"));
      object.reject_unknown_keys();
      return p;
    }
  }
}

ColourRamp read_ramp(const JsonValue& value) {
  JsonObject object(value);
  ColourRamp ramp;
  for (const JsonValue& key_value :
       object.get("keys").elements(static_cast<std::size_t>(SpecLimits::kMaxRampKeys))) {
    JsonObject key(key_value);
    RampKey ramp_key;
    ramp_key.position = static_cast<float>(key.get("position").number(kAnyLow, kAnyHigh));
    ramp_key.colour = key.get("colour").colour();
    key.reject_unknown_keys();
    ramp.keys.push_back(ramp_key);
  }
  object.reject_unknown_keys();
  return ramp;
}

ChannelSet read_channels(const JsonValue& value) {
  const std::vector<JsonValue> names = value.elements(3);
  if (names.empty()) return ChannelSet{};  // as in the protocol: colour only
  ChannelSet channels{false, false, false};
  for (const JsonValue& name : names) {
    const Channel channel = name.choice<Channel>({{"colour", Channel::colour},
                                                  {"opacity", Channel::opacity},
                                                  {"specular", Channel::specular}});
    bool& wanted = channel == Channel::colour    ? channels.colour
                   : channel == Channel::opacity ? channels.opacity
                                                 : channels.specular;
    const std::string listed = name.string();
    if (wanted) name.fail("\"" + listed + "\" is listed twice");
    wanted = true;
  }
  return channels;
}

ScalarRange read_range(const std::optional<JsonValue>& value) {
  ScalarRange range;
  if (!value) return range;
  JsonObject object(*value);
  range.low = static_cast<float>(object.number("low", range.low, kAnyLow, kAnyHigh));
  range.high = static_cast<float>(object.number("high", range.high, kAnyLow, kAnyHigh));
  object.reject_unknown_keys();
  return range;
}

const char* axis_name(Axis axis) {
  static constexpr const char* kNames[] = {"x", "y", "z"};
  return kNames[static_cast<int>(axis)];
}

const char* basis_name(NoiseBasis basis) {
  return basis == NoiseBasis::value ? "value" : "gradient";
}

json fractal_to_json(const FractalParams& f) {
  return {{"scale", f.scale},
          {"octave_min", f.octave_min},
          {"octave_max", f.octave_max},
          {"basis", basis_name(f.basis)},
          {"signed_octaves", f.signed_octaves}};
}

json colour_to_json(const glm::vec3& c) {
  return json::array({c.r, c.g, c.b});
}

json pattern_to_json(const Pattern& pattern) {
  return std::visit(
      Overloaded{
          [](const StripesParams& p) -> json {
            return {{"width", p.width}, {"offset", p.offset}, {"axis", axis_name(p.axis)}};
          },
          [](const CheckerParams& p) -> json {
            return {{"size", json::array({p.size.x, p.size.y, p.size.z})},
                    {"offset", p.offset},
                    {"three_d", p.three_d}};
          },
          [](const ColourCubeParams& p) -> json {
            return {{"period", p.period}};
          },
          [](const RingsParams& p) -> json {
            return {{"thickness", p.thickness}, {"base", p.base}, {"amplitude", p.amplitude}};
          },
          [](const WoodParams& p) -> json {
            return {{"ring_spacing", p.ring_spacing},
                    {"tilt_y", p.tilt_y},
                    {"tilt_z", p.tilt_z},
                    {"twist", p.twist},
                    {"jitter", p.jitter},
                    {"jitter_scale", p.jitter_scale},
                    {"grain_fraction", p.grain_fraction}};
          },
          [](const NoiseParams& p) -> json {
            return {{"scale", p.scale}, {"basis", basis_name(p.basis)}};
          },
          [](const TurbulenceParams& p) -> json {
            return {{"fractal", fractal_to_json(p.fractal)}};
          },
          [](const MarbleParams& p) -> json {
            return {{"frequency", p.frequency},
                    {"amplitude", p.amplitude},
                    {"ripple", p.ripple == Ripple::axis ? "axis" : "product"},
                    {"axis", axis_name(p.axis)},
                    {"turbulence", fractal_to_json(p.turbulence)}};
          },
      },
      pattern);
}

}  // namespace

TextureSpec texture_spec_from_json(const json& json_value, const std::string& file,
                                   const std::string& path) {
  JsonObject object(JsonValue(json_value, path, file));
  TextureSpec spec;
  const std::size_t which = object.one_of(
      {kPatternNames[0], kPatternNames[1], kPatternNames[2], kPatternNames[3], kPatternNames[4],
       kPatternNames[5], kPatternNames[6], kPatternNames[7], kPatternNames[8], "materialx"},
      {"ramp", "channels", "opacity", "specular"});
  const JsonValue pattern =
      object.get(which == kMaterialxChoice ? "materialx" : kPatternNames[which]);
  try {
    if (which == kGraphChoice) {
      spec.graph = graph::compile(graph_from_json(pattern));
    } else if (which == kMaterialxChoice) {
      spec.graph = read_materialx(pattern);
    } else {
      spec.pattern = read_pattern(which, JsonObject(pattern));
    }
  } catch (const SpecError& error) {
    throw SceneError::from_spec_error(file, path, error);
  }
  if (const auto ramp = object.find("ramp")) spec.ramp = read_ramp(*ramp);
  if (const auto channels = object.find("channels")) spec.channels = read_channels(*channels);
  spec.opacity = read_range(object.find("opacity"));
  spec.specular = read_range(object.find("specular"));
  object.reject_unknown_keys();
  try {
    return validated(std::move(spec));
  } catch (const SpecError& error) {
    throw SceneError::from_spec_error(file, path, error);
  }
}

json texture_spec_to_json(const TextureSpec& spec) {
  json keys = json::array();
  for (const RampKey& key : spec.ramp.keys) {
    keys.push_back({{"position", key.position}, {"colour", colour_to_json(key.colour)}});
  }
  json channels = json::array();
  if (spec.channels.colour) channels.push_back("colour");
  if (spec.channels.opacity) channels.push_back("opacity");
  if (spec.channels.specular) channels.push_back("specular");
  json pattern = spec.graph ? json{{"graph", graph_to_json(graph::source_of(*spec.graph))}}
                            : json{{pattern_name(spec.pattern), pattern_to_json(spec.pattern)}};
  pattern.update(json{{"ramp", {{"keys", keys}}},
                      {"channels", channels},
                      {"opacity", {{"low", spec.opacity.low}, {"high", spec.opacity.high}}},
                      {"specular", {{"low", spec.specular.low}, {"high", spec.specular.high}}}});
  return pattern;
}

}  // namespace soltex
