#include "accuracy_setting.h"

#include <vector>

namespace soltex::bench {

std::string CodecChoice::name() const {
  if (codec == Codec::zstd) return "zstd-" + std::to_string(zstd_level);
  return codec_name(codec);
}

CodecOptions CodecChoice::options() const {
  return served_codec_options(codec, zstd_level);  // as soltexd encodes
}

std::string octaves_name(const std::optional<int>& octave_cap) {
  return octave_cap ? std::to_string(*octave_cap) : "scene";
}

std::string AccuracySetting::label() const {
  const AccuracySetting defaults;
  std::vector<std::string> parts;
  if (finest_level != defaults.finest_level)
    parts.push_back("level=" + std::to_string(finest_level));
  if (brick_size != defaults.brick_size) parts.push_back("brick=" + std::to_string(brick_size));
  if (filter != defaults.filter)
    parts.push_back(std::string("filter=") + sample_filter_name(filter));
  if (mip != defaults.mip) parts.push_back(std::string("mip=") + mip_mode_name(mip));
  if (octave_cap != defaults.octave_cap) parts.push_back("octaves=" + octaves_name(octave_cap));
  if (codec != defaults.codec) parts.push_back("codec=" + codec.name());
  if (access != defaults.access)
    parts.push_back(std::string("access=") + texture_access_name(access));
  if (antialias != defaults.antialias) parts.push_back("antialias=" + std::to_string(antialias));
  if (anisotropy != defaults.anisotropy) {
    parts.push_back("anisotropy=" + std::to_string(anisotropy));
  }
  if (parts.empty()) return "default";
  std::string label = parts.front();
  for (std::size_t i = 1; i < parts.size(); ++i) label += " " + parts[i];
  return label;
}

bool AccuracySetting::same_frame_as(const AccuracySetting& other) const {
  AccuracySetting other_with_my_codec = other;
  other_with_my_codec.codec = codec;
  return *this == other_with_my_codec;
}

}  // namespace soltex::bench
