#include "soltex/net/request_packer.h"

#include <google/protobuf/io/coded_stream.h>

#include <algorithm>

#include "soltex/common/check.h"

namespace soltex::net {
std::size_t field_bytes(std::size_t length) {
  // Every BrickRequest field number is below 16: a one-byte tag.
  return 1 + google::protobuf::io::CodedOutputStream::VarintSize64(length) + length;
}

RequestPacker::RequestPacker(RequestBounds bounds) : bounds_(bounds) {
  bounds_.max_wants = std::max<std::size_t>(bounds_.max_wants, 1);
}

bool RequestPacker::add_texture(const std::string& serialized) {
  const std::size_t bytes = field_bytes(serialized.size());
  if (bytes > bounds_.max_bytes) return false;
  make_room(bytes, false);
  current_.add_textures()->ParseFromString(serialized);
  current_bytes_ += bytes;
  return true;
}

void RequestPacker::add_codec(v1::Codec codec) {
  make_room(kCodecBytes, false);
  current_.add_accept_codecs(codec);
  current_bytes_ += kCodecBytes;
}

void RequestPacker::add_cancel(const v1::BrickKey& key) {
  const std::size_t bytes = field_bytes(key.ByteSizeLong());
  make_room(bytes, false);
  *current_.add_cancel() = key;
  current_bytes_ += bytes;
}

void RequestPacker::add_want(const v1::BrickKey& key, int32_t priority) {
  v1::BrickWant want;
  *want.mutable_key() = key;
  want.set_priority(priority);
  const std::size_t bytes = field_bytes(want.ByteSizeLong());
  make_room(bytes, true);
  *current_.add_want() = std::move(want);
  current_bytes_ += bytes;
}

void RequestPacker::make_room(std::size_t bytes, bool want) {
  const bool too_many = want && static_cast<std::size_t>(current_.want_size()) >= bounds_.max_wants;
  if (current_bytes_ > 0 && (too_many || current_bytes_ + bytes > bounds_.max_bytes)) {
    SOLTEX_DCHECK(current_.ByteSizeLong() == current_bytes_ ||
                  current_.accept_codecs_size() > 0);  // codecs are counted at their most
    full_.push_back(std::move(current_));
    current_.Clear();
    current_bytes_ = 0;
  }
}

std::vector<v1::BrickRequest> RequestPacker::take() {
  if (current_bytes_ > 0) full_.push_back(std::move(current_));
  current_.Clear();
  current_bytes_ = 0;
  std::vector<v1::BrickRequest> out;
  out.swap(full_);
  return out;
}

}  // namespace soltex::net
