// Writes serialized BrickBatch messages into a directory, as the starting corpus of
// brick_batch_reader_fuzz: bricks of several codecs and key shapes (negative and extreme
// coordinates, a zero texture id), per-brick errors and request errors, and an empty message.
//
//   brick_batch_seed_writer <corpus-dir>

#include <string>

#include "seed_file.h"
#include "soltex/v1/brick_service.pb.h"

namespace {

namespace v1 = soltex::v1;

void set_key(v1::BrickKey* key, uint64_t texture, uint32_t level, int32_t x, int32_t y, int32_t z) {
  key->set_texture_id(texture);
  key->set_level(level);
  key->set_x(x);
  key->set_y(y);
  key->set_z(z);
}

void add_brick(v1::BrickBatch& batch, uint64_t texture, int32_t x, v1::Codec codec,
               std::size_t payload_size) {
  v1::Brick* brick = batch.add_bricks();
  set_key(brick->mutable_key(), texture, 2, x, -x, 7);
  brick->set_codec(codec);
  brick->set_payload(std::string(payload_size, static_cast<char>('A' + payload_size % 26)));
  brick->set_checksum(0x9E3779B97F4A7C15ULL * payload_size);
}

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(argc, argv, {"corpus-dir"}, [](const auto& dirs) {
    int n = 0;
    const auto write = [&](const v1::BrickBatch& batch) {
      soltex::fuzz::write_seed_file(dirs[0] / ("batch-" + std::to_string(n++)),
                                    batch.SerializeAsString());
    };
    write(v1::BrickBatch());
    v1::BrickBatch bricks;
    add_brick(bricks, 0xC3C07909A758B5B2ULL, 0, v1::CODEC_ZSTD, 40);
    add_brick(bricks, 1, -1, v1::CODEC_LZ4, 200);
    add_brick(bricks, 0, 2147483647, v1::CODEC_RAW, 30);
    write(bricks);
    v1::BrickBatch errors;
    v1::BrickError* error = errors.add_errors();
    set_key(error->mutable_key(), 5, 9, -2147483647 - 1, 0, 3);
    error->set_code(11);
    error->set_message("brick (0, 0, 3) level 9: level is outside [0, 4]");
    errors.add_request_errors()->set_code(8);
    errors.mutable_request_errors(0)->set_message("request wants 2000 bricks");
    write(errors);
    v1::BrickBatch both = bricks;
    both.MergeFrom(errors);
    write(both);
  });
}
