#include "encoded_brick.h"

#include <google/protobuf/io/coded_stream.h>
#include <grpc/slice.h>

#include <cstring>

#include "soltex/common/check.h"
#include "soltex/spec_proto/brick_proto.h"

namespace soltex::server {
namespace {

using google::protobuf::io::CodedOutputStream;

// Protobuf wire tags: (field number << 3) | wire type (0 varint, 1 fixed64, 2 length-delimited).
constexpr uint8_t kBatchBricksTag = (1 << 3) | 2;  // BrickBatch.bricks
constexpr uint8_t kKeyTag = (1 << 3) | 2;          // Brick.key
constexpr uint8_t kCodecTag = (2 << 3) | 0;        // Brick.codec
constexpr uint8_t kPayloadTag = (3 << 3) | 2;      // Brick.payload
constexpr uint8_t kChecksumTag = (4 << 3) | 1;     // Brick.checksum

}  // namespace

EncodedBrick::EncodedBrick(const BrickKey& brick_key, Codec brick_codec, std::string_view payload,
                           uint64_t brick_checksum)
    : key(brick_key), codec(brick_codec), checksum(brick_checksum), payload_size_(payload.size()) {
  // Fields in field-number order and proto3's defaults left out, as protobuf itself writes
  // them: the bytes equal a BrickBatch holding this one Brick, serialized by libprotobuf.
  const v1::BrickKey key_message = to_proto(key);
  const std::size_t key_size = key_message.ByteSizeLong();
  const auto codec_value = static_cast<uint32_t>(to_proto(codec));
  std::size_t body =
      1 + CodedOutputStream::VarintSize32(static_cast<uint32_t>(key_size)) + key_size;
  if (codec_value != 0) body += 1 + CodedOutputStream::VarintSize32(codec_value);
  if (!payload.empty()) {
    body +=
        1 + CodedOutputStream::VarintSize32(static_cast<uint32_t>(payload.size())) + payload.size();
  }
  if (checksum != 0) body += 1 + sizeof(uint64_t);
  const std::size_t total = 1 + CodedOutputStream::VarintSize32(static_cast<uint32_t>(body)) + body;

  grpc_slice slice = grpc_slice_malloc(total);
  uint8_t* const start = GRPC_SLICE_START_PTR(slice);
  uint8_t* p = start;
  *p++ = kBatchBricksTag;
  p = CodedOutputStream::WriteVarint32ToArray(static_cast<uint32_t>(body), p);
  *p++ = kKeyTag;
  p = CodedOutputStream::WriteVarint32ToArray(static_cast<uint32_t>(key_size), p);
  p = key_message.SerializeWithCachedSizesToArray(p);
  if (codec_value != 0) {
    *p++ = kCodecTag;
    p = CodedOutputStream::WriteVarint32ToArray(codec_value, p);
  }
  if (!payload.empty()) {
    *p++ = kPayloadTag;
    p = CodedOutputStream::WriteVarint32ToArray(static_cast<uint32_t>(payload.size()), p);
    payload_offset_ = static_cast<std::size_t>(p - start);
    std::memcpy(p, payload.data(), payload.size());
    p += payload.size();
  }
  if (checksum != 0) {
    *p++ = kChecksumTag;
    p = CodedOutputStream::WriteLittleEndian64ToArray(checksum, p);
  }
  SOLTEX_DCHECK(static_cast<std::size_t>(p - start) == total);
  element_ = grpc::Slice(slice, grpc::Slice::STEAL_REF);
}

}  // namespace soltex::server
