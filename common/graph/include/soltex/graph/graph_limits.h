#pragma once

// Bounds on what one graph may ask of the evaluator; published in GetServerInfo.
namespace soltex::graph {

struct GraphLimits {
  static constexpr int kMaxNodes = 256;
  static constexpr int kMaxDepth = 64;  // longest chain of nodes from an output
  // Estimated cost of one sample, in noise octaves: an octave of noise3d / fractal3d /
  // turbulence per output component costs 1, a Worley node 8, a cell noise or wood node 1,
  // any other node 1/16 (docs/TEXTURES.md, "Node graphs").
  static constexpr double kMaxCostPerSample = 96.0;
  static constexpr int kMaxNameLength = 64;
  static constexpr double kMaxConstant = 1e15;  // |constant|: beyond it, products overflow
  static constexpr int kMaxOctaves = 16;
  static constexpr double kMaxLacunarity = 16.0;
};

}  // namespace soltex::graph
