// SPDX-License-Identifier: LGPL-2.1-or-later
#include "gallery.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/height_field.hpp"
#include "caustic/image_io.hpp"
#include "caustic/pool.hpp"
#include "caustic/receiver_meshes.hpp"
#include "caustic/water_mesh.hpp"
#include "caustic/resample.hpp"
#include "caustic/screen_follow.hpp"
#include "caustic/spectral.hpp"
#include "log.hpp"

#include <algorithm>

#include <regex>
#include <thread>

namespace caustic::server {

nlohmann::json proxy_geometry(const Scene& scene, const Mesh& mesh) {
  const Placement p = place_object(scene.object, mesh);
  const auto v = [](const glm::dvec3& x) { return nlohmann::json::array({x.x, x.y, x.z}); };
  // Middle of the slab: from the flat face, half the thickness inward.
  const glm::dvec3 on_flat = onto_flat_face(p, p.center);
  const glm::dvec3 slab_center = on_flat - 0.5 * p.max_depth * p.flat_normal;
  return {{"outline", {p.footprint.x, p.footprint.y}},
          {"center", v(slab_center)},
          {"thickness", p.max_depth},
          {"flat_face_normal", v(p.flat_normal)},
          {"shape", scene_to_json(scene)["object"]["shape"]},  // the names' one table
          {"position", v(scene.object.position)},
          {"rotation_deg", v(scene.object.rotation_deg)}};
}

nlohmann::json describe(const GalleryEntry& e) {
  return {{"id", e.id},
          {"name", e.scene.name},
          {"description", e.scene.description},
          {"thumbnail", "/api/v1/scenes/" + e.id + "/thumbnail.png"},
          {"kind", e.designed ? "designed" : "classic"},
          {"proxy", e.proxy},
          {"mesh_levels", e.levels->resolutions()},
          {"calibrated", e.calibration.has_value()}};
}

Scene resolve_for(const GalleryEntry& entry, Scene scene) {
  const Placement placed = entry.levels->place(scene.object);
  scene = follow_light(std::move(scene), placed);
  return resolve_fidelity(scene, choose_fidelity(entry.calibration, scene.render.accuracy_target, *entry.levels,
                                                      scene.object.shape == Shape::solid ? entry.own_light_grid : 0));
}

nlohmann::json fidelity_of(const GalleryEntry& entry, const Scene& scene) {
  return describe_fidelity(scene, *entry.mesh, *entry.levels, entry.calibration);
}

namespace {

// All of load_entry() but the thumbnail: no GL, so several scenes may be
// prepared at once, each on a thread of its own.
std::shared_ptr<GalleryEntry> prepare_entry(const std::filesystem::path& file, const std::string& id,
                                            std::shared_ptr<const Mesh> mesh) {
  auto entry = std::make_shared<GalleryEntry>();
  entry->id = id;
  nlohmann::json written;
  entry->scene = load_scene(file, &written);
  if (entry->scene.water && !mesh) {
    auto warmed = std::make_shared<const water::WaveSolver>(water::warmed_up(*entry->scene.water));
    mesh = std::make_shared<const Mesh>(water::water_mesh(*warmed));
    entry->water = std::move(warmed);
  }
  entry->mesh = mesh ? std::move(mesh) : std::make_shared<const Mesh>(load_face(entry->scene));
  entry->levels = std::make_shared<const MeshLevels>(
      build_mesh_levels(entry->mesh, entry->scene.object.flat_face_normal, coarser_resolutions(*entry->mesh, entry->scene)));
  // Calibrated as rendered: with the screen where following puts it.
  const Scene placed = follow_light(entry->scene, entry->levels->place(entry->scene.object));
  entry->calibration = load_calibration(calibration_path(file), scene_fingerprint(placed, *entry->mesh));
  if (const auto note = stale_calibration_note(file, entry->calibration); !note.empty())
    log(Level::warning, "scene " + id + ": " + note);
  entry->own_light_grid = light_grid_bound(entry->scene);
  entry->scene = resolve_for(*entry, entry->scene);
  if (const auto& table = entry->scene.receiver_meshes)
    for (const auto& [name, shape] : table->meshes) entry->shapes[name] = receiver_mesh_json(shape);
  // A value the scene file writes for a key that fidelity "auto" decides, or
  // that another setting overrides: say so rather than ignore it.
  for (const auto& [key, detail] : scene_overrides(written, entry->scene))
    log(Level::warning, "scene " + id + ": " + detail);
  // A manual scene may name a level not on offer: at() throws then.
  entry->levels->at(entry->scene.render.mesh_resolution);
  entry->proxy = proxy_geometry(entry->scene, *entry->mesh);
  return entry;
}

// The thumbnail from the mesh level a session renders: what a visitor will
// see, and a spectral scene's K passes stay cheap at start-up.
void draw_thumbnail(GalleryEntry& entry, Engine& engine, int thumbnail) {
  Scene small = entry.scene;
  small.render.width = small.render.height = thumbnail;
  engine.set_scene(small, entry.levels->at(entry.scene.render.mesh_resolution), false, entry.levels->bounds);
  engine.render();
  entry.thumbnail_png = encode_png(engine.read_ldr());
}

}  // namespace

std::shared_ptr<GalleryEntry> load_entry(const std::filesystem::path& file, const std::string& id,
                                         const std::function<Engine&()>& engine, int thumbnail,
                                         std::shared_ptr<const Mesh> mesh) {
  auto entry = prepare_entry(file, id, std::move(mesh));
  draw_thumbnail(*entry, engine(), thumbnail);
  return entry;
}

Gallery load_gallery(const std::filesystem::path& dir, int thumbnail, const std::atomic<bool>* cancel) {
  Gallery gallery;
  static const std::regex id_pattern("[a-z0-9_-]{1,64}");
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& f : std::filesystem::directory_iterator(dir, ec))
    if (f.path().extension() == ".json" && f.path().stem().extension() != ".calibration") files.push_back(f.path());
  if (ec) gallery.problems.push_back("cannot list " + dir.string() + ": " + ec.message());
  std::sort(files.begin(), files.end());  // problems in a stable order
  // Scenes are read, meshed and resampled on every core at once (most of
  // a start-up: megabytes of OBJ text and a hierarchy a scene), then drawn
  // one after another on this thread, the only one with a GL context.
  std::vector<std::string> ids;
  for (const auto& file : files) {
    const std::string id = file.stem().string();
    ids.push_back(std::regex_match(id, id_pattern) ? id : "");
  }
  std::vector<std::shared_ptr<GalleryEntry>> prepared(files.size());
  std::vector<std::string> failed(files.size());
  std::atomic<std::size_t> next{0};
  const auto prepare = [&]() {
    for (std::size_t n; (n = next++) < files.size();) {
      if ((cancel && *cancel) || ids[n].empty()) continue;
      try {
        prepared[n] = prepare_entry(files[n], ids[n], nullptr);
      } catch (const std::exception& e) {
        failed[n] = e.what();
      }
    }
  };
  {
    const std::size_t helpers = std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), files.size());
    std::vector<std::jthread> crew;
    for (std::size_t k = 1; k < helpers; ++k) crew.emplace_back(prepare);
    prepare();
  }
  std::unique_ptr<GlContext> context;
  std::unique_ptr<Engine> engine;
  for (std::size_t n = 0; n < files.size(); ++n) {
    if (cancel && *cancel) break;
    const std::string name = files[n].filename().string();
    if (ids[n].empty()) {
      gallery.problems.push_back(name + ": not a valid scene id");
      continue;
    }
    if (!prepared[n]) {
      gallery.problems.push_back(name + ": " + failed[n]);
      continue;
    }
    try {
      // The GL context is made only once a scene has parsed: a folder of
      // broken files needs none.
      if (!context) {
        context = std::make_unique<GlContext>(egl_platform_from_environment());
        engine = std::make_unique<Engine>();
        gallery.renderer = context->renderer();
      }
      auto& entry = prepared[n];
      draw_thumbnail(*entry, *engine, thumbnail);
      // The designer leaves its report beside the scenes folder
      // (assets/designs/<id>.report.json): such a scene projects a picture.
      std::error_code exists_ec;
      entry->designed = std::filesystem::exists(dir / ".." / "designs" / (ids[n] + ".report.json"), exists_ec);
      gallery.entries[ids[n]] = std::move(entry);
    } catch (const std::exception& e) {
      gallery.problems.push_back(name + ": " + e.what());
    }
  }
  if (context) {
    engine.reset();
    context->release_current();
  }
  return gallery;
}

}  // namespace caustic::server
