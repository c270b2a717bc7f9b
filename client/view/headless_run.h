#pragma once

#include "soltex/scene/scene.h"
#include "startup_timeline.h"
#include "view_options.h"
#include "view_setup.h"

namespace soltex::view {

// soltex-view --headless: renders the scene until it converges (or --max-time-s runs out),
// writes --out, prints what happened (and with --reference the per-pixel reference's time and
// PSNR), and returns the exit code: converged, or written but not converged.
int run_headless(const ViewOptions& options, const Scene& scene, ViewSetup& setup,
                 StartupTimeline* timeline);

}  // namespace soltex::view
