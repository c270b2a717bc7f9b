#include "load_texture.h"

namespace soltex::load {

v1::RegisterTextureRequest texture_registration(const LoadOptions& options) {
  v1::RegisterTextureRequest request;
  v1::TextureSpec& spec = *request.mutable_spec();
  // Every pattern keeps its documented defaults (marble and turbulence: 6 value-noise
  // octaves), except the checker: 3D with cells of 1/8, so its bricks are not all one colour.
  switch (options.pattern) {
    case PatternKind::marble:
      spec.mutable_marble();
      break;
    case PatternKind::wood:
      spec.mutable_wood();
      break;
    case PatternKind::turbulence:
      spec.mutable_turbulence();
      break;
    case PatternKind::checker: {
      v1::Checker& checker = *spec.mutable_checker();
      checker.set_three_d(true);
      checker.mutable_size()->set_x(0.125);
      checker.mutable_size()->set_y(0.125);
      checker.mutable_size()->set_z(0.125);
      break;
    }
  }
  v1::Volume& volume = *request.mutable_volume();
  volume.mutable_min()->set_x(-1.0);
  volume.mutable_min()->set_y(-1.0);
  volume.mutable_min()->set_z(-1.0);
  volume.mutable_max()->set_x(1.0);
  volume.mutable_max()->set_y(1.0);
  volume.mutable_max()->set_z(1.0);
  volume.set_finest_level_log2(static_cast<uint32_t>(options.finest_level));
  request.set_brick_size(static_cast<uint32_t>(options.brick_size));
  request.set_mip_mode(v1::MIP_MODE_BAND_LIMITED);
  return request;
}

v1::Codec codec_to_proto(CodecChoice codec) {
  switch (codec) {
    case CodecChoice::zstd:
      return v1::CODEC_ZSTD;
    case CodecChoice::lz4:
      return v1::CODEC_LZ4;
    case CodecChoice::raw:
      return v1::CODEC_RAW;
  }
  return v1::CODEC_ZSTD;
}

}  // namespace soltex::load
