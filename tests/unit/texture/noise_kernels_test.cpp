// As in noise_kernels.cpp: Highway 1.0.3 needs this to accept a -march=native baseline that
// includes AVX3_DL.
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL
#endif

#include "noise_kernels.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dispatch_targets.h"
#include "soltex/common/fractal.h"

namespace soltex {
namespace {

std::vector<int64_t> targets_to_run() {
  return test::targets_to_run(noise_kernels::compiled_targets());
}

// fractal_sum's definition, octave by octave through the scalar noise functions.
float scalar_fractal_sum(const OctavePlan& plan, const glm::dvec3& p) {
  float sum = 0.0f;
  for (int k = 0; k < plan.count; ++k) {
    const Octave& octave = plan.octaves[k];
    if (octave.noise_weight == 0.0f) {
      sum += octave.mean_term;
      continue;
    }
    float noise = basis_noise(plan.basis, p * octave.frequency);
    if (plan.absolute) noise = std::fabs(noise);
    sum += octave.noise_weight * noise + octave.mean_term;
  }
  return sum;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Rows the kernels treat differently: ascending runs (contiguous faces, in-register lookups),
// steps wider than a cell (gathers), shuffled order, lengths that leave partial vectors, and
// coordinates far from the origin or not finite at all.
std::vector<std::vector<double>> rows_to_check() {
  std::vector<std::vector<double>> rows;
  for (std::size_t n : {1u, 5u, 16u, 17u, 64u, 97u}) {
    for (double step : {0.0123, 0.37, 3.1}) {
      for (double origin : {0.0, -7.3, 1e6 + 0.1, 1e9, -1e9}) {
        std::vector<double> x(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = origin + static_cast<double>(i) * step;
        rows.push_back(x);
      }
    }
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-600.0, 600.0);
  std::vector<double> shuffled(53);
  for (double& v : shuffled) v = u(rng);
  rows.push_back(shuffled);
  rows.push_back({0.5, kNan, 1.5, kInf, -kInf, -0.25, 1e300, -1e300, 2147483648.5, -0.0});
  return rows;
}

FractalParams params(NoiseBasis basis, bool signed_octaves, int octave_min, int octave_max) {
  FractalParams p;
  p.scale = 0.9;
  p.octave_min = octave_min;
  p.octave_max = octave_max;
  p.basis = basis;
  p.signed_octaves = signed_octaves;
  return p;
}

TEST(NoiseKernels, EveryTargetMatchesTheScalarPathBitForBit) {
  const std::vector<int64_t> targets = targets_to_run();
  ASSERT_FALSE(targets.empty());
  std::string names;
  for (const int64_t target : targets) names += std::string(hwy::TargetName(target)) + " ";
  RecordProperty("targets", names);
  const std::vector<std::vector<double>> rows = rows_to_check();
  const double yz[][2] = {{0.3, -2.7}, {-1e9, 1e9 + 0.5}, {kNan, 4.0}, {kInf, -kInf}};
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(noise_kernels::dispatched_target(), target) << hwy::TargetName(target);
    for (NoiseBasis basis : {NoiseBasis::value, NoiseBasis::gradient}) {
      for (bool signed_octaves : {false, true}) {
        for (double width : {0.0, 0.05}) {
          const OctavePlan plan = plan_octaves(params(basis, signed_octaves, 0, 7), width);
          for (const std::vector<double>& x : rows) {
            const FractalRows fractal_rows(plan, x);
            std::vector<float> out(x.size());
            for (const auto& [y, z] : yz) {
              fractal_rows.sum(y, z, out);
              for (std::size_t i = 0; i < x.size(); ++i) {
                const glm::dvec3 p(x[i], y, z);
                const float expected = scalar_fractal_sum(plan, p);
                ASSERT_TRUE(same_bits(out[i], expected))
                    << "row " << hwy::TargetName(target) << " basis " << int(basis) << " x " << x[i]
                    << " y " << y << " z " << z << ": " << out[i] << " != " << expected;
                const float any = fractal_sum(plan, p);  // dispatched per point
                ASSERT_TRUE(same_bits(any, expected))
                    << "fractal_sum " << hwy::TargetName(target) << " basis " << int(basis) << " x "
                    << x[i] << " y " << y << " z " << z << ": " << any << " != " << expected;
                if (basis != NoiseBasis::gradient) continue;
                const float point = noise_kernels::gradient_fractal_sum_dispatched(plan, p);
                ASSERT_TRUE(same_bits(point, expected))
                    << "point " << hwy::TargetName(target) << " basis " << int(basis) << " x "
                    << x[i] << " y " << y << " z " << z << ": " << point << " != " << expected;
              }
            }
          }
        }
      }
    }
  }
}

// Several rows in one call, their points end to end in the lanes: each row's sums are the
// scalar path's, whatever the row count (a partial plane, rows of one point, rows whose
// points reach many faces and so gather across rows).
TEST(NoiseKernels, RowsAtOnceMatchTheScalarPathBitForBit) {
  const std::vector<std::vector<double>> rows = rows_to_check();
  // Odd rows, then a plane's: 17 rows a step apart in y at one z, so that consecutive rows
  // share their lattice cell at the coarse octaves and not at the fine ones.
  std::vector<std::array<double, 2>> yz = {{0.3, -2.7},   {-1e9, 1e9 + 0.5}, {kNan, 4.0},
                                           {kInf, -kInf}, {0.31, -2.7},      {0.3, -2.69},
                                           {-7.25, 0.125}};
  for (int j = 0; j < 17; ++j) yz.push_back({-0.4 + 0.0625 * j, 0.37});
  const std::size_t kRows = yz.size();
  for (const int64_t target : targets_to_run()) {
    const test::ForcedTarget forced(target);
    for (NoiseBasis basis : {NoiseBasis::value, NoiseBasis::gradient}) {
      for (double width : {0.0, 0.05}) {
        const OctavePlan plan = plan_octaves(params(basis, false, 0, 7), width);
        for (const std::vector<double>& x : rows) {
          const FractalRows fractal_rows(plan, x, kRows);
          for (std::size_t count : {kRows, std::size_t{17}, std::size_t{2}, std::size_t{1}}) {
            // The last `count` rows: the plane's alone, or the odd rows before it too.
            const std::size_t first = kRows - count;
            std::vector<double> ys(count), zs(count);
            for (std::size_t r = 0; r < count; ++r) {
              ys[r] = yz[first + r][0];
              zs[r] = yz[first + r][1];
            }
            std::vector<float> out(count * x.size());
            fractal_rows.sum_rows(ys, zs, out);
            for (std::size_t r = 0; r < count; ++r) {
              for (std::size_t i = 0; i < x.size(); ++i) {
                const float expected = scalar_fractal_sum(plan, {x[i], ys[r], zs[r]});
                ASSERT_TRUE(same_bits(out[r * x.size() + i], expected))
                    << hwy::TargetName(target) << " basis " << int(basis) << " rows " << count
                    << " row " << r << " x " << x[i] << ": " << out[r * x.size() + i]
                    << " != " << expected;
              }
            }
          }
        }
      }
    }
  }
}

TEST(NoiseKernels, SinglePointFractalIsTheScalarDefinition) {
  // fractal_sum on the CPU's own target; up to the 16-octave limit, so
  // that octaves fill more than one vector.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (NoiseBasis basis : {NoiseBasis::value, NoiseBasis::gradient}) {
    for (bool signed_octaves : {false, true}) {
      const OctavePlan plan = plan_octaves(params(basis, signed_octaves, -3, 12), 0.01);
      for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 p(u(rng), u(rng), u(rng));
        ASSERT_TRUE(same_bits(fractal_sum(plan, p), scalar_fractal_sum(plan, p)))
            << p.x << " " << p.y << " " << p.z;
      }
    }
  }
}

TEST(NoiseKernels, ScalarFallbackIsCompiledAlongsideTheVectorTargets) {
  // The test above is only meaningful with more than the build's own best target.
  const int64_t compiled = noise_kernels::compiled_targets();
  EXPECT_NE(compiled & (HWY_SCALAR | HWY_EMU128), 0);
  EXPECT_GE(targets_to_run().size(), 2u);
}

}  // namespace
}  // namespace soltex
