// EncodedBrick keeps a brick as its serialized BrickBatch entry; these check that the bytes are
// exactly what libprotobuf writes for the same message, so that a message of such entries is
// a BrickBatch to any client (docs/PROTOCOL.md).

#include "encoded_brick.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "soltex/spec_proto/brick_proto.h"

namespace soltex::server {
namespace {

std::string bytes_of(const grpc::Slice& slice) {
  return {reinterpret_cast<const char*>(slice.begin()), slice.size()};
}

v1::Brick proto_brick(const BrickKey& key, Codec codec, const std::string& payload,
                      uint64_t checksum) {
  v1::Brick brick;
  *brick.mutable_key() = to_proto(key);
  brick.set_codec(to_proto(codec));
  brick.set_payload(payload);
  brick.set_checksum(checksum);
  return brick;
}

struct Case {
  BrickKey key;
  Codec codec;
  std::string payload;
  uint64_t checksum;
};

std::vector<Case> cases() {
  std::string large(70000, '\0');  // a three-byte length
  for (std::size_t i = 0; i < large.size(); ++i) large[i] = static_cast<char>(i * 31 + 7);
  return {
      {BrickKey{0xC3C07909A758B5B2ULL, 0, {0, 0, 0}}, Codec::zstd, std::string(28, 'p'), 1},
      {BrickKey{1, 4, {3, 2, 1}}, Codec::lz4, std::string(300, 'q'), 0xFFFFFFFFFFFFFFFFULL},
      {BrickKey{0, 7, {-1, -2147483647 - 1, 2147483647}}, Codec::raw, large, 0},
      {BrickKey{42, 0, {5, 0, 9}}, Codec::zstd, std::string(), 12345},
  };
}

TEST(EncodedBrick, ElementIsTheBytesProtobufWritesForABatchOfThatBrick) {
  for (const Case& c : cases()) {
    const EncodedBrick brick(c.key, c.codec, c.payload, c.checksum);
    v1::BrickBatch batch;
    *batch.add_bricks() = proto_brick(c.key, c.codec, c.payload, c.checksum);
    EXPECT_EQ(bytes_of(brick.element()), batch.SerializeAsString())
        << "payload of " << c.payload.size() << " bytes";
    EXPECT_EQ(brick.payload(), c.payload);
    EXPECT_EQ(brick.key, c.key);
    EXPECT_EQ(brick.checksum, c.checksum);
  }
}

TEST(EncodedBrick, ElementsSideBySideParseAsOneBatchInOrder) {
  std::string message;
  v1::BrickBatch expected;
  for (const Case& c : cases()) {
    const EncodedBrick brick(c.key, c.codec, c.payload, c.checksum);
    message += bytes_of(brick.element());
    *expected.add_bricks() = proto_brick(c.key, c.codec, c.payload, c.checksum);
  }
  // The errors follow as their own serialized batch, the way the stream writes them.
  v1::BrickBatch errors;
  v1::BrickError* error = errors.add_errors();
  *error->mutable_key() = to_proto(BrickKey{9, 1, {1, 2, 3}});
  error->set_code(11);
  error->set_message("brick (1, 2, 3) level 1: out of range");
  errors.add_request_errors()->set_code(8);
  message += errors.SerializeAsString();
  expected.MergeFrom(errors);

  EXPECT_EQ(message, expected.SerializeAsString());
  v1::BrickBatch parsed;
  ASSERT_TRUE(parsed.ParseFromString(message));
  ASSERT_EQ(parsed.bricks_size(), static_cast<int>(cases().size()));
  EXPECT_EQ(parsed.bricks(2).key().x(), -1);
  EXPECT_EQ(parsed.bricks(2).key().y(), -2147483647 - 1);
  EXPECT_EQ(parsed.errors(0).code(), 11);
  EXPECT_EQ(parsed.request_errors(0).code(), 8);
}

TEST(EncodedBrick, PayloadOffsetPointsAtThePayloadInTheElement) {
  const Case c = cases()[1];
  const EncodedBrick brick(c.key, c.codec, c.payload, c.checksum);
  const std::string element = bytes_of(brick.element());
  EXPECT_EQ(element.substr(brick.payload_offset(), c.payload.size()), c.payload);
}

}  // namespace
}  // namespace soltex::server
