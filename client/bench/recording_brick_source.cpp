#include "recording_brick_source.h"

namespace soltex::bench {

void RecordingBrickSource::want(std::vector<net::BrickWant> wants) {
  {
    std::lock_guard lock(mutex_);
    for (const net::BrickWant& w : wants) {
      if (seen_.insert(w.key).second) wanted_.push_back(w.key);
    }
  }
  inner_.want(std::move(wants));
}

std::vector<BrickKey> RecordingBrickSource::wanted() const {
  std::lock_guard lock(mutex_);
  return wanted_;
}

}  // namespace soltex::bench
