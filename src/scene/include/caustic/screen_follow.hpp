// SPDX-License-Identifier: LGPL-2.1-or-later
// The screen rectangle that follows the light (screen.follow_light): a turned
// light moves the caustic across the screen plane, and a fixed rectangle
// would lose it. The plane stays where the scene put it (through
// screen.center, facing screen.normal); the rectangle slides in it to stay
// centred on the light's footprint.
#pragma once

#include "caustic/mesh.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustic {

/// Where the light through the middle of the object's flat face meets the
/// screen plane: along light.direction (or from a point light through that
/// middle), mirrored about the flat face for a reflective object. Treats the
/// object as a thin slab: refraction through a slab shifts a ray sideways by
/// at most its thickness times the tangent of the refracted angle, small
/// beside any screen worth following. Empty when the light runs parallel to
/// the plane or away from it.
std::optional<glm::dvec3> light_footprint(const Scene& scene, const Placement& placement);

/// With screen.follow_light, the scene with screen.center moved in its plane
/// to light_footprint, at most kMaxFollow screen sizes from the foot of the
/// object on the plane (grazing light smears the picture over the plane
/// anyway). Otherwise, or without a footprint, the scene as it was.
Scene follow_light(Scene scene, const Placement& placement);

inline constexpr double kMaxFollow = 8.0;

/// Where a reflective object's focus_distance puts a screen whose normal the
/// scene leaves out: facing back along the light the mirror's flat face
/// reflects (the object's pose counts; light straight down onto a face
/// looking up gives [0, 0, -1]). Empty for a refractive object, or when the
/// reflection would leave behind the mirror.
std::optional<glm::dvec3> reflected_screen_normal(const ObjectParams& object, const LightParams& light);

/// A screen.center that `written` (a scene file or a patch) sets but that
/// following moved (`scene` is the result): only its distance along the
/// normal counted. One (key, detail) pair, or none.
std::vector<std::pair<std::string, std::string>> follow_overrides(const nlohmann::json& written, const Scene& scene);

}  // namespace caustic
