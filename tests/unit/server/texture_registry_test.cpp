#include "texture_registry.h"

#include <gtest/gtest.h>

#include <vector>

namespace soltex::server {
namespace {

// Distinct textures by stripe width, as a client registering in a loop would make them.
TexturePin add(TextureRegistry& registry, int i, const std::string& client) {
  TextureSpec spec;
  spec.pattern = StripesParams{.width = 1.0 + i * 1e-3};
  return registry.register_texture(spec, Volume{}, 16, MipSettings{}, client);
}

// Texture i's id, from a registry of its own (content-addressed: the same everywhere).
uint64_t id_of(int i) {
  TextureRegistry scratch({std::size_t{1} << 20, 1, 1});
  return add(scratch, i, "probe").texture()->id;
}

RegistryLimits count_limits(std::size_t total, std::size_t per_client) {
  return {std::size_t{1} << 30, total, per_client};
}

TEST(TextureRegistry, RegistrationIsIdempotentAndContentAddressed) {
  TextureRegistry registry(count_limits(8, 8));
  const uint64_t first = add(registry, 1, "a").texture()->id;
  EXPECT_EQ(add(registry, 1, "b").texture()->id, first);  // another client, the same texture
  EXPECT_NE(add(registry, 2, "a").texture()->id, first);
  EXPECT_EQ(registry.size(), 2u);
}

TEST(TextureRegistry, AClientFillingItCannotRefuseAnotherClientsTexture) {
  TextureRegistry registry(count_limits(16, 1000));
  for (int i = 0; i < 992; ++i) add(registry, i, "flood");
  EXPECT_EQ(registry.size(), 16u);
  EXPECT_NO_THROW(add(registry, 5000, "other"));
  const RegistryStats stats = registry.stats();
  EXPECT_EQ(stats.evicted, 992u + 1 - 16);
  EXPECT_EQ(stats.refused_full, 0u);
}

TEST(TextureRegistry, TheLeastRecentlyUsedUnpinnedTextureGoesFirst) {
  TextureRegistry registry(count_limits(3, 10));
  TexturePin held = add(registry, 0, "a");  // pinned: a stream uses it
  add(registry, 1, "a");
  add(registry, 2, "a");
  EXPECT_TRUE(registry.pin(id_of(1)));  // 1 used again (and let go): 2 is now the oldest
  add(registry, 3, "a");
  EXPECT_TRUE(registry.find(held.texture()->id));
  EXPECT_TRUE(registry.find(id_of(1)));
  EXPECT_FALSE(registry.find(id_of(2)));
  EXPECT_FALSE(registry.pin(id_of(2)));
  EXPECT_EQ(registry.stats().evicted, 1u);
  // An evicted texture is simply registered again, under the same id.
  EXPECT_EQ(add(registry, 2, "a").texture()->id, id_of(2));
}

TEST(TextureRegistry, RefusedOnlyWhenEveryTextureIsInUse) {
  TextureRegistry registry(count_limits(2, 10));
  std::vector<TexturePin> held;
  held.push_back(add(registry, 0, "a"));
  held.push_back(add(registry, 1, "b"));
  try {
    add(registry, 2, "c");
    FAIL() << "registered beyond a registry of pinned textures";
  } catch (const RegistryFull& e) {
    EXPECT_EQ(e.reason(), RegistryRefusal::full);
    EXPECT_NE(std::string(e.what()).find("2 textures (max_textures)"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(registry.stats().refused_full, 1u);
  EXPECT_EQ(registry.stats().pinned, 2u);
  held.pop_back();  // the stream using it ended
  EXPECT_NO_THROW(add(registry, 2, "c"));
}

TEST(TextureRegistry, AClientOverItsQuotaEvictsItsOwnTexturesFirst) {
  TextureRegistry registry(count_limits(100, 3));
  const TexturePin others = add(registry, 100, "other");
  const uint64_t others_unpinned = add(registry, 101, "other").texture()->id;
  for (int i = 0; i < 50; ++i) add(registry, i, "flood");
  EXPECT_TRUE(registry.find(others_unpinned));  // untouched although the least recently used
  EXPECT_EQ(registry.size(), 2u + 3u);

  // With all of its quota in use by its streams, the client is refused; nobody else is.
  std::vector<TexturePin> held;
  for (int i = 200; i < 203; ++i) held.push_back(add(registry, i, "greedy"));
  try {
    add(registry, 203, "greedy");
    FAIL() << "registered beyond the client's quota";
  } catch (const RegistryFull& e) {
    EXPECT_EQ(e.reason(), RegistryRefusal::client_quota);
    EXPECT_NE(std::string(e.what()).find("client greedy"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("max_textures_per_client"), std::string::npos);
  }
  EXPECT_NO_THROW(add(registry, 300, "other"));
  EXPECT_EQ(registry.stats().refused_client_quota, 1u);
}

TEST(TextureRegistry, TheMemoryBoundHoldsWhateverTheCount) {
  TextureRegistry unbounded(count_limits(1000, 1000));
  const std::size_t each = TextureRegistry::charge_of(*add(unbounded, 0, "a").texture(), "a");
  TextureRegistry registry({each * 10 + each / 2, 1000, 1000});
  for (int i = 0; i < 40; ++i) add(registry, i, "a");
  const RegistryStats stats = registry.stats();
  EXPECT_EQ(stats.textures, 10u);
  EXPECT_LE(stats.bytes, stats.max_bytes);
  EXPECT_EQ(stats.evicted, 30u);
}

}  // namespace
}  // namespace soltex::server
