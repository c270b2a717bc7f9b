#pragma once

#include "soltex/common/texture_spec.h"
#include "soltex/scene/bounding_box.h"
#include "soltex/scene/scene.h"

namespace soltex {

// The object's bounds where its texture is evaluated: the mesh's box in object space, or
// the box of the transformed vertices in world space.
BoundingBox texture_space_bounds(const SceneObject& object);

// The default cache cube around texture-space bounds: a cube (so voxels are cubes and one
// screen footprint maps to one level) on the bounds' centre, its side the longest side of
// the bounds plus 1/32 of it on each end, so samples on the surface never fall outside
// after rounding and flat objects get some thickness.
Volume padded_cube(const BoundingBox& bounds, int finest_level_log2);

// Whether the material's explicit volume box holds the object's texture-space bounds, up to
// a millionth of the box's side for rounding; true when the volume is the default one. Outside
// its volume an object's texture is the volume's edge, one flat colour, which is never meant.
bool explicit_volume_contains_object(const SceneObject& object);

// The validated volume for an object: the material's explicit box and level where given,
// otherwise padded_cube(texture_space_bounds(object)) and the client's level.
Volume texture_volume(const SceneObject& object, int client_finest_level_log2);

}  // namespace soltex
