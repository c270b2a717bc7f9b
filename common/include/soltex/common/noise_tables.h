#pragma once

#include <array>
#include <cstdint>

namespace soltex {

// One of gradient noise's sixteen lattice gradients (gradient_noise.h), as floats; padded to
// 16 bytes so that an entry's address is a shift.
struct LatticeGradient {
  float x, y, z, unused;
};

// The random tables behind both noise bases, generated once from a fixed seed so every
// process and build sees the same textures.
struct NoiseTables {
  // NoiseTable[256]: values in [0, 1].
  std::array<float, 256> value;
  // Index[256], a random permutation of 0..255, stored twice so that
  // INDEX(ix, iy, iz) = PERM(ix + PERM(iy + PERM(iz))) never needs a mask for ix, iy, iz <= 256.
  // 32-bit entries so that vectorised loops can gather from it.
  std::array<int32_t, 512> perm;
  // The mean of `value`; also the exact mean of value noise over one period, since every
  // lattice value weighs the same in the integral of a trilinear interpolant.
  float value_mean;
  // Derived from the two above for the single-point path, which then reads a corner with one
  // load instead of two dependent ones: value_at[i] = value[perm[i]], gradient_at[i] = the
  // gradient for hash perm[i] & 15.
  std::array<float, 512> value_at;
  std::array<LatticeGradient, 512> gradient_at;

  int index(int ix, int iy, int iz) const { return perm[ix + perm[iy + perm[iz]]]; }
};

// PERM(iy + dy + PERM(iz + dz)) for the four (dy, dz) corners of a y-z cell: every lattice
// cell along one x row shares them, so INDEX(ix + dx, iy + dy, iz + dz) = PERM(ix + dx + h_dydz).
struct RowHashes {
  int32_t h00, h10, h01, h11;  // h<dy><dz>
};

inline RowHashes row_hashes(const NoiseTables& t, int iy, int iz) {
  const int32_t* p = t.perm.data();
  return {p[iy + p[iz]], p[iy + 1 + p[iz]], p[iy + p[iz + 1]], p[iy + 1 + p[iz + 1]]};
}

// The seed is part of the texture definition: changing it changes every noise texture.
inline constexpr uint64_t kNoiseSeed = 0x5011'7E57'2002'1985ULL;

const NoiseTables& noise_tables();

// Builds the tables from `seed` with SplitMix64 (Steele, Lea & Flood 2014) and a
// Fisher-Yates shuffle, both fully specified here so the tables are the same everywhere.
NoiseTables make_noise_tables(uint64_t seed);

}  // namespace soltex
