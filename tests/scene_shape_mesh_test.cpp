// SPDX-License-Identifier: LGPL-2.1-or-later
// A receiver shaped by a mesh the scene file brings (receiver_meshes): read
// with the file, placed in the receiver's frame, written back by name; a
// patch moves it without opening a file and may not list one; bad files,
// names and receivers are named by their key.
#include "caustic/receiver_meshes.hpp"
#include "caustic/receivers.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace caustic;
using namespace caustic::testing;

namespace {

// A folder of its own with a scene's files in it, gone with the test.
class Folder {
 public:
  Folder() : path_(std::filesystem::temp_directory_path() / ("caustic_shape_" + std::to_string(getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~Folder() { std::filesystem::remove_all(path_); }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A plate 4 mm wide (x) and 2 mm deep (y), 1 mm up its z, its atlas across it.
const char* const kPlate =
    "v -2 -1 1\nv 2 -1 1\nv 2 1 1\nv -2 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

json plate_scene() {
  json doc = minimal();
  doc["receiver_meshes"] = {{"plate", "plate.obj"}};
  // Standing on the floor at x = 40, facing -x, up along z: the plate's x
  // runs along up x normal = (0, -1, 0), its y along z, its z along -x.
  doc["receivers"] = {{{"center", {40, 0, -30}}, {"normal", {-1, 0, 0}}, {"up", {0, 0, 1}}, {"mesh", "plate"}}};
  return doc;
}

}  // namespace

TEST(SceneShapeMesh, ReadPlacedAndWrittenBackByName) {
  Folder dir;
  dir.write("plate.obj", kPlate);
  const Scene s = scene_from_json(plate_scene(), dir.path());
  ASSERT_TRUE(s.receivers[0].shaped);
  EXPECT_EQ(s.receivers[0].shaped->name, "plate");
  EXPECT_EQ(s.receivers[0].width, 1.0);  // its tile is its (u, v) square
  const ReceiverMesh* body = s.receivers[0].body();
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(body->triangle_count(), 2u);
  // x in [-2, 2] along -y, y in [-1, 1] along z, z = 1 along -x: from the centre (40, 0, -30).
  EXPECT_NEAR(body->lower().x, 39, 1e-12);
  EXPECT_NEAR(body->upper().x, 39, 1e-12);
  EXPECT_NEAR(body->lower().y, -2, 1e-12);
  EXPECT_NEAR(body->upper().y, 2, 1e-12);
  EXPECT_NEAR(body->lower().z, -31, 1e-12);
  EXPECT_NEAR(body->upper().z, -29, 1e-12);
  // A ray along +x at y = 1 (u = 1/4 from the plate's x = 2 end, since x runs along -y), z = -29.5.
  const ReceiverHit hit = first_receiver(s, {0, 1, -29.5}, {1, 0, 0});
  EXPECT_EQ(hit.index, 1);
  EXPECT_NEAR(hit.distance, 39, 1e-12);
  EXPECT_NEAR(hit.local.x, 0.25 - 0.5, 1e-12);
  EXPECT_NEAR(hit.local.y, 0.75 - 0.5, 1e-12);
  EXPECT_NEAR(surface_stretch(s.receivers[0], hit.element), 8.0, 1e-12);  // 8 mm^2 over the unit square
  EXPECT_TRUE(has_shaped_receiver(s));
  const json back = scene_to_json(s);
  EXPECT_EQ(back["receivers"][0]["mesh"], "plate");
  EXPECT_FALSE(back["receivers"][0].contains("width"));
  EXPECT_EQ(back["receiver_meshes"], json({{"plate", "plate.obj"}}));
  EXPECT_EQ(scene_from_json(back, dir.path(), s.receiver_meshes), s);
}

TEST(SceneShapeMesh, APatchMovesItWithoutOpeningAFileAndMayNotListOne) {
  Folder dir;
  dir.write("plate.obj", kPlate);
  const Scene s = scene_from_json(plate_scene(), dir.path());
  std::filesystem::remove(dir.path() / "plate.obj");  // read once: a patch must not need it
  json patch = {{"receivers", plate_scene()["receivers"]}};
  patch["receivers"][0]["center"] = {50, 0, -30};
  const Scene moved = apply_merge_patch(s, patch);
  EXPECT_EQ(moved.receiver_meshes, s.receiver_meshes);  // the same table, not read again
  EXPECT_NEAR(moved.receivers[0].body()->lower().x, 49, 1e-12);
  // A patch that leaves it where it stands shares its placed triangles
  // (placed anew, each patch once held the main loop for every shape).
  EXPECT_EQ(apply_merge_patch(s, {{"object", {{"ior", 1.6}}}}).receivers[0].body(), s.receivers[0].body());
  // A second receiver of the same shape, added by the patch.
  patch["receivers"].push_back(plate_scene()["receivers"][0]);
  EXPECT_EQ(apply_merge_patch(s, patch).receivers.size(), 2u);
  // The same file read again is another table: never taken for the first's.
  dir.write("plate.obj", kPlate);
  EXPECT_NE(scene_from_json(plate_scene(), dir.path()).receivers[0].body(), s.receivers[0].body());
  for (const json& files : {json({{"plate", "plate.obj"}}), json({{"other", "/etc/passwd"}}), json(nullptr)}) {
    try {
      apply_merge_patch(s, {{"receiver_meshes", files}});
      ADD_FAILURE() << "a patch listed receiver_meshes " << files.dump();
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), "receiver_meshes");
    }
  }
  // Validating a scene made in code reads nothing either.
  EXPECT_NO_THROW(validate_scene(moved));
}

TEST(SceneShapeMesh, BadReceiversAreNamed) {
  Folder dir;
  dir.write("plate.obj", kPlate);
  const auto rejected = [&](const json& doc, const std::string& key, const std::string& says = "") {
    try {
      scene_from_json(doc, dir.path());
      ADD_FAILURE() << "accepted: " << doc.dump();
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find(dir.path().string()), std::string::npos) << "a path: " << e.what();
    }
  };
  json doc = plate_scene();
  doc["receivers"][0]["mesh"] = "bowl";
  rejected(doc, "receivers[0].mesh", "one of this scene's receiver_meshes: plate");
  doc = plate_scene();
  doc.erase("receiver_meshes");
  rejected(doc, "receivers[0].mesh", "lists none");
  doc = plate_scene();
  doc["receivers"][0]["width"] = 3;
  rejected(doc, "receivers[0].width");
  doc = plate_scene();
  doc["receivers"][0]["lathe"] = {{"profile", {{5, 0}, {5, 3}}}};
  rejected(doc, "receivers[0].mesh", "not both");
  doc = plate_scene();
  doc["screen"] = doc["receivers"][0];
  rejected(doc, "screen.mesh");
  doc = plate_scene();
  doc["receiver_meshes"] = {{"../plate", "plate.obj"}};
  rejected(doc, "receiver_meshes", "names are 1 to 32");
  doc["receiver_meshes"] = json::array({"plate.obj"});
  rejected(doc, "receiver_meshes");
  doc["receiver_meshes"] = json::object();
  for (int i = 0; i < 9; ++i) doc["receiver_meshes"]["m" + std::to_string(i)] = "plate.obj";
  rejected(doc, "receiver_meshes", "at most 8");
  doc = plate_scene();
  doc["receiver_meshes"]["plate"] = 3;
  rejected(doc, "receiver_meshes.plate", "path of an OBJ file");
  doc["receiver_meshes"]["plate"] = "missing.obj";
  rejected(doc, "receiver_meshes.plate", "cannot read mesh file missing.obj");
  // A NUL ended the name where the system reads it: this loaded plate.obj.
  doc["receiver_meshes"]["plate"] = std::string("plate.obj\0junk", 14);
  rejected(doc, "receiver_meshes.plate", "must not hold control characters");
  // Its atlas on every corner, inside the unit square.
  dir.write("bare.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  doc["receiver_meshes"]["plate"] = "bare.obj";
  rejected(doc, "receiver_meshes.plate", "without a texture coordinate");
  dir.write("wide.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 2 0\nvt 0 1\nf 1/1 2/2 3/3\n");
  doc["receiver_meshes"]["plate"] = "wide.obj";
  rejected(doc, "receiver_meshes.plate", "outside [0, 1]");
  dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt nan 0\nvt 0 1\nf 1/1 2/2 3/3\n");
  doc["receiver_meshes"]["plate"] = "nan.obj";
  rejected(doc, "receiver_meshes.plate", "not a finite number");
}

TEST(SceneShapeMesh, AnAtlasSeamSplitsCornersAndPartsTheTriangles) {
  // Two triangles sharing an edge in space, their atlas cut along it: the
  // shared positions become four vertices, so the two are not one piece;
  // a third triangle touching both corner to corner joins them.
  Folder dir;
  const auto file = dir.write("seam.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                          "vt 0 0\nvt 0.4 0\nvt 0.4 1\nvt 0.6 0\nvt 1 1\nvt 0.6 1\n"
                                          "f 1/1 2/2 3/3\nf 1/4 3/5 4/6\n");
  const Mesh seam = load_atlas_obj(file);
  EXPECT_EQ(seam.positions.size(), 6u);
  const ReceiverMesh split = place_receiver_mesh(seam, {0, 0, 0}, {0, 0, 1}, {0, 1, 0});
  EXPECT_FALSE(split.continuous(0, 1));
  Mesh joined = seam;
  joined.uvs = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0, 0}, {0.5, 0.5}, {0, 0.5}};
  joined.triangles.emplace_back(0, 2, 4);  // corners 0 and 2 of the first, 4 of the second
  const ReceiverMesh bridged = place_receiver_mesh(joined, {0, 0, 0}, {0, 0, 1}, {0, 1, 0});
  EXPECT_TRUE(bridged.continuous(0, 1));

  // On one piece, landings apart by up to an eighth of the atlas span one:
  // a strip of 32 quads along u, 1/32 each.
  Mesh strip;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i <= 32; ++i) {
      strip.positions.emplace_back(i, j, 0);
      strip.uvs.emplace_back(i / 32.0, j);
    }
  for (unsigned i = 0; i < 32; ++i) {
    strip.triangles.emplace_back(i, i + 1, i + 34);
    strip.triangles.emplace_back(i, i + 34, i + 33);
  }
  const ReceiverMesh long_piece = place_receiver_mesh(strip, {0, 0, 0}, {0, 0, 1}, {0, 1, 0});
  EXPECT_TRUE(long_piece.continuous(0, 6));    // three quads: 3/32 of u
  EXPECT_FALSE(long_piece.continuous(0, 12));  // six: 6/32, more than 1/8
}
