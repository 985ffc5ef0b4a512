// SPDX-License-Identifier: LGPL-2.1-or-later
// Shader files from shaders/, embedded into the binary at build time.
#pragma once

#include <map>
#include <string_view>

namespace caustic::shaders {

/// File name ("caustic.vert") -> source text.
const std::map<std::string_view, std::string_view>& sources();

}  // namespace caustic::shaders
