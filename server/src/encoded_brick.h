#pragma once

#include <grpcpp/support/slice.h>

#include <cstdint>
#include <memory>
#include <string_view>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_key.h"

namespace soltex::server {

// One brick encoded with one codec, as sent on the wire. Immutable and shared: the server
// quantizes, filters and compresses a brick once, however many streams receive it.
//
// It is kept as its `BrickBatch.bricks` entry, serialized once (the field's tag and length,
// then the `Brick` message: key, codec, payload, checksum; docs/PROTOCOL.md) in a reference-
// counted gRPC slice. A repeated field's encoding is the concatenation of its entries, so a
// message of bricks is these slices side by side: every send of a cached brick shares its
// bytes, with no copy into a protobuf message and none into gRPC's buffer.
class EncodedBrick {
 public:
  EncodedBrick(const BrickKey& key, Codec codec, std::string_view payload, uint64_t checksum);
  EncodedBrick(const EncodedBrick&) = delete;
  EncodedBrick& operator=(const EncodedBrick&) = delete;

  const BrickKey key;
  const Codec codec;
  const uint64_t checksum;

  // The encoded brick (header and compressed samples), inside element().
  std::string_view payload() const {
    return {reinterpret_cast<const char*>(element_.begin()) + payload_offset_, payload_size_};
  }
  // The serialized `BrickBatch.bricks` entry.
  const grpc::Slice& element() const { return element_; }
  // Where payload() starts within element().
  std::size_t payload_offset() const { return payload_offset_; }

 private:
  grpc::Slice element_;
  std::size_t payload_offset_ = 0;
  std::size_t payload_size_ = 0;
};

using EncodedBrickPtr = std::shared_ptr<const EncodedBrick>;

}  // namespace soltex::server
