#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "soltex/render/frame_renderer.h"

// One scene of the image suite: drawn through the brick cache until converged, and compared
// with its supersampled per-pixel reference, 4 x 4 unless the case says otherwise (or, for
// `same_as`, with another case's cached image).
namespace soltex::images {

struct ImageCase {
  std::string group;
  std::string name;
  std::string scene_json;
  double psnr_floor = 0.0;     // dB; the case fails below it
  double max_share_off = 0.0;  // of covered pixels, a channel off by more than 16 steps
  int finest_level_log2 = 8;   // where the scene's material does not set one
  int antialias = 1;
  // Sub-pixels per axis of the reference. 4 for most scenes; 8 where the frame filters finer
  // than 16 sub-pixels resolve (a grazing floor's taps: 2 x 2 sub-pixels of up to 8 taps each
  // along the long side, where a 4 x 4 reference has 4).
  int reference_supersample = 4;
  TextureAccess access = TextureAccess::automatic;  // the frame's; the reference evaluates
  std::string same_as;  // compare with this case's cached image, not the reference
  // Set: the image may be at most twice as rough from pixel to pixel as this scene's, a smooth
  // texture on the same object (a pattern finer than a pixel must look flat, not moire).
  std::string smooth_json;
};

// The suite: every pattern at a coarse, a normal and a sub-pixel scale in object and world
// space; clip planes, including planes on a face and caps on a pattern boundary; offsets of
// 0, 1e4, 1e6 and 1e9; the OBJ models in `models` (none when the folder is absent); and the
// scenes the accuracy targets are stated for. OBJ files the cases need are written to
// `scratch`.
std::vector<ImageCase> image_cases(const std::filesystem::path& models,
                                   const std::filesystem::path& scratch);

}  // namespace soltex::images
