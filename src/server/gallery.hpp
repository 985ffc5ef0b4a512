// SPDX-License-Identifier: LGPL-2.1-or-later
// The scenes a server offers: parsed scene files with their meshes, a
// rendered thumbnail each, and the proxy geometry a browser may draw.
#pragma once

#include "caustic/fidelity.hpp"
#include "caustic/mesh.hpp"
#include "caustic/mesh_levels.hpp"
#include "caustic/wave_solver.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <functional>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic {
class Engine;
}

namespace caustic::server {

struct GalleryEntry {
  std::string id;  ///< the scene file's name without .json
  Scene scene;
  std::shared_ptr<const Mesh> mesh;           ///< as loaded (of a scene with water: its warmed-up surface)
  std::shared_ptr<const water::WaveSolver> water;  ///< a scene with water: warmed up once, each session's start
  std::shared_ptr<const MeshLevels> levels;   ///< `mesh` and its coarser grids
  std::optional<Calibration> calibration;     ///< from <id>.calibration.json when it matches
  std::vector<unsigned char> thumbnail_png;
  nlohmann::json proxy;  ///< outline, thickness, pose: never the mesh itself
  /// The shapes its receivers may take (receiver_meshes), name -> geometry:
  /// scenery a viewer draws the light on, made once. Null when none.
  nlohmann::json shapes;
  bool designed = false;  ///< made by the designer from a picture (listed first), not an optics classic
  /// A solid's light grid as its file wrote it (0 for anything else): the
  /// finest auto may choose, for every session, whatever grid auto chose
  /// before (the scene a session patches is the resolved one).
  int own_light_grid = 0;
};

struct Gallery {
  std::map<std::string, std::shared_ptr<const GalleryEntry>> entries;
  std::vector<std::string> problems;  ///< scene files that were skipped, and why
  std::string renderer;               ///< GL_RENDERER of the context that drew the thumbnails
};

/// Loads every *.json in `dir` whose name is a valid id ([a-z0-9_-]+)
/// (an entry is `designed` when `dir`/../designs/<id>.report.json exists)
/// (calibrations, *.calibration.json, belong to the scene of that id),
/// builds its mesh levels, renders each thumbnail (thumbnail x thumbnail pixels) with a GL context
/// of its own on the calling thread. Broken scenes are skipped and reported.
/// `cancel`, when given and set, stops it between scenes (a shutdown during
/// a reload).
Gallery load_gallery(const std::filesystem::path& dir, int thumbnail = 256, const std::atomic<bool>* cancel = nullptr);

/// One scene file `file` as the entry `id`: parsed, its mesh loaded with its
/// levels and calibration, its thumbnail rendered with `engine()` (called
/// once the scene has parsed, on a thread whose GL context is current).
/// `mesh`, when given, is the scene's mesh already in memory (a design just
/// made), which is then not read again. Throws what the scene, mesh and
/// engine throw.
std::shared_ptr<GalleryEntry> load_entry(const std::filesystem::path& file, const std::string& id,
                                         const std::function<Engine&()>& engine, int thumbnail = 256,
                                         std::shared_ptr<const Mesh> mesh = nullptr);

/// The public description of an entry for GET /api/v1/scenes.
nlohmann::json describe(const GalleryEntry& entry);

/// What a session of this entry renders for `scene`: fidelity "auto"
/// resolved against the entry's calibration and levels.
Scene resolve_for(const GalleryEntry& entry, Scene scene);

/// The fidelity block of GET .../params for `scene` (already resolved).
nlohmann::json fidelity_of(const GalleryEntry& entry, const Scene& scene);

/// Proxy geometry of a scene: outline (footprint size), thickness, flat-face
/// normal and pose in world units.
nlohmann::json proxy_geometry(const Scene& scene, const Mesh& mesh);

}  // namespace caustic::server
