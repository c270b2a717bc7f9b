#include "soltex/common/brick_codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"

namespace soltex {
namespace {

// ---- Real bricks ---------------------------------------------------------------------------

std::vector<Pattern> all_patterns() {
  return {StripesParams{0.13, 0.0, Axis::x},
          CheckerParams{glm::dvec3(0.07), 0.0, true},
          ColourCubeParams{0.3},
          RingsParams{0.05, 0.0, 1.0},
          WoodParams{},
          NoiseParams{9.0, NoiseBasis::gradient},
          TurbulenceParams{},
          MarbleParams{}};
}

// 1: opacity only, 3: colour, 5: colour, opacity and specular.
ChannelSet channels_for(int count) {
  switch (count) {
    case 1:
      return {false, true, false};
    case 3:
      return {true, false, false};
    default:
      return {true, true, true};
  }
}

// A level-0 brick away from the volume's corner, so every pattern shows structure in it.
std::vector<uint8_t> real_brick(const Pattern& pattern, int brick_size, int channels) {
  TextureSpec spec;
  spec.pattern = pattern;
  spec.channels = channels_for(channels);
  spec.opacity = {0.2f, 0.9f};
  const TextureEvaluator texture(spec);
  const BrickLayout layout(Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 6}, brick_size);
  std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * channels);
  evaluate_brick(texture, layout, 0, glm::ivec3(1, 2, 1), MipSettings{}, samples);
  return quantize(samples);
}

struct CodecCase {
  const char* name;
  CodecOptions options;
};

std::vector<CodecCase> all_codecs(bool filter) {
  return {{"raw", {Codec::raw, 0, filter}},
          {"lz4", {Codec::lz4, 0, filter}},
          {"zstd--200", {Codec::zstd, -200, filter}},
          {"zstd-1", {Codec::zstd, 1, filter}},
          {"zstd-3", {Codec::zstd, 3, filter}}};
}

std::vector<uint8_t> random_bytes(std::size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> bytes(n);
  for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
  return bytes;
}

// ---- Round trips ---------------------------------------------------------------------------

TEST(BrickCodec, RoundTripsEveryPatternCodecAndFilter) {
  for (const Pattern& pattern : all_patterns()) {
    for (int brick_size : {8, 16}) {
      for (int channels : {3, 5}) {
        const std::vector<uint8_t> planes = real_brick(pattern, brick_size, channels);
        for (bool filter : {false, true}) {
          for (const CodecCase& c : all_codecs(filter)) {
            SCOPED_TRACE(std::string(pattern_name(pattern)) + " B=" + std::to_string(brick_size) +
                         " channels=" + std::to_string(channels) + " " + c.name +
                         (filter ? " filtered" : " unfiltered"));
            const std::vector<uint8_t> encoded =
                encode_brick(planes, brick_size, channels, c.options);
            const DecodedBrick decoded = decode_brick(encoded);
            EXPECT_EQ(decoded.brick_size, brick_size);
            EXPECT_EQ(decoded.channels, channels);
            ASSERT_EQ(decoded.samples, planes);
          }
        }
      }
    }
  }
}

// The server's encoder from floats makes the bytes of quantize() then encode_brick().
TEST(BrickCodec, EncodingSamplesEqualsQuantizingThenEncoding) {
  for (const Pattern& pattern : all_patterns()) {
    for (int brick_size : {8, 16}) {
      for (int channels : {1, 3, 5}) {
        TextureSpec spec;
        spec.pattern = pattern;
        spec.channels = channels_for(channels);
        const TextureEvaluator texture(spec);
        const BrickLayout layout(Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 6}, brick_size);
        std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * channels);
        evaluate_brick(texture, layout, 0, glm::ivec3(1, 2, 1), MipSettings{}, samples);
        const std::vector<uint8_t> planes = quantize(samples);
        for (bool filter : {false, true}) {
          for (const CodecCase& c : all_codecs(filter)) {
            SCOPED_TRACE(std::string(pattern_name(pattern)) + " B=" + std::to_string(brick_size) +
                         " channels=" + std::to_string(channels) + " " + c.name +
                         (filter ? " filtered" : " unfiltered"));
            const std::vector<uint8_t> expected =
                encode_brick(planes, brick_size, channels, c.options);
            const std::string encoded =
                encode_brick_samples(samples, brick_size, channels, c.options);
            ASSERT_EQ(std::vector<uint8_t>(encoded.begin(), encoded.end()), expected);
            // Into a buffer kept from a larger brick: the same bytes at its start.
            std::vector<uint8_t> buffer(expected.size() + 40000, 0xA5);
            const std::span<const uint8_t> in_buffer =
                encode_brick_samples(samples, brick_size, channels, c.options, buffer);
            ASSERT_EQ(in_buffer.data(), buffer.data());
            ASSERT_EQ(std::vector<uint8_t>(in_buffer.begin(), in_buffer.end()), expected);
          }
        }
      }
    }
  }
}

TEST(BrickCodec, EncodingSamplesRejectsTheWrongCount) {
  const std::vector<float> samples(17 * 17 * 17 * 3 - 1, 0.5f);
  EXPECT_THROW(encode_brick_samples(samples, 16, 3, CodecOptions{}), std::invalid_argument);
}

TEST(BrickCodec, RoundTripsEveryFilterExplicitly) {
  const std::vector<uint8_t> planes = real_brick(MarbleParams{}, 16, 3);
  for (BrickFilter filter : {BrickFilter::none, BrickFilter::delta_x, BrickFilter::gradient_xy,
                             BrickFilter::gradient_3d}) {
    for (const CodecCase& c : all_codecs(false)) {
      SCOPED_TRACE(std::string(brick_filter_name(filter)) + " " + c.name);
      const std::vector<uint8_t> encoded = encode_brick(planes, 16, 3, c.options, filter);
      EXPECT_EQ(encoded[8], static_cast<uint8_t>(filter));
      EXPECT_EQ(decode_brick(encoded).samples, planes);
    }
  }
}

// Incompressible and degenerate contents: lz4 and zstd payloads may outgrow the samples.
TEST(BrickCodec, RoundTripsConstantAndRandomSamples) {
  const std::size_t n = brick_decoded_size(16, 5);
  const std::vector<std::vector<uint8_t>> contents = {
      std::vector<uint8_t>(n, 0), std::vector<uint8_t>(n, 255), random_bytes(n, 7)};
  for (const std::vector<uint8_t>& planes : contents) {
    for (bool filter : {false, true}) {
      for (const CodecCase& c : all_codecs(filter)) {
        SCOPED_TRACE(c.name);
        EXPECT_EQ(decode_brick(encode_brick(planes, 16, 5, c.options)).samples, planes);
      }
    }
  }
}

TEST(BrickCodec, HeaderLayoutIsLittleEndianAndFixed) {
  const std::vector<uint8_t> planes = real_brick(WoodParams{}, 8, 3);
  const std::vector<uint8_t> encoded = encode_brick(planes, 8, 3, CodecOptions{});
  ASSERT_GE(encoded.size(), kBrickHeaderSize);
  EXPECT_EQ(std::memcmp(encoded.data(), "SLTX", 4), 0);
  EXPECT_EQ(encoded[4], kBrickFormatVersion);
  EXPECT_EQ(encoded[5], 8);
  EXPECT_EQ(encoded[6], 3);
  EXPECT_EQ(encoded[7], static_cast<uint8_t>(Codec::zstd));
  EXPECT_EQ(encoded[8], static_cast<uint8_t>(kBrickCodecFilter));
  EXPECT_EQ(encoded[9] | encoded[10] | encoded[11], 0);
  const uint32_t decoded_size = 9 * 9 * 9 * 3;
  EXPECT_EQ(encoded[12], decoded_size & 0xFF);
  EXPECT_EQ(encoded[13], decoded_size >> 8);
  EXPECT_EQ(encoded[14] | encoded[15], 0);
  const std::size_t payload_size = encoded.size() - kBrickHeaderSize;
  EXPECT_EQ(encoded[16] | (encoded[17] << 8) | (encoded[18] << 16) | (encoded[19] << 24),
            static_cast<int>(payload_size));
}

TEST(BrickCodec, CompressesRealBricks) {
  // Marble at level 0 is full of fine turbulence; the colour cube is smooth.
  const std::vector<uint8_t> marble = real_brick(MarbleParams{}, 16, 3);
  EXPECT_LT(encode_brick(marble, 16, 3, CodecOptions{}).size(), marble.size() * 3 / 4);
  const std::vector<uint8_t> cube = real_brick(ColourCubeParams{0.3}, 16, 3);
  EXPECT_LT(encode_brick(cube, 16, 3, CodecOptions{}).size(), cube.size() / 4);
}

// At a fast (negative) level a noisy brick goes as Huffman-coded literals only (not stored:
// it shrinks), and a smooth one keeps the match search: its ratio is beyond what coding
// literals alone can reach (at least one bit a byte, a ratio of at most 8).
TEST(BrickCodec, FastLevelsCodeNoisyBricksAsLiteralsAndSmoothOnesWithMatches) {
  const CodecOptions fast{Codec::zstd, -200, true};
  const std::vector<uint8_t> marble = real_brick(MarbleParams{}, 16, 3);
  const std::vector<uint8_t> noisy = encode_brick(marble, 16, 3, fast);
  EXPECT_EQ(decode_brick(noisy).samples, marble);
  EXPECT_LT(noisy.size(), marble.size() * 3 / 4);
  const std::vector<uint8_t> cube = real_brick(ColourCubeParams{0.3}, 16, 3);
  const std::vector<uint8_t> smooth = encode_brick(cube, 16, 3, fast);
  EXPECT_EQ(decode_brick(smooth).samples, cube);
  EXPECT_LT(smooth.size() * 8, cube.size());
}

TEST(BrickCodec, EncodeRejectsBadArguments) {
  const std::vector<uint8_t> planes(brick_decoded_size(8, 3), 0);
  EXPECT_THROW(encode_brick(planes, 4, 3, {}), std::invalid_argument);
  EXPECT_THROW(encode_brick(planes, 8, 0, {}), std::invalid_argument);
  EXPECT_THROW(encode_brick(planes, 8, 6, {}), std::invalid_argument);
  EXPECT_THROW(encode_brick(planes, 8, 2, {}), std::invalid_argument);  // size mismatch
  EXPECT_THROW(encode_brick(planes, 8, 3, {Codec::zstd, 1000, true}), std::invalid_argument);
}

// ---- Quantization --------------------------------------------------------------------------

TEST(Quantize, ClampsBeforeRounding) {
  EXPECT_EQ(quantize(0.0f), 0);
  EXPECT_EQ(quantize(-0.0f), 0);
  EXPECT_EQ(quantize(1.0f), 255);
  EXPECT_EQ(quantize(1.0000001f), 255);
  EXPECT_EQ(quantize(std::nextafter(1.0f, 2.0f)), 255);
  EXPECT_EQ(quantize(1e30f), 255);
  EXPECT_EQ(quantize(-0.1f), 0);
  EXPECT_EQ(quantize(-1e30f), 0);
  EXPECT_EQ(quantize(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(quantize(-std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(quantize(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(quantize(-std::numeric_limits<float>::infinity()), 0);
  EXPECT_EQ(quantize(std::numeric_limits<float>::denorm_min()), 0);
}

TEST(Quantize, RoundsToNearest) {
  const float half_step = 0.5f / 255.0f;
  EXPECT_EQ(quantize(std::nextafter(half_step, 0.0f)), 0);
  EXPECT_EQ(quantize(std::nextafter(half_step, 1.0f)), 1);
  EXPECT_EQ(quantize(0.5f), 128);  // 127.5 rounds away from zero
  for (int k = 0; k < 255; ++k) {
    EXPECT_EQ(quantize((static_cast<float>(k) + 0.49f) / 255.0f), k) << k;
    EXPECT_EQ(quantize((static_cast<float>(k) + 0.51f) / 255.0f), k + 1) << k;
  }
}

TEST(Quantize, DequantizeRoundTripsEveryLevel) {
  for (int k = 0; k <= 255; ++k) {
    const auto q = static_cast<uint8_t>(k);
    EXPECT_EQ(quantize(dequantize(q)), q);
  }
  EXPECT_EQ(dequantize(0), 0.0f);
  EXPECT_EQ(dequantize(255), 1.0f);
}

TEST(Quantize, SpanMatchesScalar) {
  const std::vector<float> values = {
      0.0f, 0.25f, 1.5f, -3.0f, std::numeric_limits<float>::quiet_NaN(), 0.999f};
  const std::vector<uint8_t> q = quantize(values);
  ASSERT_EQ(q.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(q[i], quantize(values[i]));
}

// ---- Malformed input -----------------------------------------------------------------------

// Runs decode_brick and returns the CodecError's message; fails the test if it decodes.
std::string decode_error(const std::vector<uint8_t>& encoded) {
  try {
    decode_brick(encoded);
  } catch (const CodecError& e) {
    return e.what();
  }
  ADD_FAILURE() << "decoded a malformed brick";
  return {};
}

bool contains_any(const std::string& text, std::initializer_list<const char*> needles) {
  for (const char* needle : needles) {
    if (text.find(needle) != std::string::npos) return true;
  }
  return false;
}

std::vector<uint8_t> valid_brick(Codec codec, int brick_size = 8, int channels = 3) {
  return encode_brick(real_brick(MarbleParams{}, brick_size, channels), brick_size, channels,
                      {codec, 3, true});
}

void put_u32(std::vector<uint8_t>& bytes, std::size_t offset, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<uint8_t>(v >> (8 * i));
}

// The header of `like` with `payload` after it (payload size fixed up).
std::vector<uint8_t> with_payload(const std::vector<uint8_t>& like,
                                  const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> out(kBrickHeaderSize + payload.size());
  std::copy_n(like.begin(), kBrickHeaderSize, out.begin());
  std::copy(payload.begin(), payload.end(), out.begin() + kBrickHeaderSize);
  put_u32(out, 16, static_cast<uint32_t>(payload.size()));
  return out;
}

std::vector<uint8_t> payload_of(const std::vector<uint8_t>& encoded) {
  return {encoded.begin() + kBrickHeaderSize, encoded.end()};
}

TEST(DecodeBrick, RejectsEveryTruncation) {
  for (Codec codec : {Codec::raw, Codec::lz4, Codec::zstd}) {
    const std::vector<uint8_t> encoded = valid_brick(codec);
    for (std::size_t length = 0; length < encoded.size(); ++length) {
      const std::vector<uint8_t> cut(encoded.begin(), encoded.begin() + length);
      const std::string error = decode_error(cut);
      if (length < kBrickHeaderSize) {
        EXPECT_NE(error.find("truncated header: " + std::to_string(length) + " bytes"),
                  std::string::npos)
            << error;
        EXPECT_NE(error.find("needs 28"), std::string::npos) << error;
      } else {
        EXPECT_NE(error.find("payload size"), std::string::npos) << error;
      }
    }
  }
}

TEST(DecodeBrick, RejectsBadMagic) {
  for (std::size_t i = 0; i < 4; ++i) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[i] ^= 0x20;
    EXPECT_NE(decode_error(encoded).find("bad magic"), std::string::npos);
  }
}

TEST(DecodeBrick, RejectsUnsupportedVersion) {
  for (uint8_t version : {0, 2, 255}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[4] = version;
    const std::string error = decode_error(encoded);
    EXPECT_NE(error.find("unsupported format version " + std::to_string(version)),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("reads version 1"), std::string::npos) << error;
  }
}

TEST(DecodeBrick, RejectsBrickSizesOtherThan8And16) {
  for (uint8_t size : {0, 1, 7, 9, 15, 17, 32, 255}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[5] = size;
    const std::string error = decode_error(encoded);
    EXPECT_NE(error.find("brick size " + std::to_string(size) + " must be 8 or 16"),
              std::string::npos)
        << error;
  }
}

TEST(DecodeBrick, RejectsChannelCountsOutside1To5) {
  for (uint8_t channels : {0, 6, 255}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[6] = channels;
    const std::string error = decode_error(encoded);
    EXPECT_NE(error.find("channel count " + std::to_string(channels) + " must be in [1, 5]"),
              std::string::npos)
        << error;
  }
}

TEST(DecodeBrick, RejectsUnknownCodecAndFilter) {
  for (uint8_t id : {3, 4, 128, 255}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[7] = id;
    EXPECT_NE(decode_error(encoded).find("unknown codec " + std::to_string(id)), std::string::npos);
  }
  for (uint8_t id : {4, 5, 255}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[8] = id;
    EXPECT_NE(decode_error(encoded).find("unknown filter " + std::to_string(id)),
              std::string::npos);
  }
}

TEST(DecodeBrick, RejectsNonZeroReservedBytes) {
  for (std::size_t i = 9; i < 12; ++i) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[i] = 1;
    EXPECT_NE(decode_error(encoded).find("reserved header bytes"), std::string::npos);
  }
}

TEST(DecodeBrick, RejectsDecodedSizeThatDoesNotMatchTheShape) {
  for (uint32_t size : {0u, 2186u, 2188u, 24565u, 0xFFFFFFFFu}) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);  // B = 8, 3 channels: 2187 bytes
    put_u32(encoded, 12, size);
    const std::string error = decode_error(encoded);
    EXPECT_NE(error.find("declared decoded size " + std::to_string(size)), std::string::npos)
        << error;
    EXPECT_NE(error.find("= 2187"), std::string::npos) << error;
  }
  // A changed brick size or channel count no longer matches the declared size either.
  std::vector<uint8_t> resized = valid_brick(Codec::zstd);
  resized[5] = 16;
  EXPECT_NE(decode_error(resized).find("declared decoded size 2187"), std::string::npos);
  std::vector<uint8_t> rechannelled = valid_brick(Codec::zstd);
  rechannelled[6] = 1;
  EXPECT_NE(decode_error(rechannelled).find("declared decoded size 2187"), std::string::npos);
}

TEST(DecodeBrick, RejectsPayloadSizeThatDoesNotMatchTheBytes) {
  for (Codec codec : {Codec::raw, Codec::lz4, Codec::zstd}) {
    const std::vector<uint8_t> valid = valid_brick(codec);
    const auto payload = static_cast<uint32_t>(valid.size() - kBrickHeaderSize);
    for (uint32_t declared : {0u, payload - 1, payload + 1, 0xFFFFFFFFu}) {
      std::vector<uint8_t> encoded = valid;
      put_u32(encoded, 16, declared);
      const std::string error = decode_error(encoded);
      EXPECT_NE(error.find("payload size " + std::to_string(declared) + " does not match the " +
                           std::to_string(payload) + " bytes after the header"),
                std::string::npos)
          << error;
    }
    std::vector<uint8_t> trailing = valid;
    trailing.push_back(0);
    EXPECT_NE(decode_error(trailing).find("payload size"), std::string::npos);
  }
}

TEST(DecodeBrick, RejectsPayloadsBeyondTheCodecBound) {
  for (Codec codec : {Codec::raw, Codec::lz4, Codec::zstd}) {
    const std::vector<uint8_t> valid = valid_brick(codec);
    const std::vector<uint8_t> huge(64 * 1024, 0);
    const std::string error = decode_error(with_payload(valid, huge));
    EXPECT_NE(error.find("exceeds the bound"), std::string::npos) << error;
  }
}

TEST(DecodeBrick, RejectsRawPayloadOfTheWrongSize) {
  const std::vector<uint8_t> valid = valid_brick(Codec::raw);
  std::vector<uint8_t> payload = payload_of(valid);
  payload.resize(payload.size() - 1);
  const std::string error = decode_error(with_payload(valid, payload));
  EXPECT_NE(error.find("raw payload of 2186 bytes must equal the decoded size, 2187"),
            std::string::npos)
      << error;
}

// Another brick's payload behind this header: a stream that decodes, but to the wrong size.
TEST(DecodeBrick, RejectsPayloadsOfTheWrongDecompressedSize) {
  const std::vector<uint8_t> lz4 = valid_brick(Codec::lz4, 8, 3);
  const std::vector<uint8_t> lz4_small = valid_brick(Codec::lz4, 8, 1);
  std::string error = decode_error(with_payload(lz4, payload_of(lz4_small)));
  EXPECT_NE(error.find("lz4 payload decompressed to 729 bytes, expected 2187"), std::string::npos)
      << error;

  const std::vector<uint8_t> zstd = valid_brick(Codec::zstd, 8, 3);
  const std::vector<uint8_t> zstd_small = valid_brick(Codec::zstd, 8, 1);
  error = decode_error(with_payload(zstd, payload_of(zstd_small)));
  EXPECT_NE(error.find("zstd frame declares 729 bytes, expected 2187"), std::string::npos) << error;
}

// Hand-made zstd frames (RFC 8878): magic, frame header descriptor, then one raw block.
std::vector<uint8_t> zstd_frame(bool declare_size, uint32_t declared, uint32_t raw_bytes) {
  std::vector<uint8_t> frame = {0x28, 0xB5, 0x2F, 0xFD};
  if (declare_size) {
    frame.push_back(0xA0);  // 4-byte content size, single segment
    for (int i = 0; i < 4; ++i) frame.push_back(static_cast<uint8_t>(declared >> (8 * i)));
  } else {
    frame.push_back(0x00);  // no content size
    frame.push_back(0x58);  // window descriptor: 2^(10 + 11) bytes
  }
  const uint32_t block_header = 1u | (raw_bytes << 3);  // last block, raw
  for (int i = 0; i < 3; ++i) frame.push_back(static_cast<uint8_t>(block_header >> (8 * i)));
  frame.insert(frame.end(), raw_bytes, 0x11);
  return frame;
}

TEST(DecodeBrick, RejectsZstdFramesThatAreNotExact) {
  const std::vector<uint8_t> valid = valid_brick(Codec::zstd, 8, 3);
  std::string error = decode_error(with_payload(valid, {1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_NE(error.find("does not start with a zstd frame header"), std::string::npos) << error;

  error = decode_error(with_payload(valid, zstd_frame(false, 0, 2187)));
  EXPECT_NE(error.find("does not declare its content size"), std::string::npos) << error;

  // Declares the right size but holds fewer bytes.
  error = decode_error(with_payload(valid, zstd_frame(true, 2187, 2000)));
  EXPECT_NE(error.find("zstd decompression failed"), std::string::npos) << error;

  // A well-formed frame with the right size and the wrong samples.
  error = decode_error(with_payload(valid, zstd_frame(true, 2187, 2187)));
  EXPECT_NE(error.find("checksum mismatch"), std::string::npos) << error;
}

TEST(DecodeBrick, RejectsBytesAfterTheZstdFrame) {
  const std::vector<uint8_t> valid = valid_brick(Codec::zstd, 8, 3);
  std::vector<uint8_t> payload = payload_of(valid);
  // A skippable frame (magic 0x184D2A50, 4 bytes of content) that zstd itself would ignore.
  for (uint8_t b : {0x50, 0x2A, 0x4D, 0x18, 0x04, 0x00, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04}) {
    payload.push_back(b);
  }
  const std::string error = decode_error(with_payload(valid, payload));
  EXPECT_NE(error.find("zstd payload holds 12 bytes after its frame"), std::string::npos) << error;
}

TEST(DecodeBrick, RejectsCorruptLz4Streams) {
  const std::vector<uint8_t> valid = valid_brick(Codec::lz4);
  const std::string error = decode_error(with_payload(valid, {0xF0, 0xFF, 0xFF, 0xFF}));
  EXPECT_NE(error.find("lz4 decompression failed"), std::string::npos) << error;
}

// A flipped payload byte is either caught, or harmless: an lz4 match offset or a zstd bit that
// happens to yield the same samples. Whatever decodes must be the original brick.
TEST(DecodeBrick, DetectsEveryHarmfulFlippedPayloadByte) {
  for (Codec codec : {Codec::raw, Codec::lz4, Codec::zstd}) {
    const std::vector<uint8_t> planes = real_brick(MarbleParams{}, 8, 3);
    const std::vector<uint8_t> valid = encode_brick(planes, 8, 3, {codec, 3, true});
    int caught = 0;
    int harmless = 0;
    for (std::size_t i = kBrickHeaderSize; i < valid.size(); ++i) {
      for (uint8_t mask : {0x01, 0x80, 0xFF}) {
        std::vector<uint8_t> encoded = valid;
        encoded[i] ^= mask;
        try {
          ASSERT_EQ(decode_brick(encoded).samples, planes) << codec_name(codec) << " byte " << i;
          ++harmless;
        } catch (const CodecError& e) {
          ++caught;
          EXPECT_TRUE(
              contains_any(e.what(), {"checksum mismatch", "decompression failed",
                                      "decompressed to", "frame declares", "after its frame"}))
              << codec_name(codec) << " byte " << i << ": " << e.what();
        }
      }
    }
    if (codec == Codec::raw) {
      EXPECT_EQ(harmless, 0);
    }
    EXPECT_GT(caught, 20 * harmless) << codec_name(codec);
  }
}

TEST(DecodeBrick, DetectsAFlippedChecksum) {
  for (std::size_t i = 20; i < 28; ++i) {
    std::vector<uint8_t> encoded = valid_brick(Codec::zstd);
    encoded[i] ^= 0x04;
    const std::string error = decode_error(encoded);
    EXPECT_NE(error.find("checksum mismatch: the header says 0x"), std::string::npos) << error;
  }
}

TEST(DecodeBrick, ErrorsAreRuntimeErrors) {
  EXPECT_THROW(decode_brick({}), std::runtime_error);
}

}  // namespace
}  // namespace soltex
