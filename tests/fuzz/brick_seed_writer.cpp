// Writes valid encoded bricks into a directory, as the starting corpus of brick_decoder_fuzz:
// both brick sizes, 1, 3 and 5 channels, every codec and every filter, over fields shaped like
// the textures' (smooth ramps, bands with hard edges, hashed noise).
//
//   brick_seed_writer <corpus-dir>
//
// It needs only the codec, not the texture evaluator, so it builds wherever the fuzz target
// does.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "seed_file.h"
#include "soltex/common/brick_codec.h"

namespace {

struct SeedField {
  const char* name;
  float (*value)(int x, int y, int z, int channel);
};

float ramp(int x, int y, int z, int channel) {
  return static_cast<float>(x + 2 * y + 3 * z + 5 * channel) / 120.0f;
}

float bands(int x, int y, int z, int channel) {
  const float band = std::sin(0.7f * static_cast<float>(x) + 0.3f * static_cast<float>(y + z));
  return band > 0.2f ? 0.9f - 0.1f * static_cast<float>(channel) : 0.1f;
}

float noise(int x, int y, int z, int channel) {
  uint32_t h = static_cast<uint32_t>(x * 73856093) ^ static_cast<uint32_t>(y * 19349663) ^
               static_cast<uint32_t>(z * 83492791) ^ static_cast<uint32_t>(channel * 2654435761u);
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 0xFFFF) / 65535.0f;
}

std::vector<uint8_t> field_samples(const SeedField& field, int brick_size, int channels) {
  const int side = brick_size + 1;
  std::vector<float> samples;
  samples.reserve(soltex::brick_decoded_size(brick_size, channels));
  for (int c = 0; c < channels; ++c) {
    for (int z = 0; z < side; ++z) {
      for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) samples.push_back(field.value(x, y, z, c));
      }
    }
  }
  return soltex::quantize(samples);
}

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(argc, argv, {"corpus-dir"}, [](const auto& dirs) {
    const std::filesystem::path& dir = dirs[0];
    const SeedField fields[] = {{"ramp", ramp}, {"bands", bands}, {"noise", noise}};
    const soltex::BrickFilter filters[] = {soltex::BrickFilter::none, soltex::BrickFilter::delta_x,
                                           soltex::BrickFilter::gradient_xy,
                                           soltex::BrickFilter::gradient_3d};
    int written = 0;
    for (const SeedField& field : fields) {
      for (int brick_size : {8, 16}) {
        for (int channels : {1, 3, 5}) {
          const std::vector<uint8_t> samples = field_samples(field, brick_size, channels);
          for (soltex::Codec codec :
               {soltex::Codec::raw, soltex::Codec::lz4, soltex::Codec::zstd}) {
            // Filters rotate with brick size and channel count: each one appears under every
            // codec while the corpus stays small.
            const soltex::BrickFilter filter = filters[(brick_size / 8 + channels) % 4];
            const std::string name = std::string("seed-") + field.name + "-b" +
                                     std::to_string(brick_size) + "-c" + std::to_string(channels) +
                                     "-" + soltex::codec_name(codec) + "-" +
                                     soltex::brick_filter_name(filter);
            soltex::CodecOptions options;
            options.codec = codec;
            const std::vector<uint8_t> encoded =
                soltex::encode_brick(samples, brick_size, channels, options, filter);
            soltex::fuzz::write_seed_file(
                dir / name,
                std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
            ++written;
          }
        }
      }
    }
    std::printf("wrote %d seed bricks to %s\n", written, dir.c_str());
  });
}
