// Brick codec throughput and compression, single thread: encode_brick and decode_brick over
// a fixed set of real bricks.
//
// Bricks: B = 16, RGB, level 0 of Volume{[-1, 1]^3, 2^8 cells per axis}, band-limited (the
// server's default), eight bricks spread over the volume, quantized once up front.
// Benchmarks are named <Encode|Decode>/<pattern>/<codec>/<filter>. Rates are of decoded bytes
// (the quantized samples): bytes_per_second is encoded or decoded sample bytes per second.
// The counter `ratio` is decoded bytes / encoded bytes, headers included.
//
// EncodeSamples/<pattern>/<codec> is the server's encoder, encode_brick_samples(): float
// samples quantized and predicted (gradient_3d) in one pass, then compressed; it sweeps zstd's
// levels, the negative (fast) ones included, to choose soltexd's --zstd-level.

#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"

namespace {

constexpr int kBrickSize = 16;
constexpr int kChannels = 3;

struct NamedPattern {
  const char* name;
  soltex::Pattern pattern;
};

struct NamedCodec {
  const char* name;
  soltex::Codec codec;
  int zstd_level;
};

// The gallery's parameters, except the checker: its gallery size 0.25 puts every edge on a
// level-0 brick face (bricks are 0.125 wide), which leaves the bricks' insides constant; at 0.1
// edges cross the bricks.
const NamedPattern kPatterns[] = {
    {"marble", soltex::MarbleParams{}},
    {"wood", soltex::WoodParams{}},
    {"checker-3d", soltex::CheckerParams{glm::dvec3(0.1), 0.0, true}},
    {"turbulence",
     soltex::TurbulenceParams{soltex::FractalParams{4.0, 0, 5, soltex::NoiseBasis::value, false}}},
    {"colour-cube", soltex::ColourCubeParams{1.0}},
};

const NamedCodec kCodecs[] = {
    {"raw", soltex::Codec::raw, 0},
    {"lz4", soltex::Codec::lz4, 0},
    {"zstd-1", soltex::Codec::zstd, 1},
    {"zstd-3", soltex::Codec::zstd, 3},
};

const soltex::BrickFilter kFilters[] = {soltex::BrickFilter::none, soltex::BrickFilter::delta_x,
                                        soltex::BrickFilter::gradient_xy,
                                        soltex::BrickFilter::gradient_3d};

const glm::ivec3 kBricks[] = {{0, 0, 0}, {15, 15, 15}, {3, 7, 11},  {12, 4, 9},
                              {8, 8, 8}, {5, 13, 2},   {10, 1, 14}, {14, 10, 6}};

// zstd levels the server's encoder is measured at, and lz4 for comparison.
const NamedCodec kServerCodecs[] = {
    {"lz4", soltex::Codec::lz4, 0},
    {"zstd--10000", soltex::Codec::zstd, -10000},
    {"zstd--1000", soltex::Codec::zstd, -1000},
    {"zstd--200", soltex::Codec::zstd, -200},
    {"zstd--50", soltex::Codec::zstd, -50},
    {"zstd--20", soltex::Codec::zstd, -20},
    {"zstd--5", soltex::Codec::zstd, -5},
    {"zstd--1", soltex::Codec::zstd, -1},
    {"zstd-1", soltex::Codec::zstd, 1},
    {"zstd-3", soltex::Codec::zstd, 3},
};

using Planes = std::vector<uint8_t>;
using Samples = std::vector<float>;

std::vector<Samples> float_bricks(const soltex::Pattern& pattern) {
  soltex::TextureSpec spec;
  spec.pattern = pattern;
  const soltex::TextureEvaluator texture(spec);
  const soltex::BrickLayout layout(soltex::Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 8},
                                   kBrickSize);
  std::vector<Samples> bricks;
  for (const glm::ivec3& brick : kBricks) {
    Samples samples(static_cast<std::size_t>(layout.samples_per_brick()) * kChannels);
    soltex::evaluate_brick(texture, layout, 0, brick, soltex::MipSettings{}, samples);
    bricks.push_back(std::move(samples));
  }
  return bricks;
}

void encode_samples(benchmark::State& state, const std::vector<Samples>* bricks,
                    soltex::CodecOptions options) {
  int64_t decoded = 0, encoded = 0;
  for (const Samples& samples : *bricks) {
    decoded += static_cast<int64_t>(samples.size());
    encoded += static_cast<int64_t>(
        soltex::encode_brick_samples(samples, kBrickSize, kChannels, options).size());
  }
  for (auto _ : state) {
    for (const Samples& samples : *bricks) {
      benchmark::DoNotOptimize(
          soltex::encode_brick_samples(samples, kBrickSize, kChannels, options));
    }
  }
  state.SetBytesProcessed(state.iterations() * decoded);
  state.counters["ratio"] = static_cast<double>(decoded) / static_cast<double>(encoded);
  state.counters["us_per_brick"] = benchmark::Counter(
      static_cast<double>(bricks->size()) * 1e-6,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The quantizer, and the quantizer with the 3D predictor, over the brick set: the scalar
// functions (quantize(), then apply_brick_filter()) against the Highway kernels
// (quantize_values(), quantize_and_predict()). CPU per brick in the time column / 8.
void quantize_bricks(benchmark::State& state, const std::vector<Samples>* bricks, bool simd,
                     bool predict) {
  Planes quantized(bricks->front().size() + soltex::kQuantizePredictSlack);
  Planes residual(quantized.size());
  for (auto _ : state) {
    for (const Samples& samples : *bricks) {
      if (simd && predict) {
        soltex::quantize_and_predict(samples, kBrickSize + 1, quantized, residual);
      } else if (simd) {
        soltex::quantize_values(samples, quantized);
      } else {
        Planes planes = soltex::quantize(samples);
        if (predict) {
          soltex::apply_brick_filter(soltex::BrickFilter::gradient_3d, kBrickSize + 1, planes);
        }
        benchmark::DoNotOptimize(planes.data());
      }
      benchmark::DoNotOptimize(residual.data());
      benchmark::DoNotOptimize(quantized.data());
    }
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bricks->size()) *
                          static_cast<int64_t>(bricks->front().size()));
}

std::vector<Planes> quantized_bricks(const soltex::Pattern& pattern) {
  soltex::TextureSpec spec;
  spec.pattern = pattern;
  const soltex::TextureEvaluator texture(spec);
  const soltex::BrickLayout layout(soltex::Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 8},
                                   kBrickSize);
  std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * kChannels);
  std::vector<Planes> bricks;
  for (const glm::ivec3& brick : kBricks) {
    soltex::evaluate_brick(texture, layout, 0, brick, soltex::MipSettings{}, samples);
    bricks.push_back(soltex::quantize(samples));
  }
  return bricks;
}

struct Encoded {
  std::vector<std::vector<uint8_t>> bricks;
  double ratio = 0.0;
  int64_t decoded_bytes = 0;
};

Encoded encode_all(const std::vector<Planes>& bricks, const soltex::CodecOptions& options,
                   soltex::BrickFilter filter) {
  Encoded out;
  int64_t encoded_bytes = 0;
  for (const Planes& planes : bricks) {
    out.bricks.push_back(soltex::encode_brick(planes, kBrickSize, kChannels, options, filter));
    encoded_bytes += static_cast<int64_t>(out.bricks.back().size());
    out.decoded_bytes += static_cast<int64_t>(planes.size());
  }
  out.ratio = static_cast<double>(out.decoded_bytes) / static_cast<double>(encoded_bytes);
  return out;
}

void encode(benchmark::State& state, const std::vector<Planes>* bricks,
            soltex::CodecOptions options, soltex::BrickFilter filter) {
  const Encoded reference = encode_all(*bricks, options, filter);
  for (auto _ : state) {
    for (const Planes& planes : *bricks) {
      benchmark::DoNotOptimize(
          soltex::encode_brick(planes, kBrickSize, kChannels, options, filter));
    }
  }
  state.SetBytesProcessed(state.iterations() * reference.decoded_bytes);
  state.counters["ratio"] = reference.ratio;
}

void decode(benchmark::State& state, const std::vector<Planes>* bricks,
            soltex::CodecOptions options, soltex::BrickFilter filter) {
  const Encoded encoded = encode_all(*bricks, options, filter);
  for (auto _ : state) {
    for (const std::vector<uint8_t>& brick : encoded.bricks) {
      benchmark::DoNotOptimize(soltex::decode_brick(brick));
    }
  }
  state.SetBytesProcessed(state.iterations() * encoded.decoded_bytes);
  state.counters["ratio"] = encoded.ratio;
}

}  // namespace

int main(int argc, char** argv) {
  // The registered benchmarks point into `bricks`, which lives until main returns.
  std::vector<std::vector<Planes>> bricks;
  for (const NamedPattern& pattern : kPatterns) bricks.push_back(quantized_bricks(pattern.pattern));

  for (std::size_t p = 0; p < std::size(kPatterns); ++p) {
    for (const NamedCodec& codec : kCodecs) {
      for (soltex::BrickFilter filter : kFilters) {
        soltex::CodecOptions options;
        options.codec = codec.codec;
        options.zstd_level = codec.zstd_level;
        const std::string suffix = std::string(kPatterns[p].name) + "/" + codec.name + "/" +
                                   soltex::brick_filter_name(filter);
        const std::vector<Planes>* set = &bricks[p];
        benchmark::RegisterBenchmark(("Encode/" + suffix).c_str(), encode, set, options, filter);
        benchmark::RegisterBenchmark(("Decode/" + suffix).c_str(), decode, set, options, filter);
      }
    }
  }
  std::vector<std::vector<Samples>> samples;
  for (const NamedPattern& pattern : kPatterns) samples.push_back(float_bricks(pattern.pattern));
  for (std::size_t p = 0; p < std::size(kPatterns); ++p) {
    for (const NamedCodec& codec : kServerCodecs) {
      const soltex::CodecOptions options{codec.codec, codec.zstd_level, true};
      benchmark::RegisterBenchmark(
          ("EncodeSamples/" + std::string(kPatterns[p].name) + "/" + codec.name).c_str(),
          encode_samples, &samples[p], options);
    }
  }
  for (const bool predict : {false, true}) {
    for (const bool simd : {false, true}) {
      const std::string name =
          std::string(predict ? "QuantizePredict/" : "Quantize/") + (simd ? "highway" : "scalar");
      benchmark::RegisterBenchmark(name.c_str(), quantize_bricks, &samples[0], simd, predict);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
