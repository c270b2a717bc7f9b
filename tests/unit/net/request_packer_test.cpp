#include "soltex/net/request_packer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace soltex::net {
namespace {

v1::BrickKey key(int i) {
  v1::BrickKey k;
  k.set_texture_id(0x0123456789abcdefULL);
  k.set_level(static_cast<uint32_t>(i % 5));
  k.set_x(i);
  k.set_y(-i);
  k.set_z(i * 1000);
  return k;
}

std::string texture_of(std::size_t bytes) {
  v1::RegisterTextureRequest texture;
  texture.set_brick_size(16);
  texture.mutable_spec()->mutable_graph()->add_nodes()->set_name(std::string(bytes, 'n'));
  return texture.SerializeAsString();
}

// What the messages carry, in order, as one list of wants' x coordinates (cancels negated).
std::vector<int> keys_in_order(const std::vector<v1::BrickRequest>& messages) {
  std::vector<int> keys;
  for (const v1::BrickRequest& m : messages) {
    for (const v1::BrickKey& k : m.cancel()) keys.push_back(-k.x() - 1);
    for (const v1::BrickWant& w : m.want()) keys.push_back(w.key().x());
  }
  return keys;
}

TEST(RequestPacker, EveryMessageFitsTheBoundsAndNothingIsLostOrReordered) {
  for (const RequestBounds bounds : {RequestBounds{1024, 16}, RequestBounds{200, 1000},
                                     RequestBounds{4u << 20, 7}, RequestBounds{64, 1}}) {
    RequestPacker packer(bounds);
    std::vector<int> expected;
    ASSERT_TRUE(packer.add_texture(texture_of(30)));
    packer.add_codec(v1::CODEC_ZSTD);
    for (int i = 0; i < 20; ++i) {
      packer.add_cancel(key(i));
      expected.push_back(-i - 1);
    }
    for (int i = 0; i < 300; ++i) {
      packer.add_want(key(i), i * 7919);
      expected.push_back(i);
    }
    const std::vector<v1::BrickRequest> messages = packer.take();
    ASSERT_FALSE(messages.empty());
    for (const v1::BrickRequest& m : messages) {
      EXPECT_LE(m.ByteSizeLong(), bounds.max_bytes) << bounds.max_bytes;
      EXPECT_LE(static_cast<std::size_t>(m.want_size()), bounds.max_wants);
      EXPECT_GT(m.ByteSizeLong(), 0u);
    }
    EXPECT_EQ(keys_in_order(messages), expected);
    // The texture and the codec come first, before any want that may name the texture.
    EXPECT_EQ(messages.front().textures_size(), 1);
    EXPECT_EQ(messages.front().accept_codecs_size(), 1);
    EXPECT_TRUE(packer.take().empty());
  }
}

TEST(RequestPacker, OneMessageWhenEverythingFits) {
  RequestPacker packer({});
  ASSERT_TRUE(packer.add_texture(texture_of(100)));
  for (int i = 0; i < 256; ++i) packer.add_want(key(i), i);
  const std::vector<v1::BrickRequest> messages = packer.take();
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_EQ(messages[0].want_size(), 256);
  // The packer's count is protobuf's: a message as full as the bound is allowed still fits.
  RequestPacker exact({messages[0].ByteSizeLong(), 1024});
  ASSERT_TRUE(exact.add_texture(texture_of(100)));
  for (int i = 0; i < 256; ++i) exact.add_want(key(i), i);
  EXPECT_EQ(exact.take().size(), 1u);
}

TEST(RequestPacker, ATextureLargerThanAMessageIsRefusedAndTheRestGoes) {
  RequestPacker packer({512, 16});
  EXPECT_FALSE(packer.add_texture(texture_of(600)));
  EXPECT_TRUE(packer.add_texture(texture_of(480)));
  packer.add_want(key(1), 1);
  const std::vector<v1::BrickRequest> messages = packer.take();
  ASSERT_EQ(messages.size(), 2u);  // the 480-byte texture leaves no room for the want
  EXPECT_EQ(messages[0].textures_size(), 1);
  EXPECT_EQ(messages[1].want_size(), 1);
}

TEST(RequestPacker, NothingAddedMeansNoMessage) {
  RequestPacker packer({});
  EXPECT_TRUE(packer.take().empty());
}

}  // namespace
}  // namespace soltex::net
