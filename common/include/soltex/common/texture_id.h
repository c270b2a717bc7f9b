#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_spec.h"

// Content addressing: the same texture has the same id on every server and client.
namespace soltex {

// The canonical byte encoding of a validated spec + volume + brick size + MIP construction
// (together they fix every sample of every brick): a format tag, then
// every parameter in a fixed order as little-endian IEEE-754 / two's-complement values, with
// -0.0 written as +0.0. Independent of protobuf's serializer, compiler and platform.
std::vector<uint8_t> canonical_encoding(const TextureSpec& spec, const Volume& volume,
                                        int brick_size, const MipSettings& mip = {});

// xxHash64 (seed 0) of the canonical encoding. Validates spec and volume first.
uint64_t texture_id(const TextureSpec& spec, const Volume& volume, int brick_size,
                    const MipSettings& mip = {});

// 16 lower-case hex digits.
std::string texture_id_hex(uint64_t id);

}  // namespace soltex
