// soltex-bench's codec choices encode bricks as soltexd does: the 3D predictor before a
// compressor, none before raw (the client would only undo it).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "accuracy_setting.h"
#include "soltex/common/brick_codec.h"

namespace soltex::bench {
namespace {

constexpr int kBrickSize = 8;
constexpr std::size_t kFilterByte = 8;  // the header's filter field

std::vector<uint8_t> ramp_planes() {
  std::vector<uint8_t> planes(brick_decoded_size(kBrickSize, 1));
  for (std::size_t i = 0; i < planes.size(); ++i) planes[i] = static_cast<uint8_t>(i * 7);
  return planes;
}

TEST(CodecChoice, RawCarriesTheSamplesThemselves) {
  const std::vector<uint8_t> planes = ramp_planes();
  const CodecChoice raw{Codec::raw, 1};
  const std::vector<uint8_t> encoded = encode_brick(planes, kBrickSize, 1, raw.options());
  ASSERT_EQ(encoded.size(), kBrickHeaderSize + planes.size());
  EXPECT_EQ(encoded[kFilterByte], static_cast<uint8_t>(BrickFilter::none));
  EXPECT_EQ(std::vector<uint8_t>(encoded.begin() + kBrickHeaderSize, encoded.end()), planes);
}

TEST(CodecChoice, CompressorsRunThePredictorFirst) {
  const std::vector<uint8_t> planes = ramp_planes();
  for (const CodecChoice choice :
       {CodecChoice{Codec::lz4, 1}, CodecChoice{Codec::zstd, 1}, CodecChoice{Codec::zstd, 3}}) {
    const std::vector<uint8_t> encoded = encode_brick(planes, kBrickSize, 1, choice.options());
    ASSERT_GT(encoded.size(), kBrickHeaderSize) << choice.name();
    EXPECT_EQ(encoded[kFilterByte], static_cast<uint8_t>(kBrickCodecFilter)) << choice.name();
    EXPECT_EQ(decode_brick(encoded).samples, planes) << choice.name();
  }
}

}  // namespace
}  // namespace soltex::bench
