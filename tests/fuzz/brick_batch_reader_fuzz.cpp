// libFuzzer target for soltex-load's BrickBatchReader: on any bytes it must return without a
// crash or a sanitizer finding, and wherever libprotobuf parses the bytes as a BrickBatch the
// reader must accept them too and read the same keys, codecs, checksums, payloads and codes.
// (The reader may accept more: it skips an error's message text, which protobuf also checks
// for UTF-8.)

#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "brick_batch_reader.h"
#include "soltex/v1/brick_service.pb.h"

namespace {

using soltex::load::BrickBatchReader;

[[noreturn]] void fail(const char* what, int index) {
  std::fprintf(stderr, "brick_batch_reader_fuzz: %s (entry %d)\n", what, index);
  std::abort();
}

bool same_key(const soltex::BrickKey& key, const soltex::v1::BrickKey& message) {
  return key.texture == message.texture_id() &&
         key.level == static_cast<int32_t>(message.level()) && key.brick.x == message.x() &&
         key.brick.y == message.y() && key.brick.z == message.z();
}

void compare(const BrickBatchReader& reader, const soltex::v1::BrickBatch& batch) {
  if (reader.bricks().size() != static_cast<std::size_t>(batch.bricks_size())) {
    fail("a different number of bricks", -1);
  }
  for (int i = 0; i < batch.bricks_size(); ++i) {
    const BrickBatchReader::Brick& got = reader.bricks()[static_cast<std::size_t>(i)];
    const soltex::v1::Brick& want = batch.bricks(i);
    if (!same_key(got.key, want.key())) fail("a different brick key", i);
    if (got.codec != static_cast<int32_t>(want.codec())) fail("a different codec", i);
    if (got.checksum != want.checksum()) fail("a different checksum", i);
    if (got.payload_size != want.payload().size()) fail("a different payload size", i);
    if (reader.payloads().compare(got.payload_offset, got.payload_size, want.payload()) != 0) {
      fail("a different payload", i);
    }
  }
  if (reader.errors().size() != static_cast<std::size_t>(batch.errors_size())) {
    fail("a different number of errors", -1);
  }
  for (int i = 0; i < batch.errors_size(); ++i) {
    const BrickBatchReader::Error& got = reader.errors()[static_cast<std::size_t>(i)];
    if (!same_key(got.key, batch.errors(i).key())) fail("a different error key", i);
    if (got.code != batch.errors(i).code()) fail("a different error code", i);
  }
  if (reader.request_errors().size() != static_cast<std::size_t>(batch.request_errors_size())) {
    fail("a different number of request errors", -1);
  }
  for (int i = 0; i < batch.request_errors_size(); ++i) {
    if (reader.request_errors()[static_cast<std::size_t>(i)] != batch.request_errors(i).code()) {
      fail("a different request error code", i);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const int length = static_cast<int>(size);
  BrickBatchReader reader;
  {
    // Blocks of 13 bytes: fields straddle the buffers, as in a message gRPC received in parts.
    google::protobuf::io::ArrayInputStream in(data, length, 13);
    (void)reader.read(in, false);
  }
  soltex::v1::BrickBatch batch;
  if (!batch.ParseFromArray(data, length)) return 0;
  google::protobuf::io::ArrayInputStream in(data, length, 13);
  if (!reader.read(in, true)) fail("protobuf parses it, the reader refuses it", -1);
  compare(reader, batch);
  return 0;
}
