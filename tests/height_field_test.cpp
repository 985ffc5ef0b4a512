// SPDX-License-Identifier: LGPL-2.1-or-later
// A slab's caustic face as a height field over its flat face: a face whose
// triangles overlap seen from the flat face once drew twice the light that
// crossed the glass (the engine 1.84x what the reference tracer found).
#include "caustic/height_field.hpp"
#include "caustic/scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <unistd.h>

using namespace caustic;

namespace {

// An n x n grid over [-10, 10]² at height z (a gentle ripple), flat face along +z.
Mesh grid(int n, float z = -1.0f) {
  Mesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = -10.0f + 20.0f * i / (n - 1), y = -10.0f + 20.0f * j / (n - 1);
      m.positions.push_back({x, y, z + 0.1f * std::sin(x) * std::cos(y)});
      m.normals.push_back({0, 0, 1});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const unsigned a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}

Mesh joined(const Mesh& first, const Mesh& second) {
  Mesh m = first;
  const auto base = static_cast<unsigned>(m.positions.size());
  m.positions.insert(m.positions.end(), second.positions.begin(), second.positions.end());
  m.normals.insert(m.normals.end(), second.normals.begin(), second.normals.end());
  for (glm::uvec3 t : second.triangles) m.triangles.push_back(t + glm::uvec3(base));
  return m;
}

std::string refusal(const Mesh& mesh, glm::dvec3 normal = {0, 0, 1}) {
  try {
    check_height_field(mesh, normal);
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "mesh");
    return e.what();
  }
  return "";
}

}  // namespace

TEST(HeightField, AGridOverTheFlatFacePasses) {
  EXPECT_EQ(refusal(grid(64)), "");
  EXPECT_EQ(refusal(grid(2)), "");
  // Seen along any normal the grid is not folded over: tilted 45°, still one layer.
  EXPECT_EQ(refusal(grid(64), glm::normalize(glm::dvec3(1, 0, 1))), "");
  // Edge-on (a plane seen with the flat face at right angles to it): no
  // footprint, nothing to overlap. The rippled grid seen so folds over itself.
  Mesh plane = grid(16);
  for (auto& p : plane.positions) p.z = -1.0f;
  EXPECT_EQ(refusal(plane, {1, 0, 0}), "");
  EXPECT_NE(refusal(grid(16), {1, 0, 0}), "");
}

TEST(HeightField, EveryFaceWrittenTwiceIsRefused) {
  const Mesh once = grid(64);
  Mesh twice = once;
  twice.triangles.insert(twice.triangles.end(), once.triangles.begin(), once.triangles.end());
  const std::string why = refusal(twice);
  EXPECT_NE(why.find("overlap"), std::string::npos) << why;
  EXPECT_NE(why.find("at least 2"), std::string::npos) << why;  // refused as soon as it is past the share let pass
}

TEST(HeightField, TwoSheetsStackedAreRefused) {
  EXPECT_NE(refusal(joined(grid(48, -1.0f), grid(48, -1.001f))), "");
  // Side by side they are one layer: [-10, 10] and [20, 40] apart.
  Mesh beside = grid(32);
  for (auto& p : beside.positions) p.x += 30.0f;
  EXPECT_EQ(refusal(joined(grid(32), beside)), "");
}

TEST(HeightField, AFoldIsRefusedAndASliverOfOnePasses) {
  // The middle third of the columns folded back over the first: the face
  // runs right, back left over itself, then right again.
  Mesh folded = grid(33);
  for (auto& p : folded.positions)
    if (p.x > -10.0f / 3 && p.x < 10.0f / 3) p.x = -p.x;
  EXPECT_NE(refusal(folded), "");
  // One column's vertices pushed a fifth of a cell past their neighbours':
  // a sliver of fold, under 2% of the footprint, as designed faces have.
  Mesh sliver = grid(65);
  for (auto& p : sliver.positions)
    if (std::abs(p.x - 0.0f) < 1e-4f) p.x += 0.2f * 20.0f / 64 + 20.0f / 64;
  EXPECT_EQ(refusal(sliver), "");
}

TEST(HeightField, AThinFootprintOrLayersByTheThousandAreCheckedInBoundedWork) {
  // A footprint 20 x 2e-13 once asked 2.5 GB of sample points; at 1e-20
  // its rows overflowed an int. The sheet is edge-on to rounding: nothing
  // to overlap.
  Mesh sliver = grid(8);
  for (auto& p : sliver.positions) p.y *= 1e-14f;
  EXPECT_EQ(refusal(sliver), "");
  // A footprint 20 x 0.002: a thin one, still checked (and a layer twice over refused).
  Mesh strip = grid(64);
  for (auto& p : strip.positions) p.y *= 1e-4f;
  EXPECT_EQ(refusal(strip), "");
  EXPECT_NE(refusal(joined(strip, strip)), "");
  // Two thousand triangles each over the whole footprint: refused as soon
  // as the overlap passes the share let pass, not after walking them all.
  Mesh layers;
  for (int k = 0; k < 2000; ++k) {
    const auto base = static_cast<unsigned>(layers.positions.size());
    for (const glm::vec3 p : {glm::vec3(-10, -10, -1 - 0.001f * k), glm::vec3(10, -10, -1 - 0.001f * k),
                              glm::vec3(-10, 10, -1 - 0.001f * k)}) {
      layers.positions.push_back(p);
      layers.normals.push_back({0, 0, 1});
    }
    layers.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_NE(refusal(layers).find("overlap"), std::string::npos);
}

TEST(HeightField, ASceneFaceIsCheckedAsItLoads) {
  const auto folder = std::filesystem::temp_directory_path() / ("height_field_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  Mesh twice = grid(16);
  const std::vector<glm::uvec3> once = twice.triangles;
  twice.triangles.insert(twice.triangles.end(), once.begin(), once.end());
  write_obj(twice, folder / "twice.obj");
  write_obj(grid(16), folder / "once.obj");
  nlohmann::json doc;
  doc["mesh"] = "twice.obj";
  doc["object"]["flat_face_offset"] = 1.0;
  Scene scene = scene_from_json(doc, folder);
  try {
    load_face(scene);
    ADD_FAILURE() << "a face of every triangle twice loaded";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("overlap"), std::string::npos) << e.what();
  }
  scene.mesh = "once.obj";
  EXPECT_EQ(load_face(scene).triangles.size(), once.size());
  std::filesystem::remove_all(folder);
}
