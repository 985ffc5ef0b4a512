// SPDX-License-Identifier: LGPL-2.1-or-later
// Settings that are valid but show a visitor little or nothing: the light
// travels away from the screen, or misses it. They are judged on the public
// proxy only (the object's bounding box, as glass or a mirror whose far
// face is flat: parallel to the flat face, or tilted as far as the box's
// thickness across its width allows, the tilt that lands the most light),
// never on the freeform face, so a warning says nothing about the secret
// mesh; a freeform face bends the light unevenly, so the shares are rough.
#pragma once

#include "caustic/mesh.hpp"
#include "caustic/scene.hpp"

#include <string>
#include <vector>

namespace caustic {

struct SceneWarning {
  std::string key;     ///< the setting to change, e.g. "screen.center"
  std::string detail;  ///< what happens and what to do
};

/// The share of the object's footprint whose light lands on the screen
/// rectangle, traced through the proxy on a 9 x 9 grid (0 to 1).
double proxy_share_on_screen(const Scene& scene, const Placement& placement);

/// Warnings for `scene` posed by `placement` (only its bounding box and flat
/// face are read): none when most of the light lands on the screen.
std::vector<SceneWarning> light_warnings(const Scene& scene, const Placement& placement);

}  // namespace caustic
