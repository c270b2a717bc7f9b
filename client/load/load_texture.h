#pragma once

#include "load_options.h"
#include "soltex/v1/brick_service.pb.h"

namespace soltex::load {

// The RegisterTexture request of a run: the chosen pattern over the box [-1, 1]^3 with
// 2^finest_level cells per axis at level 0, RGB, band-limited MIP levels.
v1::RegisterTextureRequest texture_registration(const LoadOptions& options);

v1::Codec codec_to_proto(CodecChoice codec);

}  // namespace soltex::load
