#pragma once

#include <optional>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_key.h"
#include "soltex/v1/brick_service.pb.h"

// Brick-service messages <-> soltex::common values, shared by soltexd and its clients.
namespace soltex {

v1::BrickKey to_proto(const BrickKey& key);
BrickKey from_proto(const v1::BrickKey& message);

v1::Codec to_proto(Codec codec);
// CODEC_UNSPECIFIED means "any" and gives zstd; an unknown value gives nullopt.
std::optional<Codec> codec_from_proto(v1::Codec codec);

v1::MipMode to_proto(MipMode mode);
// nullopt for an unknown value.
std::optional<MipMode> mip_mode_from_proto(v1::MipMode mode);

}  // namespace soltex
