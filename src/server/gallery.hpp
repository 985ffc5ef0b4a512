// The scenes a server offers: parsed scene files with their meshes, a
// rendered thumbnail each, and the proxy geometry a browser may draw.
#pragma once

#include "caustic/mesh.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic::server {

struct GalleryEntry {
  std::string id;  ///< the scene file's name without .json
  Scene scene;
  std::shared_ptr<const Mesh> mesh;
  std::vector<unsigned char> thumbnail_png;
  nlohmann::json proxy;  ///< outline, thickness, pose: never the mesh itself
};

struct Gallery {
  std::map<std::string, std::shared_ptr<const GalleryEntry>> entries;
  std::vector<std::string> problems;  ///< scene files that were skipped, and why
  std::string renderer;               ///< GL_RENDERER of the context that drew the thumbnails
};

/// Loads every *.json in `dir` whose name is a valid id ([a-z0-9_-]+),
/// renders each thumbnail (thumbnail x thumbnail pixels) with a GL context
/// of its own on the calling thread. Broken scenes are skipped and reported.
Gallery load_gallery(const std::filesystem::path& dir, int thumbnail = 256);

/// The public description of an entry for GET /api/v1/scenes.
nlohmann::json describe(const GalleryEntry& entry);

/// Proxy geometry of a scene: outline (footprint size), thickness, flat-face
/// normal and pose in world units.
nlohmann::json proxy_geometry(const Scene& scene, const Mesh& mesh);

}  // namespace caustic::server
