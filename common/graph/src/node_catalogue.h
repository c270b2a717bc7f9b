#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

// Every node category a graph may use: its inputs, their kinds and defaults, and how the
// output type follows from them. Names and semantics are MaterialX's standard library
// (Standard Nodes) where the node exists there; docs/SCENES.md lists them all.
namespace soltex::graph {

enum class ValueType : uint8_t { float_, vector3, color3 };

const char* type_name(ValueType type);
int components(ValueType type);

enum class Op : uint8_t {
  position,
  constant,
  add,
  subtract,
  multiply,
  divide,
  modulo,
  power,
  min,
  max,
  abs,
  floor,
  ceil,
  fract,
  sin,
  cos,
  sqrt,
  clamp,
  smoothstep,
  remap,
  mix,
  dotproduct,
  magnitude,
  extract,
  combine3,
  convert,
  noise3d,
  fractal3d,
  turbulence,
  cellnoise3d,
  worleynoise3d,
  ramp,
  stripes,
  checker,
  colour_cube,
  rings,
  wood,
  marble,
};

// What an input accepts.
enum class Slot : uint8_t {
  working,           // the node's working type T (connectable)
  working_or_float,  // T, or a float broadcast to every component (connectable)
  float_,            // a float (connectable)
  position,          // a vector3 position (connectable); absent: the texture-space position
  any_vector,        // vector3 or color3 (connectable)
  any,               // any type (connectable)
  number,            // a constant number in [lo, hi]
  integer,           // a constant integer in [lo, hi]
  boolean,           // a constant 0 or 1 (true / false)
  vector_param,      // a constant vector, each component in [lo, hi]
  choice,            // a constant name, one of `choices`
  keys,              // constant ramp keys
};

inline bool connectable(Slot slot) {
  return slot <= Slot::any;
}

struct InputDef {
  const char* name;
  Slot slot;
  double fallback;  // default; NaN: the input is required
  double lo = -1e300, hi = 1e300;
  const char* choices = "";  // '|'-separated, the first is the default
};

// How the output type is found.
enum class TypeRule : uint8_t {
  working,   // T: the node's declared type, else the widest type among its working inputs
  declared,  // the node's declared type, else `fallback_type`; one of `allowed`
  fixed,     // always `fallback_type`
};

struct NodeDef {
  const char* category;
  Op op;
  TypeRule rule;
  ValueType fallback_type;
  std::vector<ValueType> allowed;
  std::vector<InputDef> inputs;
};

// nullptr for an unknown category.
const NodeDef* find_node_def(std::string_view category);

// Every category, for messages ("must be one of ...") and the documentation test.
const std::vector<NodeDef>& node_catalogue();

}  // namespace soltex::graph
