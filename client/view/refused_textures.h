#pragma once

#include "soltex/net/brick_source.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::view {

// A warning for each object whose texture the server refused, naming it and why: its texture
// is evaluated per pixel here instead.
void warn_of_refused_textures(const PreparedScene& prepared);

// Takes the textures `source` refused since (on its brick stream, after registering them),
// marks their objects evaluated per pixel and warns of each as above.
void adopt_refused_textures(PreparedScene& prepared, net::BrickSource& source);

}  // namespace soltex::view
