// SPDX-License-Identifier: LGPL-2.1-or-later
// The scene a caustic render models: the object (its flat face, material and
// pose), the light, the screen rectangle, and the render and post-processing
// settings. docs/scene-format.md documents every key of the JSON form.
#pragma once

#include "caustic/colour.hpp"
#include "caustic/dispersion.hpp"
#include "caustic/receiver_mesh.hpp"
#include "caustic/water_params.hpp"

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace caustic {

/// A rejected scene, parameter patch or mesh. `key` names the offending JSON
/// key path ("object.ior") or is empty when the problem is not a single key.
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string key, const std::string& message)
      : std::runtime_error(key.empty() ? message : key + ": " + message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

enum class Material { refractive, reflective };
/// What the mesh is: the caustic face of a slab whose other face is the flat
/// plane (the per-vertex method), a closed glass body whose every face
/// refracts (the multipass tracer: double-sided lenses, stacked pieces), or
/// the surface of a medium that fills the space beyond it, screen included
/// (water over a pool's floor: one refraction, per vertex, and the light
/// lands without leaving the medium).
enum class Shape { slab, solid, surface };
enum class LightType { directional, point };
enum class PointModel { approximate, exact };
enum class IntensityMode { energy, report };
enum class Fidelity { automatic, manual };
enum class ExposureMode { automatic, manual };
enum class ToneMap { global, local };

/// A dispersive material: a catalogue glass by name (optics::materials())
/// or a law given by its coefficients (name empty).
struct Glass {
  std::string name;
  std::variant<optics::Sellmeier, optics::Cauchy> law;
  /// The index at `nm` (a validated glass has one in [1, 10] over 380..780 nm).
  double index(double nm) const;
  bool operator==(const Glass&) const = default;
};

struct ObjectParams {
  Material material = Material::refractive;
  /// "solid": the mesh is closed and wound outward; the flat face then only
  /// orients the footprint (fit_size, the public box) and is not glass.
  Shape shape = Shape::slab;
  /// The index of a glass without dispersion; with `glass` set, the glass's
  /// index at the d line (587.6 nm), which monochrome frames use.
  double ior = 1.5;
  std::optional<Glass> glass;  ///< none: one index for every wavelength
  glm::dvec3 flat_face_normal{0, 0, 1};     ///< outward, mesh coordinates, unit
  std::optional<double> flat_face_offset;   ///< plane dot(x, n) = offset; default: extreme vertex
  glm::dvec3 position{0, 0, 0};
  glm::dvec3 rotation_deg{0, 0, 0};         ///< Euler angles, three.js order "XYZ"
  std::optional<double> fit_size;           ///< footprint size after centring; none: file units

  bool operator==(const ObjectParams&) const = default;
};

struct LightParams {
  LightType type = LightType::directional;
  glm::dvec3 direction{0, 0, -1};  ///< propagation direction of a directional light, unit
  glm::dvec3 position{0, 0, 100};  ///< point light position
  PointModel point_model = PointModel::exact;
  /// What the light emits; a spectral frame white-balances to it (colour.hpp).
  optics::LightSpectrum spectrum;

  bool operator==(const LightParams&) const = default;
};

/// A receiver shaped as a surface of revolution (caustic/receiver_mesh.hpp):
/// a vase, a bowl, a column. Its mesh is built when the scene is read.
struct Lathe {
  std::vector<glm::dvec2> profile;  ///< (radius, height along up) from the centre of its base
  int segments = 64;                ///< steps round the axis
  std::shared_ptr<const ReceiverMesh> mesh;  ///< world space; follows from the rest

  bool operator==(const Lathe& o) const { return profile == o.profile && segments == o.segments; }
};

/// A receiver of a shape its scene file brings (caustic/receiver_meshes.hpp),
/// by name; placed as a lathe is.
struct ShapedMesh {
  std::string name;                          ///< one of the scene's receiver_meshes
  std::shared_ptr<const ReceiverMesh> mesh;  ///< world space; follows from the rest

  bool operator==(const ShapedMesh& o) const { return name == o.name; }
};

struct ScreenParams {
  glm::dvec3 center{0, 0, -100};
  glm::dvec3 normal{0, 0, 1};  ///< unit, facing the object
  glm::dvec3 up{0, 1, 0};      ///< unit, perpendicular to normal after validation
  double width = 40;
  double height = 40;
  /// The rectangle slides in its plane to stay on the light's footprint
  /// (caustic/screen_follow.hpp); center then fixes only the plane.
  bool follow_light = false;
  /// A receiver of this shape instead of a rectangle: center is its base,
  /// up its axis, normal where its atlas starts; width and height are then
  /// 1, its atlas's (u, v) square.
  std::optional<Lathe> lathe;
  /// Or a shape of the scene file's, placed the same way.
  std::optional<ShapedMesh> shaped;

  /// A lathe's or a shape's triangles, in the world; null on a rectangle.
  const ReceiverMesh* body() const {
    return lathe ? lathe->mesh.get() : shaped ? shaped->mesh.get() : nullptr;
  }
  bool operator==(const ScreenParams&) const = default;
};

struct RenderParams {
  int width = 1024;
  int height = 1024;
  IntensityMode intensity = IntensityMode::energy;
  bool fresnel = true;
  double report_plane_distance = 1.0;  ///< virtual plane behind the screen, "report" mode
  /// "auto": the server picks mesh_resolution, light.point_model and fresnel
  /// (the cheapest calibrated configuration meeting accuracy_target);
  /// "manual": they are used as written. Renderers only read the three.
  Fidelity fidelity = Fidelity::automatic;
  double accuracy_target = 0.05;  ///< relative L1 against the reference, for "auto"
  int mesh_resolution = 0;        ///< 0: the mesh as loaded; n: resampled on an n x n grid
  /// Wavelength samples of a spectral frame (object.glass set); previews
  /// while the scene moves use at most kPreviewWavelengths.
  int wavelengths = 8;
  /// Wavelength samples of a spectral picture left standing (the stream
  /// draws it once more after a moment's stillness); at most
  /// optics::kMaxWavelengths, and a count at or below `wavelengths` adds none.
  int still_wavelengths = 32;
  /// Rays per side of the light's grid that the multipass tracer follows
  /// through a solid (object.shape "solid"); previews use a coarser grid.
  int light_grid = 256;

  bool operator==(const RenderParams&) const = default;
};

struct PostParams {
  /// "auto": the exposure is metered from each frame (the auto_percentile
  /// of the lit pixels lands just below white, docs/physics.md) and
  /// `exposure` multiplies it (exposure compensation, 1 = as metered);
  /// "manual": `exposure` is used as written.
  ExposureMode exposure_mode = ExposureMode::automatic;
  double exposure = 1.0;
  double auto_percentile = 0.99;  ///< of the lit pixels, for "auto"
  double exposure_adapt_s = 0.25; ///< time constant of "auto" following a change; 0: at once
  /// "global": one curve for the whole picture; "local": large-scale
  /// brightness compressed by local_strength first, detail kept.
  ToneMap tone_map = ToneMap::global;
  double local_strength = 0.5;    ///< 0: as global, 1: large-scale variation flattened
  double gamma = 2.2;
  double bloom_threshold = 1.0;
  double bloom_strength = 0.3;
  double bloom_radius = 8.0;  ///< Gaussian sigma in output pixels

  bool operator==(const PostParams&) const = default;
};

/// Largest coordinate a scene may hold (mm): far beyond any real set-up, small
/// enough that squared distances stay exact in doubles.
inline constexpr double kMaxCoordinate = 1e6;
/// Wavelength samples of a spectral preview (the scene moving).
inline constexpr int kPreviewWavelengths = 3;
/// Receivers besides the screen (caustic/receivers.hpp): eight surfaces in
/// all, the atlas's tiles.
inline constexpr std::size_t kMaxReceivers = 7;
/// A lathe's profile points and steps round its axis at the most: 32,768
/// triangles, built in milliseconds each time a patch moves it.
inline constexpr std::size_t kMaxLatheProfile = 64;
inline constexpr int kMaxLatheSegments = 256;

struct ReceiverMeshTable;

struct Scene {
  std::string name;
  std::string description;
  std::string mesh;                      ///< OBJ path as written, relative to base_dir
  std::filesystem::path base_dir;        ///< folder of the scene file; not part of the JSON
  std::optional<double> focus_distance;  ///< places the screen when screen.center is omitted
  ObjectParams object;
  LightParams light;
  ScreenParams screen;
  /// More rectangles that catch the light (a floor, walls, a table): each
  /// ray lands on the first one it meets, the screen included, and each
  /// gets its own tile of the picture (caustic/receivers.hpp). Their
  /// follow_light is false.
  std::vector<ScreenParams> receivers;
  /// The shapes receivers may take (the scene file's receiver_meshes), read
  /// with the file and shared by every scene patched from it; null: none.
  std::shared_ptr<const ReceiverMeshTable> receiver_meshes;
  RenderParams render;
  PostParams post;
  /// A pool whose surface is the caustic face (object.shape "surface"):
  /// made by the wave solver instead of read from `mesh`, and moving while
  /// a stream shows it.
  std::optional<water::WaveParams> water;

  std::filesystem::path mesh_path() const { return base_dir / mesh; }
  bool operator==(const Scene&) const = default;
};

/// Parses and validates a scene; every key is checked, unknown keys are
/// rejected. Throws SceneError naming the key. `loaded`: the receiver
/// meshes already read for this scene (a patch's); its "receiver_meshes"
/// must then list the same files, and no file is opened.
Scene scene_from_json(const nlohmann::json& j, const std::filesystem::path& base_dir,
                      std::shared_ptr<const ReceiverMeshTable> loaded = nullptr);

/// The complete JSON form of a scene (every key, defaults filled in).
nlohmann::json scene_to_json(const Scene& scene);

/// Validates a scene built in code the same way a parsed one is (ranges,
/// finiteness, unit vectors), so NaN or Inf never reach a renderer.
/// Throws SceneError naming the key.
void validate_scene(const Scene& scene);

/// The largest scene file read: scenes name their meshes, never hold them.
inline constexpr std::size_t kMaxSceneFileBytes = std::size_t{16} << 20;
/// The most rays a frame may trace (one per wavelength): a solid's
/// light_grid², or a manual mesh_resolution², times its still frame's
/// wavelengths. A scene that asks more is refused, naming the key.
inline constexpr std::uint64_t kMaxFrameRays = std::uint64_t{1} << 23;

/// Reads a scene file (at most kMaxSceneFileBytes, parsed as every outside
/// JSON text is: caustic/json_text.hpp). Throws SceneError on I/O, size,
/// syntax or validation errors. `written`, when given, receives the file's
/// JSON as written, for warnings about keys that other settings override.
Scene load_scene(const std::filesystem::path& file, nlohmann::json* written = nullptr);

/// Applies an RFC 7396 JSON merge patch and validates the result; the input
/// scene is left untouched, so a rejected patch changes nothing. With an
/// `origin` (the scene as its file wrote it), a null restores the origin's
/// value at that place instead of the global default.
Scene apply_merge_patch(const Scene& scene, const nlohmann::json& patch, const Scene* origin = nullptr);

/// Applies `patches` in turn and validates once, at the end: a later patch
/// may make an earlier one fit (the CLI's `--set water.grid=64 --set
/// object.shape=surface`, in either order).
Scene apply_merge_patches(const Scene& scene, const std::vector<nlohmann::json>& patches);

/// Turns "a.b.c=value" into a merge patch {"a":{"b":{"c":value}}}; the value
/// is read as JSON when it parses, otherwise as a string.
nlohmann::json patch_from_assignment(const std::string& assignment);

}  // namespace caustic
