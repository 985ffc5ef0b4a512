# SPDX-License-Identifier: LGPL-2.1-or-later
# Writes a C++ source that holds every shader file as a string, so the binary
# does not depend on where its data files are installed.
# Inputs: OUTPUT (the .cpp to write), SHADERS (files separated by "|").
string(REPLACE "|" ";" SHADERS "${SHADERS}")
set(body "// Generated from shaders/ by cmake/embed_shaders.cmake; do not edit.\n#include \"shader_sources.hpp\"\n\nnamespace caustic::shaders {\n\nconst std::map<std::string_view, std::string_view>& sources() {\n  static const std::map<std::string_view, std::string_view> table = {\n")
foreach(file IN LISTS SHADERS)
  get_filename_component(name "${file}" NAME)
  file(READ "${file}" text)
  string(APPEND body "    {\"${name}\", R\"glsl(${text})glsl\"},\n")
endforeach()
string(APPEND body "  };\n  return table;\n}\n\n}  // namespace caustic::shaders\n")
file(WRITE "${OUTPUT}.tmp" "${body}")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
