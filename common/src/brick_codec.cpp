#include "soltex/common/brick_codec.h"

#include <lz4.h>
#include <xxhash.h>
// ZSTD_c_literalCompressionMode is in zstd's experimental section (Debian's libzstd 1.5.4
// exports it; the parameter is checked at run time).
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <new>

#include "soltex/common/brick_layout.h"

namespace soltex {
namespace {

constexpr std::size_t kVersionOffset = 4;
constexpr std::size_t kBrickSizeOffset = 5;
constexpr std::size_t kChannelsOffset = 6;
constexpr std::size_t kCodecOffset = 7;
constexpr std::size_t kFilterOffset = 8;
constexpr std::size_t kReservedOffset = 9;
constexpr std::size_t kReservedSize = 3;
constexpr std::size_t kDecodedSizeOffset = 12;
constexpr std::size_t kPayloadSizeOffset = 16;
constexpr std::size_t kChecksumOffset = 20;
static_assert(kChecksumOffset + 8 == kBrickHeaderSize);

constexpr uint8_t kMaxCodecId = static_cast<uint8_t>(Codec::zstd);

void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t get_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(p[i]) << (8 * i);
  return v;
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}

std::string hex(uint64_t v) {
  char text[19];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(v));
  return text;
}

uint64_t checksum(std::span<const uint8_t> samples) {
  return XXH64(samples.data(), samples.size(), 0);
}

[[noreturn]] void fail(const std::string& what) {
  throw CodecError("encoded brick: " + what);
}

// zstd contexts hold their tables between calls; one per thread keeps encode and decode free of
// per-brick allocation.
struct ZstdContextFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

ZSTD_CCtx* thread_compressor() {
  thread_local std::unique_ptr<ZSTD_CCtx, ZstdContextFree> context(ZSTD_createCCtx());
  if (!context) throw std::bad_alloc();
  return context.get();
}

ZSTD_DCtx* thread_decompressor() {
  thread_local std::unique_ptr<ZSTD_DCtx, ZstdContextFree> context(ZSTD_createDCtx());
  if (!context) throw std::bad_alloc();
  return context.get();
}

void set_zstd_parameter(ZSTD_CCtx* context, ZSTD_cParameter parameter, int value) {
  const std::size_t result = ZSTD_CCtx_setParameter(context, parameter, value);
  if (ZSTD_isError(result)) {
    throw std::runtime_error(std::string("encode_brick: zstd parameter ") +
                             std::to_string(static_cast<int>(parameter)) + " = " +
                             std::to_string(value) + " refused: " + ZSTD_getErrorName(result));
  }
}

void check_shape(int brick_size, int channels) {
  if (brick_size != kMinBrickSize && brick_size != kMaxBrickSize) {
    throw std::invalid_argument("encode_brick: brick_size = " + std::to_string(brick_size) +
                                " must be 8 or 16");
  }
  if (channels < 1 || channels > kMaxBrickChannels) {
    throw std::invalid_argument("encode_brick: channels = " + std::to_string(channels) +
                                " must be in [1, " + std::to_string(kMaxBrickChannels) + "]");
  }
}

// Whether a predicted brick is mostly runs of one byte value (a smooth pattern's zero
// residuals), from one probe every 64 bytes: four equal bytes in a row.
bool mostly_runs(std::span<const uint8_t> input) {
  constexpr std::size_t kStride = 64;
  std::size_t probes = 0, runs = 0;
  for (std::size_t i = 0; i + 4 <= input.size(); i += kStride) {
    ++probes;
    runs += input[i] == input[i + 1] && input[i] == input[i + 2] && input[i] == input[i + 3];
  }
  return 3 * runs >= 2 * probes;
}

std::size_t compress_zstd(int zstd_level, std::span<const uint8_t> input, uint8_t* out,
                          std::size_t capacity) {
  ZSTD_CCtx* context = thread_compressor();
  // ZSTD_compressSequences leaves the context past the start of a frame, and some parameters
  // are set only there: the session is reset first, which keeps the frame parameters.
  ZSTD_CCtx_reset(context, ZSTD_reset_session_only);
  // Literals are always entropy coded: after the predictor a brick is mostly literals, and
  // their Huffman coding is most of what zstd gains over lz4 (docs/PERFORMANCE.md, "Brick
  // codec").
  set_zstd_parameter(context, ZSTD_c_compressionLevel, zstd_level);
  set_zstd_parameter(context, ZSTD_c_literalCompressionMode, ZSTD_ps_enable);
  std::size_t written = 0;
  if (zstd_level < 0 && input.size() <= ZSTD_BLOCKSIZE_MAX && !mostly_runs(input)) {
    // A fast level on a noisy brick: the matches a fast search finds cost more bytes than they
    // save, so the brick goes as one block of literals, with no search at all. The same kind of
    // frame; a fifth less CPU.
    set_zstd_parameter(context, ZSTD_c_blockDelimiters, ZSTD_sf_explicitBlockDelimiters);
    const ZSTD_Sequence literals{0, static_cast<unsigned>(input.size()), 0, 0};
    written =
        ZSTD_compressSequences(context, out, capacity, &literals, 1, input.data(), input.size());
  } else {
    written = ZSTD_compress2(context, out, capacity, input.data(), input.size());
  }
  if (ZSTD_isError(written)) {
    throw std::runtime_error(std::string("encode_brick: zstd compression failed: ") +
                             ZSTD_getErrorName(written));
  }
  return written;
}

// Compresses `input` into `out` (capacity `capacity`); returns the bytes written.
std::size_t compress(Codec codec, int zstd_level, std::span<const uint8_t> input, uint8_t* out,
                     std::size_t capacity) {
  switch (codec) {
    case Codec::raw:
      std::memcpy(out, input.data(), input.size());
      return input.size();
    case Codec::lz4: {
      const int written = LZ4_compress_default(
          reinterpret_cast<const char*>(input.data()), reinterpret_cast<char*>(out),
          static_cast<int>(input.size()), static_cast<int>(capacity));
      if (written <= 0) throw std::runtime_error("encode_brick: lz4 compression failed");
      return static_cast<std::size_t>(written);
    }
    case Codec::zstd:
      return compress_zstd(zstd_level, input, out, capacity);
  }
  throw std::invalid_argument("encode_brick: codec id " + std::to_string(static_cast<int>(codec)) +
                              " is unknown");
}

std::size_t compress_bound(Codec codec, std::size_t decoded_size) {
  switch (codec) {
    case Codec::raw:
      return decoded_size;
    case Codec::lz4:
      return static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(decoded_size)));
    case Codec::zstd:
      return ZSTD_compressBound(decoded_size);
  }
  return 0;
}

void decompress(Codec codec, std::span<const uint8_t> payload, std::span<uint8_t> out) {
  const std::size_t bound = compress_bound(codec, out.size());
  if (payload.size() > bound) {
    fail(std::string(codec_name(codec)) + " payload of " + std::to_string(payload.size()) +
         " bytes exceeds the bound of " + std::to_string(bound) + " bytes for a " +
         std::to_string(out.size()) + "-byte brick");
  }
  switch (codec) {
    case Codec::raw:
      if (payload.size() != out.size()) {
        fail("raw payload of " + std::to_string(payload.size()) +
             " bytes must equal the decoded size, " + std::to_string(out.size()) + " bytes");
      }
      std::memcpy(out.data(), payload.data(), out.size());
      return;
    case Codec::lz4: {
      // Sizes fit in int: both are at most the lz4 bound of a largest brick.
      const int written = LZ4_decompress_safe(
          reinterpret_cast<const char*>(payload.data()), reinterpret_cast<char*>(out.data()),
          static_cast<int>(payload.size()), static_cast<int>(out.size()));
      if (written < 0) fail("lz4 decompression failed: the payload is corrupt");
      if (static_cast<std::size_t>(written) != out.size()) {
        fail("lz4 payload decompressed to " + std::to_string(written) + " bytes, expected " +
             std::to_string(out.size()));
      }
      return;
    }
    case Codec::zstd: {
      const unsigned long long declared = ZSTD_getFrameContentSize(payload.data(), payload.size());
      if (declared == ZSTD_CONTENTSIZE_ERROR) {
        fail("zstd decompression failed: the payload does not start with a zstd frame header");
      }
      if (declared == ZSTD_CONTENTSIZE_UNKNOWN) {
        fail("zstd decompression failed: the frame does not declare its content size");
      }
      if (declared != out.size()) {
        fail("zstd frame declares " + std::to_string(declared) + " bytes, expected " +
             std::to_string(out.size()));
      }
      // One frame and nothing after it: trailing (e.g. skippable) frames would be ignored by
      // the decompressor, so a brick would have more than one encoding.
      const std::size_t frame_size = ZSTD_findFrameCompressedSize(payload.data(), payload.size());
      if (ZSTD_isError(frame_size)) {
        fail(std::string("zstd decompression failed: ") + ZSTD_getErrorName(frame_size));
      }
      if (frame_size != payload.size()) {
        fail("zstd payload holds " + std::to_string(payload.size() - frame_size) +
             " bytes after its frame");
      }
      // Exact capacity: a frame that would write more fails instead of growing anything.
      const std::size_t written = ZSTD_decompressDCtx(thread_decompressor(), out.data(), out.size(),
                                                      payload.data(), payload.size());
      if (ZSTD_isError(written)) {
        fail(std::string("zstd decompression failed: ") + ZSTD_getErrorName(written));
      }
      if (written != out.size()) {
        fail("zstd payload decompressed to " + std::to_string(written) + " bytes, expected " +
             std::to_string(out.size()));
      }
      return;
    }
  }
}

}  // namespace

uint8_t quantize(float value) {
  if (!(value > 0.0f)) return 0;  // also NaN
  if (value >= 1.0f) return 255;
  // Exact in double (a float times 255 needs at most 32 significant bits), so this is round
  // half up of the exact product, and the loop over a brick vectorizes where lround would not.
  return static_cast<uint8_t>(static_cast<double>(value) * 255.0 + 0.5);
}

std::vector<uint8_t> quantize(std::span<const float> values) {
  std::vector<uint8_t> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = quantize(values[i]);
  return out;
}

const char* codec_name(Codec codec) {
  switch (codec) {
    case Codec::raw:
      return "raw";
    case Codec::lz4:
      return "lz4";
    case Codec::zstd:
      return "zstd";
  }
  return "unknown";
}

std::size_t brick_decoded_size(int brick_size, int channels) {
  const auto side = static_cast<std::size_t>(brick_size) + 1;
  return side * side * side * static_cast<std::size_t>(channels);
}

std::vector<uint8_t> encode_brick(std::span<const uint8_t> quantized_planes, int brick_size,
                                  int channels, const CodecOptions& options) {
  return encode_brick(quantized_planes, brick_size, channels, options,
                      options.filter ? kBrickCodecFilter : BrickFilter::none);
}

namespace {

void check_encoding(std::size_t samples, int brick_size, int channels,
                    const CodecOptions& options) {
  check_shape(brick_size, channels);
  const std::size_t decoded_size = brick_decoded_size(brick_size, channels);
  if (samples != decoded_size) {
    throw std::invalid_argument("encode_brick: " + std::to_string(samples) +
                                " samples given, a brick of size " + std::to_string(brick_size) +
                                " with " + std::to_string(channels) + " channels has " +
                                std::to_string(decoded_size));
  }
  if (options.codec == Codec::zstd &&
      (options.zstd_level < ZSTD_minCLevel() || options.zstd_level > ZSTD_maxCLevel())) {
    throw std::invalid_argument("encode_brick: zstd_level = " + std::to_string(options.zstd_level) +
                                " must be in [" + std::to_string(ZSTD_minCLevel()) + ", " +
                                std::to_string(ZSTD_maxCLevel()) + "]");
  }
}

// Header and compressed `filtered` at the start of `out`, which grows to the codec's bound
// but never shrinks (shrinking and growing again would zero the bytes between, every brick);
// returns the encoded size. `quantized` is what the checksum covers.
std::size_t write_encoded(std::span<const uint8_t> filtered, std::span<const uint8_t> quantized,
                          int brick_size, int channels, const CodecOptions& options,
                          BrickFilter filter, std::vector<uint8_t>& out) {
  const std::size_t decoded_size = filtered.size();
  const std::size_t bound = kBrickHeaderSize + compress_bound(options.codec, decoded_size);
  if (out.size() < bound) out.resize(bound);
  const std::size_t payload_size =
      compress(options.codec, options.zstd_level, filtered, out.data() + kBrickHeaderSize,
               bound - kBrickHeaderSize);

  uint8_t* header = out.data();
  std::memcpy(header, kBrickMagic, sizeof kBrickMagic);
  header[kVersionOffset] = kBrickFormatVersion;
  header[kBrickSizeOffset] = static_cast<uint8_t>(brick_size);
  header[kChannelsOffset] = static_cast<uint8_t>(channels);
  header[kCodecOffset] = static_cast<uint8_t>(options.codec);
  header[kFilterOffset] = static_cast<uint8_t>(filter);
  std::memset(header + kReservedOffset, 0, kReservedSize);
  put_u32(header + kDecodedSizeOffset, static_cast<uint32_t>(decoded_size));
  put_u32(header + kPayloadSizeOffset, static_cast<uint32_t>(payload_size));
  put_u64(header + kChecksumOffset, checksum(quantized));
  return kBrickHeaderSize + payload_size;
}

}  // namespace

std::vector<uint8_t> encode_brick(std::span<const uint8_t> quantized_planes, int brick_size,
                                  int channels, const CodecOptions& options, BrickFilter filter) {
  check_encoding(quantized_planes.size(), brick_size, channels, options);
  thread_local std::vector<uint8_t> filtered;
  filtered.assign(quantized_planes.begin(), quantized_planes.end());
  apply_brick_filter(filter, brick_size + 1, filtered);
  std::vector<uint8_t> out;
  out.resize(write_encoded(filtered, quantized_planes, brick_size, channels, options, filter, out));
  return out;
}

std::span<const uint8_t> encode_brick_samples(std::span<const float> samples, int brick_size,
                                              int channels, const CodecOptions& options,
                                              std::vector<uint8_t>& out) {
  check_encoding(samples.size(), brick_size, channels, options);
  // Scratch per thread, with the slack the vector kernels write into.
  thread_local std::vector<uint8_t> quantized, filtered;
  quantized.resize(samples.size() + kQuantizePredictSlack);
  const std::span<const uint8_t> planes(quantized.data(), samples.size());
  std::size_t size = 0;
  if (options.filter) {
    static_assert(kBrickCodecFilter == BrickFilter::gradient_3d, "the fused kernel's predictor");
    filtered.resize(samples.size() + kQuantizePredictSlack);
    quantize_and_predict(samples, brick_size + 1, quantized, filtered);
    size = write_encoded(std::span<const uint8_t>(filtered.data(), samples.size()), planes,
                         brick_size, channels, options, kBrickCodecFilter, out);
  } else {
    quantize_values(samples, quantized);
    size = write_encoded(planes, planes, brick_size, channels, options, BrickFilter::none, out);
  }
  return {out.data(), size};
}

std::string encode_brick_samples(std::span<const float> samples, int brick_size, int channels,
                                 const CodecOptions& options) {
  thread_local std::vector<uint8_t> buffer;
  const std::span<const uint8_t> encoded =
      encode_brick_samples(samples, brick_size, channels, options, buffer);
  return std::string(encoded.begin(), encoded.end());
}

DecodedBrick decode_brick(std::span<const uint8_t> encoded) {
  if (encoded.size() < kBrickHeaderSize) {
    fail("truncated header: " + std::to_string(encoded.size()) + " bytes, the header needs " +
         std::to_string(kBrickHeaderSize));
  }
  const uint8_t* header = encoded.data();
  if (std::memcmp(header, kBrickMagic, sizeof kBrickMagic) != 0) {
    fail("bad magic: the first 4 bytes must be \"SLTX\"");
  }
  if (header[kVersionOffset] != kBrickFormatVersion) {
    fail("unsupported format version " + std::to_string(header[kVersionOffset]) +
         ": this decoder reads version " + std::to_string(kBrickFormatVersion));
  }
  const int brick_size = header[kBrickSizeOffset];
  if (brick_size != kMinBrickSize && brick_size != kMaxBrickSize) {
    fail("brick size " + std::to_string(brick_size) + " must be 8 or 16");
  }
  const int channels = header[kChannelsOffset];
  if (channels < 1 || channels > kMaxBrickChannels) {
    fail("channel count " + std::to_string(channels) + " must be in [1, " +
         std::to_string(kMaxBrickChannels) + "]");
  }
  if (header[kCodecOffset] > kMaxCodecId) {
    fail("unknown codec " + std::to_string(header[kCodecOffset]) +
         ": known codecs are 0 (raw), 1 (lz4) and 2 (zstd)");
  }
  const auto codec = static_cast<Codec>(header[kCodecOffset]);
  if (header[kFilterOffset] > kMaxBrickFilterId) {
    fail("unknown filter " + std::to_string(header[kFilterOffset]) + ": filter ids go up to " +
         std::to_string(kMaxBrickFilterId));
  }
  const auto filter = static_cast<BrickFilter>(header[kFilterOffset]);
  for (std::size_t i = 0; i < kReservedSize; ++i) {
    if (header[kReservedOffset + i] != 0) fail("reserved header bytes 9..11 must be zero");
  }
  const std::size_t decoded_size = brick_decoded_size(brick_size, channels);
  const uint32_t declared_size = get_u32(header + kDecodedSizeOffset);
  if (declared_size != decoded_size) {
    fail("declared decoded size " + std::to_string(declared_size) + " does not match (B + 1)^3 * " +
         "channels = " + std::to_string(decoded_size) + " for B = " + std::to_string(brick_size) +
         " and " + std::to_string(channels) + " channels");
  }
  const uint32_t payload_size = get_u32(header + kPayloadSizeOffset);
  const std::size_t remaining = encoded.size() - kBrickHeaderSize;
  if (payload_size != remaining) {
    fail("payload size " + std::to_string(payload_size) + " does not match the " +
         std::to_string(remaining) + " bytes after the header");
  }

  DecodedBrick brick;
  brick.brick_size = brick_size;
  brick.channels = channels;
  brick.samples.resize(decoded_size);
  decompress(codec, encoded.subspan(kBrickHeaderSize), brick.samples);
  undo_brick_filter(filter, brick_size + 1, brick.samples);

  const uint64_t expected = get_u64(header + kChecksumOffset);
  const uint64_t actual = checksum(brick.samples);
  if (actual != expected) {
    fail("checksum mismatch: the header says " + hex(expected) + ", the decoded samples hash to " +
         hex(actual));
  }
  return brick;
}

uint64_t encoded_brick_checksum(std::span<const uint8_t> encoded) {
  if (encoded.size() < kBrickHeaderSize) {
    throw CodecError("encoded brick of " + std::to_string(encoded.size()) +
                     " bytes is shorter than its " + std::to_string(kBrickHeaderSize) +
                     "-byte header");
  }
  return get_u64(encoded.data() + kChecksumOffset);
}

}  // namespace soltex
