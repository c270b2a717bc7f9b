#pragma once

#include <memory>

#include "soltex/capability/capability.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/brick_fetcher.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene.h"
#include "startup_timeline.h"
#include "view_options.h"

namespace soltex::view {

// What a run of soltex-view draws with: this machine's and its link's capability, what was
// chosen from them (levels, frame size, cache budget), and the cache and brick source opened
// at that budget.
struct ViewSetup {
  capability::Capability measured;   // as measured
  capability::Capability effective;  // with --capability's simulated limits
  capability::Choice choice;
  std::unique_ptr<BrickCache> cache;
  std::unique_ptr<net::BrickSource> source;
};

// Measures the machine (a window) or its memory (headless), probes the link unless it is
// loopback or in-process, chooses from the measurements and the options, and opens the cache
// and the brick source; each step logged with why, and marked on `timeline` where not null.
ViewSetup set_up_view(const ViewOptions& options, const Scene& scene,
                      net::FetcherOptions fetcher_options, StartupTimeline* timeline);

}  // namespace soltex::view
