#include "soltex/spec_proto/brick_proto.h"

namespace soltex {

v1::BrickKey to_proto(const BrickKey& key) {
  v1::BrickKey m;
  m.set_texture_id(key.texture);
  m.set_level(static_cast<uint32_t>(key.level));
  m.set_x(key.brick.x);
  m.set_y(key.brick.y);
  m.set_z(key.brick.z);
  return m;
}

BrickKey from_proto(const v1::BrickKey& m) {
  return {m.texture_id(), static_cast<int32_t>(m.level()), {m.x(), m.y(), m.z()}};
}

v1::Codec to_proto(Codec codec) {
  switch (codec) {
    case Codec::raw:
      return v1::CODEC_RAW;
    case Codec::lz4:
      return v1::CODEC_LZ4;
    case Codec::zstd:
      return v1::CODEC_ZSTD;
  }
  return v1::CODEC_UNSPECIFIED;
}

std::optional<Codec> codec_from_proto(v1::Codec codec) {
  switch (codec) {
    case v1::CODEC_RAW:
      return Codec::raw;
    case v1::CODEC_LZ4:
      return Codec::lz4;
    case v1::CODEC_ZSTD:
    case v1::CODEC_UNSPECIFIED:
      return Codec::zstd;
    default:
      return std::nullopt;
  }
}

v1::MipMode to_proto(MipMode mode) {
  switch (mode) {
    case MipMode::point:
      return v1::MIP_MODE_POINT;
    case MipMode::supersampled:
      return v1::MIP_MODE_SUPERSAMPLED;
    case MipMode::band_limited:
      break;
  }
  return v1::MIP_MODE_BAND_LIMITED;
}

std::optional<MipMode> mip_mode_from_proto(v1::MipMode mode) {
  switch (mode) {
    case v1::MIP_MODE_BAND_LIMITED:
      return MipMode::band_limited;
    case v1::MIP_MODE_POINT:
      return MipMode::point;
    case v1::MIP_MODE_SUPERSAMPLED:
      return MipMode::supersampled;
    default:
      return std::nullopt;
  }
}

}  // namespace soltex
