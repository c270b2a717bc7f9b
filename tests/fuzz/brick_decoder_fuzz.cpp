// libFuzzer target for decode_brick: any input either decodes or throws CodecError, without a
// crash, a sanitizer report or an out-of-bounds allocation. What decodes must survive a round
// trip through the encoder with the codec and filter its header named.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "soltex/common/brick_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::span<const uint8_t> input(data, size);
  soltex::DecodedBrick brick;
  try {
    brick = soltex::decode_brick(input);
  } catch (const soltex::CodecError&) {
    return 0;
  }
  if (brick.samples.size() != soltex::brick_decoded_size(brick.brick_size, brick.channels)) {
    std::abort();
  }
  // A successful decode validated these header bytes.
  soltex::CodecOptions options;
  options.codec = static_cast<soltex::Codec>(input[7]);
  const auto filter = static_cast<soltex::BrickFilter>(input[8]);
  const soltex::DecodedBrick again = soltex::decode_brick(
      soltex::encode_brick(brick.samples, brick.brick_size, brick.channels, options, filter));
  if (again.brick_size != brick.brick_size || again.channels != brick.channels ||
      again.samples != brick.samples) {
    std::abort();
  }
  return 0;
}
