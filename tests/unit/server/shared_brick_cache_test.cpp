#include "shared_brick_cache.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace soltex::server {
namespace {

TEST(SharedBrickCache, KeysNameTextureLevelBrickAndCodec) {
  const BrickKey key{0x0123456789abcdefULL, 3, {-1, 2, 30}};
  EXPECT_EQ(SharedBrickCache::key_of(key, Codec::zstd),
            "soltex1:0123456789abcdef:3:-1:2:30:2");  // the codec's number in brick headers
  EXPECT_NE(SharedBrickCache::key_of(key, Codec::zstd), SharedBrickCache::key_of(key, Codec::lz4));
  // memcached keys: at most 250 bytes, no spaces or control characters.
  const std::string longest = SharedBrickCache::key_of(
      {~0ULL, 99, {-2147483647 - 1, -2147483647 - 1, -2147483647 - 1}}, Codec::raw);
  EXPECT_LE(longest.size(), 250u);
  EXPECT_EQ(longest.find(' '), std::string::npos);
}

TEST(SharedBrickCache, RefusesAddressesThatDoNotParse) {
  EXPECT_THROW(SharedBrickCache(SharedCacheConfig{}), std::invalid_argument);
  EXPECT_THROW(SharedBrickCache(SharedCacheConfig{{"no-port"}}), std::invalid_argument);
  EXPECT_THROW(SharedBrickCache(SharedCacheConfig{{"127.0.0.1:0"}}), std::invalid_argument);
  EXPECT_THROW(SharedBrickCache(SharedCacheConfig{{"127.0.0.1:99999"}}), std::invalid_argument);
}

}  // namespace
}  // namespace soltex::server
