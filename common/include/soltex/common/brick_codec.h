#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "soltex/common/brick_filter.h"

// The wire and cache form of a brick: quantized to 8 bits per sample, filtered by a
// predictor, compressed, behind a small fixed header.
//
// Encoded brick, little-endian, kBrickHeaderSize bytes of header then the payload:
//   offset  size  field
//        0     4  magic "SLTX"
//        4     1  format version (kBrickFormatVersion)
//        5     1  brick size B (8 or 16)
//        6     1  channel count (1..5), planes in the order R, G, B, opacity, specular
//        7     1  codec (Codec)
//        8     1  filter (BrickFilter)
//        9     3  reserved, zero
//       12     4  decoded size in bytes: (B + 1)^3 * channels
//       16     4  payload size in bytes: everything after the header
//       20     8  XXH64 (seed 0) of the decoded quantized samples
//       28        payload
//
// Decoding trusts nothing: every field is checked against the bounds the format allows before
// anything is allocated or decompressed, so a decoder never holds more than
// (kMaxBrickSize + 1)^3 * kMaxBrickChannels bytes of output for any input.
namespace soltex {

// ---- Quantization --------------------------------------------------------------------------

// Clamps to [0, 1] first (NaN and -inf give 0, +inf and 1.0000001 give 255), then rounds
// v * 255 to the nearest integer.
uint8_t quantize(float value);
std::vector<uint8_t> quantize(std::span<const float> values);

inline constexpr float dequantize(uint8_t q) {
  return static_cast<float>(q) / 255.0f;
}

// ---- Encoding ------------------------------------------------------------------------------

// Stored in the header: never renumber.
enum class Codec : uint8_t { raw = 0, lz4 = 1, zstd = 2 };

const char* codec_name(Codec codec);

struct CodecOptions {
  Codec codec = Codec::zstd;
  int zstd_level = 3;
  bool filter = true;  // apply kBrickCodecFilter before compressing
};

// The options soltexd encodes `codec` with: the predictor only for a compressor, which it
// helps; a raw brick without it, which a client would only have to undo.
inline CodecOptions served_codec_options(Codec codec, int zstd_level) {
  return CodecOptions{codec, zstd_level, codec != Codec::raw};
}

// The predictor the codec applies when CodecOptions::filter is set: the 3D Lorenzo predictor
// compressed real bricks best (docs/PERFORMANCE.md, "Brick codec").
inline constexpr BrickFilter kBrickCodecFilter = BrickFilter::gradient_3d;

inline constexpr char kBrickMagic[4] = {'S', 'L', 'T', 'X'};
inline constexpr uint8_t kBrickFormatVersion = 1;
inline constexpr std::size_t kBrickHeaderSize = 28;
inline constexpr int kMaxBrickChannels = 5;

// (B + 1)^3 * channels: the size of a brick's quantized planes.
std::size_t brick_decoded_size(int brick_size, int channels);

// Encodes quantized channel-planar samples (x fastest, one (B + 1)^3 plane per channel).
// Throws std::invalid_argument when brick_size is not 8 or 16, channels is not in [1, 5],
// the sample count does not match, or zstd_level is outside zstd's range.
std::vector<uint8_t> encode_brick(std::span<const uint8_t> quantized_planes, int brick_size,
                                  int channels, const CodecOptions& options);

// The same with an explicit predictor (options.filter is ignored): for measuring predictors
// against each other. Every BrickFilter decodes.
std::vector<uint8_t> encode_brick(std::span<const uint8_t> quantized_planes, int brick_size,
                                  int channels, const CodecOptions& options, BrickFilter filter);

// encode_brick(quantize(samples), ...) from float samples, with the quantizer and predictor
// fused into one SIMD pass (quantize_and_predict): the same bytes, one copy fewer. The server's
// encoder; the string is the payload it caches and sends. Throws as encode_brick() does.
std::string encode_brick_samples(std::span<const float> samples, int brick_size, int channels,
                                 const CodecOptions& options);

// The same into `buffer`, for a caller that keeps it from brick to brick: no allocation and no
// copy beyond the compressor's output. Returns the encoded brick, at the start of `buffer`
// (which grows to the codec's bound and never shrinks) and valid until its next use.
std::span<const uint8_t> encode_brick_samples(std::span<const float> samples, int brick_size,
                                              int channels, const CodecOptions& options,
                                              std::vector<uint8_t>& buffer);

// ---- Decoding ------------------------------------------------------------------------------

// An encoded brick that is malformed, truncated or corrupt. The message names what is wrong
// and the bound it breaks.
class CodecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DecodedBrick {
  int brick_size = 0;
  int channels = 0;
  std::vector<uint8_t> samples;  // channel-planar, x fastest
};

// Throws CodecError for anything but a well-formed brick whose samples match its checksum.
DecodedBrick decode_brick(std::span<const uint8_t> encoded);

// The checksum an encoded brick's header declares, without decoding it. Throws CodecError
// when `encoded` is shorter than a header.
uint64_t encoded_brick_checksum(std::span<const uint8_t> encoded);

}  // namespace soltex
