#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "soltex/net/request_bounds.h"
#include "soltex/v1/brick_service.pb.h"

namespace soltex::net {

// Packs what the fetcher has to say into as few BrickRequests as fit the server's bounds, in
// the order given: textures first, so that every message's wants name textures the server has
// already read. Sizes are counted as protobuf encodes them, so a message never exceeds
// max_bytes.
class RequestPacker {
 public:
  // What one codec in accept_codecs adds at most: a packed repeated enum's tag and length once,
  // then a varint per codec, every codec below 128.
  static constexpr std::size_t kCodecBytes = 3;

  explicit RequestPacker(RequestBounds bounds);

  // A serialized RegisterTextureRequest. False, and nothing added, when it alone is larger
  // than a message may be.
  bool add_texture(const std::string& serialized);
  void add_codec(v1::Codec codec);
  void add_cancel(const v1::BrickKey& key);
  void add_want(const v1::BrickKey& key, int32_t priority);

  // The messages packed so far, none of them empty; the packer starts over.
  std::vector<v1::BrickRequest> take();

 private:
  // Starts a new message unless the current one has room for `bytes` more (and a want more).
  void make_room(std::size_t bytes, bool want);

  RequestBounds bounds_;
  std::vector<v1::BrickRequest> full_;
  v1::BrickRequest current_;
  std::size_t current_bytes_ = 0;
};

// The bytes a field of `length` encoded bytes takes in its message: its tag, length and body.
std::size_t field_bytes(std::size_t length);

}  // namespace soltex::net
