#include "soltex/common/noise_tables.h"

#include <numeric>
#include <utility>

#include "soltex/common/gradient_noise.h"

namespace soltex {
namespace {

// SplitMix64: a 64-bit state advanced by a Weyl constant and mixed by two
// multiply-xorshift rounds.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

  // Uniform in [0, bound) without modulo bias (Lemire's multiply-shift with rejection).
  uint32_t below(uint32_t bound) {
    for (;;) {
      const uint64_t product = (next() >> 32) * bound;
      if (static_cast<uint32_t>(product) >= (0x1'0000'0000ULL % bound)) {
        return static_cast<uint32_t>(product >> 32);
      }
    }
  }

 private:
  uint64_t state_;
};

}  // namespace

NoiseTables make_noise_tables(uint64_t seed) {
  SplitMix64 random(seed);
  NoiseTables tables{};
  double sum = 0.0;
  for (float& v : tables.value) {
    // 24 random bits over 2^24 - 1: exactly representable floats covering [0, 1] inclusive.
    v = static_cast<float>(random.next() >> 40) / 16777215.0f;
    sum += v;
  }
  tables.value_mean = static_cast<float>(sum / 256.0);

  std::array<uint8_t, 256> perm{};
  std::iota(perm.begin(), perm.end(), 0);
  for (uint32_t i = 255; i > 0; --i) std::swap(perm[i], perm[random.below(i + 1)]);
  for (int i = 0; i < 512; ++i) {
    tables.perm[i] = perm[i & 255];
    tables.value_at[i] = tables.value[tables.perm[i]];
    const int h = tables.perm[i] & 15;
    tables.gradient_at[i] = {static_cast<float>(detail::kGradX[h]),
                             static_cast<float>(detail::kGradY[h]),
                             static_cast<float>(detail::kGradZ[h]), 0.0f};
  }
  return tables;
}

const NoiseTables& noise_tables() {
  static const NoiseTables tables = make_noise_tables(kNoiseSeed);
  return tables;
}

}  // namespace soltex
