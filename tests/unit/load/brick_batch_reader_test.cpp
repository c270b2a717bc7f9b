// BrickBatchReader reads soltex-load's answers without protobuf's message classes; these
// compare it with libprotobuf's own parse of the same bytes.

#include "brick_batch_reader.h"

#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <gtest/gtest.h>

#include <string>

#include "soltex/spec_proto/brick_proto.h"

namespace soltex::load {
namespace {

using google::protobuf::io::ArrayInputStream;

v1::BrickBatch sample_batch() {
  v1::BrickBatch batch;
  const BrickKey keys[] = {{0xC3C07909A758B5B2ULL, 0, {0, 0, 0}},
                           {7, 3, {-1, 2147483647, -2147483647 - 1}},
                           {0, 12, {5, 6, 7}}};
  int n = 0;
  for (const BrickKey& key : keys) {
    v1::Brick* brick = batch.add_bricks();
    *brick->mutable_key() = to_proto(key);
    brick->set_codec(n == 1 ? v1::CODEC_LZ4 : v1::CODEC_ZSTD);
    brick->set_payload(
        std::string(static_cast<std::size_t>(100 + 4000 * n), static_cast<char>('a' + n)));
    brick->set_checksum(0x0123456789ABCDEFULL * static_cast<uint64_t>(n + 1));
    ++n;
  }
  v1::BrickError* error = batch.add_errors();
  *error->mutable_key() = to_proto(BrickKey{9, 1, {-4, 0, 2}});
  error->set_code(11);
  error->set_message("brick (-4, 0, 2) level 1: coordinates must be in [0, 63]");
  batch.add_request_errors()->set_code(8);
  batch.add_request_errors()->set_code(3);
  return batch;
}

void expect_same(const BrickBatchReader& reader, const v1::BrickBatch& batch, bool payloads) {
  ASSERT_EQ(reader.bricks().size(), static_cast<std::size_t>(batch.bricks_size()));
  for (int i = 0; i < batch.bricks_size(); ++i) {
    const BrickBatchReader::Brick& got = reader.bricks()[static_cast<std::size_t>(i)];
    const v1::Brick& want = batch.bricks(i);
    EXPECT_EQ(got.key, from_proto(want.key())) << "brick " << i;
    EXPECT_EQ(got.codec, static_cast<int32_t>(want.codec()));
    EXPECT_EQ(got.checksum, want.checksum());
    EXPECT_EQ(got.payload_size, want.payload().size());
    if (payloads) {
      EXPECT_EQ(reader.payloads().substr(got.payload_offset, got.payload_size), want.payload());
    }
  }
  ASSERT_EQ(reader.errors().size(), static_cast<std::size_t>(batch.errors_size()));
  for (int i = 0; i < batch.errors_size(); ++i) {
    EXPECT_EQ(reader.errors()[static_cast<std::size_t>(i)].key, from_proto(batch.errors(i).key()));
    EXPECT_EQ(reader.errors()[static_cast<std::size_t>(i)].code, batch.errors(i).code());
  }
  ASSERT_EQ(reader.request_errors().size(), static_cast<std::size_t>(batch.request_errors_size()));
  for (int i = 0; i < batch.request_errors_size(); ++i) {
    EXPECT_EQ(reader.request_errors()[static_cast<std::size_t>(i)], batch.request_errors(i).code());
  }
}

TEST(BrickBatchReader, ReadsWhatProtobufWrites) {
  const v1::BrickBatch batch = sample_batch();
  const std::string bytes = batch.SerializeAsString();
  for (const bool payloads : {false, true}) {
    // Small blocks: fields and payloads straddle the buffers a gRPC message arrives in.
    for (const int block : {-1, 1, 7, 1000}) {
      ArrayInputStream in(bytes.data(), static_cast<int>(bytes.size()), block);
      BrickBatchReader reader;
      ASSERT_TRUE(reader.read(in, payloads)) << "block " << block;
      expect_same(reader, batch, payloads);
    }
  }
}

TEST(BrickBatchReader, SkipsFieldsItDoesNotKnow) {
  v1::BrickBatch batch = sample_batch();
  // Unknown fields at each level: a top-level varint, a brick's length-delimited field, a key's
  // fixed32. Written by hand after what protobuf writes, which a parser must accept.
  std::string bytes = batch.SerializeAsString();
  bytes += std::string("\x48\x96\x01", 3);  // field 9, varint 150
  std::string brick = batch.bricks(0).SerializeAsString();
  brick += std::string("\x2A\x03xyz", 5);  // field 5, 3 bytes
  std::string key = batch.bricks(0).key().SerializeAsString();
  key += std::string("\x35\x01\x02\x03\x04", 5);                          // field 6, fixed32
  brick += std::string("\x0A", 1) + static_cast<char>(key.size()) + key;  // key again: merged
  bytes += std::string("\x0A", 1);
  bytes += static_cast<char>(0x80 | (brick.size() & 0x7F));
  bytes += static_cast<char>(brick.size() >> 7);
  bytes += brick;

  v1::BrickBatch parsed;
  ASSERT_TRUE(parsed.ParseFromString(bytes));
  ArrayInputStream in(bytes.data(), static_cast<int>(bytes.size()));
  BrickBatchReader reader;
  ASSERT_TRUE(reader.read(in, true));
  expect_same(reader, parsed, true);
}

TEST(BrickBatchReader, RefusesTruncatedOrMalformedMessages) {
  const std::string bytes = sample_batch().SerializeAsString();
  for (std::size_t cut : {std::size_t{1}, std::size_t{5}, bytes.size() / 2, bytes.size() - 1}) {
    const std::string part = bytes.substr(0, cut);
    v1::BrickBatch parsed;
    ASSERT_FALSE(parsed.ParseFromString(part)) << "cut at " << cut;
    ArrayInputStream in(part.data(), static_cast<int>(part.size()));
    BrickBatchReader reader;
    EXPECT_FALSE(reader.read(in, false)) << "cut at " << cut;
  }
  const std::string bad_length("\x0A\xFF\xFF\xFF\xFF\x0F", 6);  // a brick of 4 GiB
  ArrayInputStream in(bad_length.data(), static_cast<int>(bad_length.size()));
  BrickBatchReader reader;
  EXPECT_FALSE(reader.read(in, false));
}

TEST(BrickBatchReader, AnEmptyMessageHasNothing) {
  ArrayInputStream in("", 0);
  BrickBatchReader reader;
  ASSERT_TRUE(reader.read(in, false));
  EXPECT_TRUE(reader.bricks().empty());
  EXPECT_TRUE(reader.errors().empty());
  EXPECT_TRUE(reader.request_errors().empty());
}

}  // namespace
}  // namespace soltex::load
