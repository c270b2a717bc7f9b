#pragma once

#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex::server {

// A texture the server can evaluate bricks of. Immutable once registered, shared by every
// stream and worker that uses it.
struct RegisteredTexture {
  uint64_t id;
  TextureEvaluator evaluator;
  BrickLayout layout;
  MipSettings mip;
};

using TexturePtr = std::shared_ptr<const RegisteredTexture>;

// The largest supersampling factor a texture may be registered with.
inline constexpr int kMaxSupersample = 4;

// Why a registration was refused.
enum class RegistryRefusal { full, client_quota };

class RegistryFull : public std::runtime_error {
 public:
  RegistryFull(RegistryRefusal reason, const std::string& message)
      : std::runtime_error(message), reason_(reason) {}
  RegistryRefusal reason() const { return reason_; }

 private:
  RegistryRefusal reason_;
};

struct RegistryLimits {
  std::size_t max_bytes = 8u << 20;
  std::size_t max_textures = 16384;
  std::size_t max_textures_per_client = 1024;
};

struct RegistryStats {
  std::size_t textures = 0;
  std::size_t pinned = 0;  // in use by an open stream
  std::size_t bytes = 0;
  std::size_t max_bytes = 0;
  uint64_t evicted = 0;
  uint64_t refused_full = 0;
  uint64_t refused_client_quota = 0;
};

class TextureRegistry;

// Keeps one texture in the registry while held (a stream holds one per texture it uses).
// Movable; an empty pin holds nothing.
class TexturePin {
 public:
  TexturePin() = default;
  TexturePin(TextureRegistry* registry, TexturePtr texture)
      : registry_(registry), texture_(std::move(texture)) {}
  TexturePin(TexturePin&& other) noexcept { *this = std::move(other); }
  TexturePin& operator=(TexturePin&& other) noexcept;
  TexturePin(const TexturePin&) = delete;
  TexturePin& operator=(const TexturePin&) = delete;
  ~TexturePin() { reset(); }

  void reset();
  const TexturePtr& texture() const { return texture_; }
  explicit operator bool() const { return texture_ != nullptr; }

 private:
  TextureRegistry* registry_ = nullptr;
  TexturePtr texture_;
};

// Content-addressed: registering the same texture twice returns the first entry, whoever
// registers it. Bounded by an estimate of its memory and by a count; when a new texture does
// not fit, the least recently used textures that no open stream uses (none pinned) are
// evicted. A texture evicted is simply registered again, under the same id. Each client
// (identity) may own at most max_textures_per_client textures: beyond that its own least
// recently used unpinned texture makes room, so a client registering in a loop churns its
// own share and nobody else's.
class TextureRegistry {
 public:
  explicit TextureRegistry(RegistryLimits limits) : limits_(limits) {}

  // Validates (throws SpecError naming the field) and registers for `client`, or finds the
  // same texture registered before; throws RegistryFull when every texture that could make
  // room is pinned. The texture comes pinned (before anything else could evict it): a caller
  // that does not use it lets go of the pin, which leaves it the most recently used.
  // `check`, when given, sees the texture before it is registered and may refuse it by
  // throwing, which leaves the registry as it was.
  using Check = std::function<void(const RegisteredTexture&)>;
  TexturePin register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                              const MipSettings& mip, const std::string& client,
                              const Check& check = {});

  // A pin on the texture, or an empty pin when it is not registered (or was evicted).
  TexturePin pin(uint64_t id);

  TexturePtr find(uint64_t id) const;
  std::size_t size() const;
  RegistryStats stats() const;

  // The memory a registered texture is charged with.
  static std::size_t charge_of(const RegisteredTexture& texture, const std::string& owner);

 private:
  friend class TexturePin;
  using LruList = std::list<uint64_t>;  // front: most recently used
  struct Entry {
    TexturePtr texture;
    std::string owner;
    std::size_t bytes = 0;
    uint32_t pins = 0;
    LruList::iterator in_all;    // valid while pins == 0
    LruList::iterator in_owner;  // valid while pins == 0
  };
  struct Owner {
    std::size_t owned = 0;
    LruList unpinned;
  };

  // All below: mutex_ held.
  void unpin(uint64_t id);
  void make_unpinned(uint64_t id, Entry& entry);  // enters the LRU lists at the front
  void make_pinned(Entry& entry);                 // leaves them
  void evict(uint64_t id);
  void make_room_for(const std::string& client, std::size_t bytes);
  [[noreturn]] void refuse(RegistryRefusal reason, const std::string& message);

  const RegistryLimits limits_;
  mutable std::mutex mutex_;
  std::unordered_map<uint64_t, Entry> textures_;
  std::unordered_map<std::string, Owner> owners_;
  LruList unpinned_;
  std::size_t bytes_ = 0;
  uint64_t evicted_ = 0;
  uint64_t refused_full_ = 0;
  uint64_t refused_client_quota_ = 0;
};

}  // namespace soltex::server
