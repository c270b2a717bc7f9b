#pragma once

#include <array>
#include <glm/vec3.hpp>
#include <vector>

#include "node_catalogue.h"
#include "soltex/common/texture_spec.h"

// A compiled graph: registers of planar values and the instructions that fill them, in an
// order where every instruction's inputs come first. Each instruction runs as one array kernel
// over all the samples of a batch.
namespace soltex::graph {

// A register holds `components` planes of doubles, one value per sample.
struct Register {
  int components = 1;
  bool constant = false;  // filled once per batch from `value`
  glm::dvec3 value{0.0};
  // How much wider than the texture-space filter width the value's features are blurred:
  // width(value) = width_scale * width(texture space). See docs/TEXTURES.md, "Node graphs".
  double width_scale = 0.0;
  // Each component depends only on the same texture-space axis (position scaled and shifted
  // per axis): along a grid row, x varies alone and y, z are the row's.
  bool separable = true;
  // The register holding, per sample, the variance within the sample's box of what this value
  // does not show (faded octaves, ripples finer than the box), or -1 where none is kept. A
  // ramp reading the value averages its colours over it, as a built-in pattern's ramp does;
  // only a noise or marble node's own output carries one.
  int variance = -1;
};

struct NoiseSetup {
  NoiseBasis basis = NoiseBasis::gradient;
  bool absolute = false;
  int octaves = 1;
  double lacunarity = 2.0;
  double diminish = 0.5;
};

enum class WorleyFeature : uint8_t { f1, f2, f2_minus_f1 };

struct WorleySetup {
  double jitter = 1.0;
  WorleyFeature feature = WorleyFeature::f1;
  float mean = 0.0f;  // over space, what a faded Worley node becomes
};

inline constexpr int kMaxOperands = 5;

struct Instruction {
  Op op = Op::constant;
  int out = -1;
  int operand_count = 0;
  std::array<int, kMaxOperands> in{-1, -1, -1, -1, -1};
  int index = 0;          // extract's component
  int variance_out = -1;  // where the output's variance goes (Register::variance), or -1
  // For arithmetic that scales and shifts one input by constants (add, subtract, multiply,
  // divide, remap): that input, whose variance times `variance_gain` (the scale's square) is
  // the output's.
  int variance_in = -1;
  double variance_gain = 0.0;
  NoiseSetup noise;
  WorleySetup worley;
  ColourRamp ramp;
  Pattern pattern;  // the built-in pattern of a pattern node
};

struct Program {
  std::vector<Register> registers;
  std::vector<Instruction> instructions;
  int position = -1;                             // the texture-space position register
  int colour = -1, opacity = -1, specular = -1;  // output registers, -1 when absent
  double cost_per_sample = 0.0;
  int depth = 0;
};

}  // namespace soltex::graph
