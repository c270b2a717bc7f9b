#include "brick_batch_reader.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

namespace soltex::load {
namespace {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedInputStream;

constexpr uint32_t tag(int field, WireFormatLite::WireType type) {
  return (static_cast<uint32_t>(field) << 3) | static_cast<uint32_t>(type);
}
constexpr uint32_t kVarint(int field) {
  return tag(field, WireFormatLite::WIRETYPE_VARINT);
}
constexpr uint32_t kFixed64(int field) {
  return tag(field, WireFormatLite::WIRETYPE_FIXED64);
}
constexpr uint32_t kBytes(int field) {
  return tag(field, WireFormatLite::WIRETYPE_LENGTH_DELIMITED);
}

// Runs `field(tag)` for each field of the length-delimited message at the input's position;
// `field` returns false on bad input. Nesting is bounded by the callers (two levels).
template <typename Field>
bool read_message(CodedInputStream& in, Field field) {
  uint32_t length = 0;
  if (!in.ReadVarint32(&length) || length > static_cast<uint32_t>(INT32_MAX)) return false;
  const CodedInputStream::Limit limit = in.PushLimit(static_cast<int>(length));
  for (uint32_t t = in.ReadTag(); t != 0; t = in.ReadTag()) {
    if (!field(t)) return false;
  }
  // ReadTag() gives 0 at the limit, and also on a malformed tag or a truncated message.
  if (!in.ConsumedEntireMessage() || in.BytesUntilLimit() != 0) return false;
  in.PopLimit(limit);
  return true;
}

bool read_int32(CodedInputStream& in, int32_t& value) {
  uint64_t raw = 0;  // int32 is sent as a sign-extended varint; protobuf keeps the low 32 bits
  if (!in.ReadVarint64(&raw)) return false;
  value = static_cast<int32_t>(static_cast<uint32_t>(raw));
  return true;
}

bool read_key(CodedInputStream& in, BrickKey& key) {
  return read_message(in, [&](uint32_t t) {
    switch (t) {
      case kFixed64(1):
        return in.ReadLittleEndian64(&key.texture);
      case kVarint(2): {
        int32_t level = 0;  // uint32 on the wire; a level past INT32_MAX is out of range anyway
        if (!read_int32(in, level)) return false;
        key.level = level;
        return true;
      }
      case kVarint(3):
        return read_int32(in, key.brick.x);
      case kVarint(4):
        return read_int32(in, key.brick.y);
      case kVarint(5):
        return read_int32(in, key.brick.z);
      default:
        return WireFormatLite::SkipField(&in, t);
    }
  });
}

}  // namespace

bool BrickBatchReader::read(google::protobuf::io::ZeroCopyInputStream& message,
                            bool keep_payloads) {
  bricks_.clear();
  errors_.clear();
  request_errors_.clear();
  payloads_.clear();
  CodedInputStream in(&message);
  in.SetTotalBytesLimit(INT32_MAX);
  for (uint32_t t = in.ReadTag(); t != 0; t = in.ReadTag()) {
    bool good = true;
    switch (t) {
      case kBytes(1): {
        Brick& brick = bricks_.emplace_back();
        good = read_message(in, [&](uint32_t f) {
          switch (f) {
            case kBytes(1):
              return read_key(in, brick.key);
            case kVarint(2):
              return read_int32(in, brick.codec);
            case kBytes(3): {
              uint32_t size = 0;
              if (!in.ReadVarint32(&size)) return false;
              brick.payload_size = size;  // a repeated field: the last one counts
              if (!keep_payloads) return in.Skip(static_cast<int>(size));
              brick.payload_offset = payloads_.size();
              std::string payload;
              if (!in.ReadString(&payload, static_cast<int>(size))) return false;
              payloads_ += payload;
              return true;
            }
            case kFixed64(4):
              return in.ReadLittleEndian64(&brick.checksum);
            default:
              return WireFormatLite::SkipField(&in, f);
          }
        });
        break;
      }
      case kBytes(2): {
        Error& error = errors_.emplace_back();
        good = read_message(in, [&](uint32_t f) {
          switch (f) {
            case kBytes(1):
              return read_key(in, error.key);
            case kVarint(2):
              return read_int32(in, error.code);
            default:
              return WireFormatLite::SkipField(&in, f);  // the message text among them
          }
        });
        break;
      }
      case kBytes(3): {
        int32_t& code = request_errors_.emplace_back();
        good = read_message(in, [&](uint32_t f) {
          if (f == kVarint(1)) return read_int32(in, code);
          return WireFormatLite::SkipField(&in, f);
        });
        break;
      }
      default:
        good = WireFormatLite::SkipField(&in, t);
    }
    if (!good) return false;
  }
  return in.ConsumedEntireMessage();
}

}  // namespace soltex::load
