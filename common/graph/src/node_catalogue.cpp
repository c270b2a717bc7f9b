#include "node_catalogue.h"

#include <algorithm>
#include <limits>

namespace soltex::graph {
namespace {

constexpr double kRequired = std::numeric_limits<double>::quiet_NaN();
constexpr ValueType F = ValueType::float_, V = ValueType::vector3, C = ValueType::color3;
const std::vector<ValueType> kAnyType{F, V, C};
const std::vector<ValueType> kNoiseTypes{F, V};

NodeDef unary(const char* category, Op op) {
  return {category, op, TypeRule::working, F, kAnyType, {{"in", Slot::working, kRequired}}};
}

NodeDef binary(const char* category, Op op, double in2) {
  return {
      category,          op,
      TypeRule::working, F,
      kAnyType,          {{"in1", Slot::working, kRequired}, {"in2", Slot::working_or_float, in2}}};
}

// Inputs every noise node shares, in MaterialX's order.
std::vector<InputDef> fractal_inputs() {
  return {{"amplitude", Slot::working_or_float, 1.0},
          {"octaves", Slot::integer, 3.0, 1.0, 16.0},
          {"lacunarity", Slot::number, 2.0, 1.0, 16.0},
          {"diminish", Slot::number, 0.5, 0.0, 1.0},
          {"position", Slot::position, 0.0},
          {"basis", Slot::choice, 0.0, 0.0, 0.0, "gradient|value"}};
}

std::vector<NodeDef> make_catalogue() {
  std::vector<NodeDef> defs = {
      {"position", Op::position, TypeRule::fixed, V, {V}, {}},
      {"constant",
       Op::constant,
       TypeRule::working,
       F,
       kAnyType,
       {{"value", Slot::working, kRequired}}},
      binary("add", Op::add, 0.0),
      binary("subtract", Op::subtract, 0.0),
      binary("multiply", Op::multiply, 1.0),
      binary("divide", Op::divide, 1.0),
      binary("modulo", Op::modulo, 1.0),
      binary("power", Op::power, 1.0),
      binary("min", Op::min, 0.0),
      binary("max", Op::max, 0.0),
      unary("absval", Op::abs),
      unary("floor", Op::floor),
      unary("ceil", Op::ceil),
      unary("fract", Op::fract),
      unary("sin", Op::sin),
      unary("cos", Op::cos),
      unary("sqrt", Op::sqrt),
      {"clamp",
       Op::clamp,
       TypeRule::working,
       F,
       kAnyType,
       {{"in", Slot::working, kRequired},
        {"low", Slot::working_or_float, 0.0},
        {"high", Slot::working_or_float, 1.0}}},
      {"smoothstep",
       Op::smoothstep,
       TypeRule::working,
       F,
       kAnyType,
       {{"in", Slot::working, kRequired},
        {"low", Slot::working_or_float, 0.0},
        {"high", Slot::working_or_float, 1.0}}},
      {"remap",
       Op::remap,
       TypeRule::working,
       F,
       kAnyType,
       {{"in", Slot::working, kRequired},
        {"inlow", Slot::working_or_float, 0.0},
        {"inhigh", Slot::working_or_float, 1.0},
        {"outlow", Slot::working_or_float, 0.0},
        {"outhigh", Slot::working_or_float, 1.0}}},
      {"mix",
       Op::mix,
       TypeRule::working,
       F,
       kAnyType,
       {{"fg", Slot::working, kRequired},
        {"bg", Slot::working, kRequired},
        {"mix", Slot::working_or_float, 0.0}}},
      {"dotproduct",
       Op::dotproduct,
       TypeRule::fixed,
       F,
       {F},
       {{"in1", Slot::any_vector, kRequired}, {"in2", Slot::any_vector, kRequired}}},
      {"magnitude", Op::magnitude, TypeRule::fixed, F, {F}, {{"in", Slot::any_vector, kRequired}}},
      {"extract",
       Op::extract,
       TypeRule::fixed,
       F,
       {F},
       {{"in", Slot::any_vector, kRequired}, {"index", Slot::integer, 0.0, 0.0, 2.0}}},
      {"combine3",
       Op::combine3,
       TypeRule::declared,
       V,
       {V, C},
       {{"in1", Slot::float_, 0.0}, {"in2", Slot::float_, 0.0}, {"in3", Slot::float_, 0.0}}},
      {"convert", Op::convert, TypeRule::declared, V, kAnyType, {{"in", Slot::any, kRequired}}},
      {"noise3d",
       Op::noise3d,
       TypeRule::declared,
       F,
       kNoiseTypes,
       {{"amplitude", Slot::working_or_float, 1.0},
        {"pivot", Slot::float_, 0.0},
        {"position", Slot::position, 0.0},
        {"basis", Slot::choice, 0.0, 0.0, 0.0, "gradient|value"}}},
      {"fractal3d", Op::fractal3d, TypeRule::declared, F, kNoiseTypes, fractal_inputs()},
      {"turbulence", Op::turbulence, TypeRule::declared, F, kNoiseTypes, fractal_inputs()},
      {"cellnoise3d",
       Op::cellnoise3d,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0}}},
      {"worleynoise3d",
       Op::worleynoise3d,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"jitter", Slot::number, 1.0, 0.0, 1.0},
        {"feature", Slot::choice, 0.0, 0.0, 0.0, "f1|f2|f2_minus_f1"}}},
      {"ramp",
       Op::ramp,
       TypeRule::fixed,
       C,
       {C},
       {{"in", Slot::float_, kRequired}, {"keys", Slot::keys, kRequired}}},
      {"stripes",
       Op::stripes,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"width", Slot::number, 1.0},
        {"offset", Slot::number, 0.0},
        {"axis", Slot::choice, 0.0, 0.0, 0.0, "x|y|z"}}},
      {"checker",
       Op::checker,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"size", Slot::vector_param, 1.0},
        {"offset", Slot::number, 0.0},
        {"three_d", Slot::boolean, 0.0}}},
      {"colour_cube",
       Op::colour_cube,
       TypeRule::fixed,
       C,
       {C},
       {{"position", Slot::position, 0.0}, {"period", Slot::number, 1.0}}},
      {"rings",
       Op::rings,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"thickness", Slot::number, 0.1},
        {"base", Slot::number, 0.0},
        {"amplitude", Slot::number, 1.0}}},
      {"wood",
       Op::wood,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"ring_spacing", Slot::number, 0.1},
        {"tilt_y", Slot::number, 0.3},
        {"tilt_z", Slot::number, 0.15},
        {"twist", Slot::number, 0.5},
        {"jitter", Slot::number, 0.6},
        {"jitter_scale", Slot::number, 4.0},
        {"grain_fraction", Slot::number, 0.2}}},
      {"marble",
       Op::marble,
       TypeRule::fixed,
       F,
       {F},
       {{"position", Slot::position, 0.0},
        {"turbulence", Slot::float_, 0.0},
        {"frequency", Slot::number, 2.0},
        {"amplitude", Slot::number, 4.0},
        {"ripple", Slot::choice, 0.0, 0.0, 0.0, "axis|product"},
        {"axis", Slot::choice, 0.0, 0.0, 0.0, "x|y|z"}}},
  };
  return defs;
}

}  // namespace

const char* type_name(ValueType type) {
  switch (type) {
    case ValueType::float_:
      return "float";
    case ValueType::vector3:
      return "vector3";
    case ValueType::color3:
      return "color3";
  }
  return "unknown";
}

int components(ValueType type) {
  return type == ValueType::float_ ? 1 : 3;
}

const std::vector<NodeDef>& node_catalogue() {
  static const std::vector<NodeDef> catalogue = make_catalogue();
  return catalogue;
}

const NodeDef* find_node_def(std::string_view category) {
  for (const NodeDef& def : node_catalogue()) {
    if (category == def.category) return &def;
  }
  return nullptr;
}

bool takes_boolean(std::string_view category, std::string_view input) {
  const NodeDef* def = find_node_def(category);
  if (def == nullptr) return false;
  return std::any_of(def->inputs.begin(), def->inputs.end(), [&](const InputDef& in) {
    return in.slot == Slot::boolean && input == in.name;
  });
}

}  // namespace soltex::graph
