#pragma once

#include <atomic>
#include <cstdint>

// How much noise brick evaluation computed, and how much band limiting spared it: per
// evaluate_brick() call, the octaves it evaluated and the octaves it replaced by their mean,
// each times the samples of the call. Counted once per call (a few relaxed atomic adds against
// thousands of samples), never per sample, so evaluation loops are unchanged.
namespace soltex {

struct OctaveCounts {
  uint64_t samples = 0;                   // sample points evaluated (supersamples included)
  uint64_t evaluated_octave_samples = 0;  // sum over calls of evaluated octaves x samples
  uint64_t skipped_octave_samples = 0;    // sum over calls of faded-out octaves x samples
};

class OctaveCounters {
 public:
  void add(uint64_t samples, int evaluated_octaves, int skipped_octaves) {
    samples_.fetch_add(samples, std::memory_order_relaxed);
    evaluated_.fetch_add(samples * static_cast<uint64_t>(evaluated_octaves),
                         std::memory_order_relaxed);
    skipped_.fetch_add(samples * static_cast<uint64_t>(skipped_octaves), std::memory_order_relaxed);
  }

  // Each field is read on its own: a snapshot taken while other threads add is a consistent
  // count per field, not across fields.
  OctaveCounts snapshot() const {
    return {samples_.load(std::memory_order_relaxed), evaluated_.load(std::memory_order_relaxed),
            skipped_.load(std::memory_order_relaxed)};
  }

 private:
  std::atomic<uint64_t> samples_{0};
  std::atomic<uint64_t> evaluated_{0};
  std::atomic<uint64_t> skipped_{0};
};

// The process's counters, which evaluate_brick() adds to.
inline OctaveCounters& octave_counters() {
  static OctaveCounters counters;
  return counters;
}

}  // namespace soltex
