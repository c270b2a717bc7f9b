#include "texture_registry.h"

#include <string>

#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"

namespace soltex::server {
namespace {

// What a registry entry costs beyond the texture itself: the shared_ptr control block, the
// hash node and two list nodes.
constexpr std::size_t kEntryOverhead = 192;

std::string mib(std::size_t bytes) {
  return std::to_string((bytes + (1u << 19)) >> 20) + " MiB";
}

}  // namespace

TexturePin& TexturePin::operator=(TexturePin&& other) noexcept {
  if (this != &other) {
    reset();
    registry_ = other.registry_;
    texture_ = std::move(other.texture_);
    other.registry_ = nullptr;
  }
  return *this;
}

void TexturePin::reset() {
  if (registry_ != nullptr && texture_ != nullptr) {
    std::lock_guard lock(registry_->mutex_);
    registry_->unpin(texture_->id);
  }
  registry_ = nullptr;
  texture_.reset();
}

std::size_t TextureRegistry::charge_of(const RegisteredTexture& texture, const std::string& owner) {
  return sizeof(RegisteredTexture) + kEntryOverhead + owner.capacity() +
         texture.evaluator.spec().ramp.keys.capacity() * sizeof(RampKey);
}

TexturePin TextureRegistry::register_texture(const TextureSpec& spec, const Volume& volume,
                                             int brick_size, const MipSettings& mip,
                                             const std::string& client, const Check& check) {
  if (mip.mode == MipMode::supersampled &&
      (mip.supersample < 1 || mip.supersample > kMaxSupersample)) {
    throw SpecError("supersample", std::to_string(mip.supersample),
                    "must be in [1, " + std::to_string(kMaxSupersample) + "]");
  }
  // Validation and id computation happen outside the lock: they may throw and take time.
  auto texture = std::make_shared<const RegisteredTexture>(
      RegisteredTexture{texture_id(spec, volume, brick_size, mip), TextureEvaluator(spec),
                        BrickLayout(volume, brick_size), mip});
  if (check) check(*texture);
  const std::size_t bytes = charge_of(*texture, client);
  std::lock_guard lock(mutex_);
  if (auto it = textures_.find(texture->id); it != textures_.end()) {
    make_pinned(it->second);
    return {this, it->second.texture};
  }
  make_room_for(client, bytes);
  Entry& entry = textures_[texture->id];
  entry.texture = texture;
  entry.owner = client;
  entry.bytes = bytes;
  entry.pins = 1;
  bytes_ += bytes;
  ++owners_[client].owned;
  return {this, std::move(texture)};
}

void TextureRegistry::make_room_for(const std::string& client, std::size_t bytes) {
  if (const auto owner = owners_.find(client);
      owner != owners_.end() && owner->second.owned >= limits_.max_textures_per_client) {
    if (owner->second.unpinned.empty()) {
      refuse(RegistryRefusal::client_quota,
             "client " + client + " has registered " + std::to_string(owner->second.owned) +
                 " textures, every one in use by its open streams; at most " +
                 std::to_string(limits_.max_textures_per_client) +
                 " per client (max_textures_per_client)");
    }
    evict(owner->second.unpinned.back());  // the client's own least recently used
  }
  while (bytes_ + bytes > limits_.max_bytes || textures_.size() + 1 > limits_.max_textures) {
    if (unpinned_.empty()) {
      refuse(RegistryRefusal::full,
             "texture registry is full: " + std::to_string(textures_.size()) + " textures (" +
                 mib(bytes_) + "), every one in use by an open stream; the bounds are " +
                 std::to_string(limits_.max_textures) + " textures (max_textures) and " +
                 mib(limits_.max_bytes) + " (registry_mb)");
    }
    evict(unpinned_.back());
  }
}

void TextureRegistry::refuse(RegistryRefusal reason, const std::string& message) {
  ++(reason == RegistryRefusal::full ? refused_full_ : refused_client_quota_);
  throw RegistryFull(reason, message);
}

void TextureRegistry::evict(uint64_t id) {
  const auto it = textures_.find(id);
  Entry& entry = it->second;
  auto owner = owners_.find(entry.owner);
  owner->second.unpinned.erase(entry.in_owner);
  if (--owner->second.owned == 0) owners_.erase(owner);
  unpinned_.erase(entry.in_all);
  bytes_ -= entry.bytes;
  ++evicted_;
  textures_.erase(it);  // workers still making its bricks hold their own reference
}

void TextureRegistry::make_pinned(Entry& entry) {
  if (entry.pins++ > 0) return;
  unpinned_.erase(entry.in_all);
  owners_[entry.owner].unpinned.erase(entry.in_owner);
}

void TextureRegistry::make_unpinned(uint64_t id, Entry& entry) {
  unpinned_.push_front(id);
  entry.in_all = unpinned_.begin();
  LruList& own = owners_[entry.owner].unpinned;
  own.push_front(id);
  entry.in_owner = own.begin();
}

void TextureRegistry::unpin(uint64_t id) {
  const auto it = textures_.find(id);
  if (it == textures_.end()) return;  // cannot happen: a pinned texture is never evicted
  if (--it->second.pins == 0) make_unpinned(id, it->second);
}

TexturePin TextureRegistry::pin(uint64_t id) {
  std::lock_guard lock(mutex_);
  const auto it = textures_.find(id);
  if (it == textures_.end()) return {};
  make_pinned(it->second);
  return {this, it->second.texture};
}

TexturePtr TextureRegistry::find(uint64_t id) const {
  std::lock_guard lock(mutex_);
  auto it = textures_.find(id);
  return it == textures_.end() ? nullptr : it->second.texture;
}

std::size_t TextureRegistry::size() const {
  std::lock_guard lock(mutex_);
  return textures_.size();
}

RegistryStats TextureRegistry::stats() const {
  std::lock_guard lock(mutex_);
  // Every texture no stream pins is in the LRU list; the others are pinned.
  return {textures_.size(),
          textures_.size() - unpinned_.size(),
          bytes_,
          limits_.max_bytes,
          evicted_,
          refused_full_,
          refused_client_quota_};
}

}  // namespace soltex::server
