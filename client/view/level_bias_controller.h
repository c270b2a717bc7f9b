#pragma once

// The automatic level-of-detail control while the viewer is being interacted with: a level
// bias (added to every pixel's level; positive is coarser) that holds a target frame time.
// Slow frames raise the bias in small steps, clearly fast ones lower it, never below 0. When
// the interaction stops the bias drops to 0 at once, so a still view refines to full detail;
// when it starts again the bias it had reached comes back, so the frame rate does not have
// to be won back step by step.
namespace soltex::view {

struct LevelBiasSettings {
  double target_frame_ms = 33.0;
  // Lower the bias only when frames take less than this share of the target: a gap between
  // "slow" and "fast" keeps the bias from flipping between two steps every decision.
  double fast_fraction = 0.6;
  double step = 0.25;
  double max_bias = 4.0;
  // Frames measured after a change before the next decision, so that each decision sees
  // frames drawn with the bias before it.
  int frames_per_decision = 3;
};

class LevelBiasController {
 public:
  explicit LevelBiasController(LevelBiasSettings settings = {});

  // Records how long the last frame took and whether the user was interacting while it was
  // drawn; returns the bias for the next frame.
  double record_frame(double frame_ms, bool interacting);

  double bias() const { return bias_; }
  // The bias to come back to when the interaction resumes.
  double interaction_bias() const { return interaction_bias_; }
  const LevelBiasSettings& settings() const { return settings_; }

  // Back to full detail, forgetting the interaction bias and the frames measured.
  void reset();

 private:
  void start_measuring();

  LevelBiasSettings settings_;
  double bias_ = 0.0;
  double interaction_bias_ = 0.0;
  bool was_interacting_ = false;
  int measured_frames_ = 0;
  double measured_ms_ = 0.0;
};

}  // namespace soltex::view
