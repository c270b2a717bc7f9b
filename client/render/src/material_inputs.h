#pragma once

#include <glm/vec3.hpp>

#include "soltex/common/texture_evaluator.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::render {

// What a pixel's texture values give its lighting.
struct SurfaceInputs {
  glm::vec3 albedo;
  float opacity;
  float specular;
};

// Where a texture's sampled channels go: albedo (three channels, or one grey), opacity and
// specular (their index in the samples, or -1 for none).
struct MaterialInputs {
  bool colour = true;
  int opacity = -1;
  int specular = -1;
  float material_specular = 0.0f;
  float shininess = 0.0f;
  bool unlit = false;

  // Whether the channels are the albedo alone: opacity 1 and the material's specular for
  // every pixel.
  bool colour_only() const { return colour && opacity < 0 && specular < 0; }

  // `values`: the texture's channels in order, as sampled or evaluated.
  SurfaceInputs read(const float* values) const {
    return {colour ? glm::vec3(values[0], values[1], values[2]) : glm::vec3(values[0]),
            opacity >= 0 ? values[opacity] : 1.0f,
            specular >= 0 ? values[specular] : material_specular};
  }
};

inline MaterialInputs material_inputs(const PreparedObject& object) {
  const ChannelSet& channels = object.texture.channels;
  const Material& material = object.object->material;
  MaterialInputs m;
  m.colour = channels.colour;
  int next = channels.colour ? 3 : 0;
  if (channels.opacity) m.opacity = next++;
  if (channels.specular) m.specular = next++;
  m.material_specular = material.specular;
  m.shininess = material.shininess;
  m.unlit = material.unlit;
  return m;
}

// An evaluated texel as the channels a brick of `spec` would hold, in the same order.
inline void texel_channels(const TextureSpec& spec, const Texel& texel, float* values) {
  int next = 0;
  if (spec.channels.colour) {
    values[next++] = texel.colour.r;
    values[next++] = texel.colour.g;
    values[next++] = texel.colour.b;
  }
  const auto scalar = [&](const ScalarRange& r) { return r.low + (r.high - r.low) * texel.field; };
  if (spec.channels.opacity) values[next++] = scalar(spec.opacity);
  if (spec.channels.specular) values[next++] = scalar(spec.specular);
}

}  // namespace soltex::render
