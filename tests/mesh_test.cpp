// SPDX-License-Identifier: LGPL-2.1-or-later
// OBJ loading, normals, placement and geometry checks.
#include "caustic/mesh.hpp"
#include "scratch_dir.hpp"
#include "caustic/surfaces.hpp"
#include "scene_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace caustic;

namespace {

// A scratch folder of its own per test (dir_).
class ObjFiles : public caustic::testing::ScratchDirTest {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }

  // Expects load_obj to fail with a message containing `fragment`.
  void expect_error(const std::string& text, const std::string& fragment, const MeshLimits& limits = {}) {
    const auto path = write("bad.obj", text);
    try {
      load_obj(path, limits);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), "mesh");
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      // The message names the file, never the folder it lives in.
      EXPECT_EQ(std::string(e.what()).find(dir_.string()), std::string::npos) << e.what();
    }
  }

  void expect_error_at(const std::filesystem::path& file, const std::string& fragment) {
    try {
      load_obj(file);
      ADD_FAILURE() << "accepted " << file;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }

};

const char* kSquare =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "f 1 2 3\nf 1 3 4\n";

}  // namespace

TEST_F(ObjFiles, LoadsTrianglesAndComputesMissingNormals) {
  const Mesh m = load_obj(write("square.obj", kSquare));
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
  for (const auto& n : m.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);  // counter-clockwise seen from +z
}

TEST_F(ObjFiles, KeepsFileNormalsAndSplitsVerticesWithDifferentOnes) {
  const Mesh m = load_obj(write("n.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 0 1 0\n"
                                "f 1//1 2//1 3//1\nf 1//2 3//2 2//2\n"));
  EXPECT_EQ(m.positions.size(), 6u);
  EXPECT_FLOAT_EQ(m.normals[0].z, 1.0f);  // normalised
}

TEST_F(ObjFiles, RoundTripsThroughWriteObj) {
  const Mesh original = grid_mesh(plano_convex_lens(40, 10), 9, 7);
  write_obj(original, dir_ / "lens.obj");
  const Mesh loaded = load_obj(dir_ / "lens.obj");
  ASSERT_EQ(loaded.positions.size(), original.positions.size());
  ASSERT_EQ(loaded.triangles.size(), original.triangles.size());
  // Vertices may be renumbered; triangles keep their order and corners.
  for (std::size_t t = 0; t < loaded.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const unsigned a = loaded.triangles[t][k], b = original.triangles[t][k];
      EXPECT_NEAR(glm::length(loaded.positions[a] - original.positions[b]), 0.0f, 1e-5f);
      EXPECT_NEAR(glm::length(loaded.normals[a] - original.normals[b]), 0.0f, 1e-5f);
    }
}

// A disk that fills while the file is written fails the write: a small
// file's only write happens at the close, which was not checked, and a
// face cut short was kept as if whole. /dev/full fails every write (ENOSPC).
TEST_F(ObjFiles, AWriteTheDiskHasNoRoomForFails) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  const Mesh small = grid_mesh(plano_convex_lens(40, 10), 3, 3);
  try {
    write_obj(small, "/dev/full");
    ADD_FAILURE() << "a write into a full disk succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("error while writing /dev/full: No space left on device"), std::string::npos)
        << e.what();
  }
}

TEST_F(ObjFiles, ReadsAndWritesVertexColoursAsTheFacesTint) {
  const Mesh m = load_obj(write("tinted.obj",
                                "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 0.5 0.5 0.5\n"
                                "f 1 2 3\nf 1 3 4\n"));
  ASSERT_TRUE(tinted(m));
  ASSERT_EQ(m.colours.size(), m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    // Each colour stays with its position (vertices may be renumbered).
    const glm::vec3 p = m.positions[i], c = m.colours[i];
    const glm::vec3 expected = p == glm::vec3(0, 0, 0)   ? glm::vec3(1, 0, 0)
                               : p == glm::vec3(1, 0, 0) ? glm::vec3(0, 1, 0)
                               : p == glm::vec3(1, 1, 0) ? glm::vec3(0, 0, 1)
                                                         : glm::vec3(0.5f);
    EXPECT_EQ(c, expected) << i;
  }
  write_obj(m, dir_ / "again.obj");
  const Mesh again = load_obj(dir_ / "again.obj");
  EXPECT_EQ(again.colours, m.colours);
  EXPECT_FALSE(tinted(load_obj(write("clear.obj", kSquare))));
  // A joint weight (v x y z w) is no colour.
  EXPECT_FALSE(tinted(load_obj(write("w.obj", "v 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\nf 1 2 3\n"))));
}

TEST_F(ObjFiles, RejectsWhatTheLoaderWouldMisreadOrHoardBeforeItRuns) {
  const std::string corners = "v 0 0 0\nv 1 0 0\nv 1 1 0\n";
  // A face's index past 2^31 wrapped round to another vertex; "1.5" and
  // "3x" were read as 1 and 3.
  for (const char* face : {"f 1 2 99999999999999999999", "f 1 2 4294967299", "f 1.5 2 3", "f 1 2 3x", "f 1 2 +3",
                           "f 1 2 0", "f 1 2 3/", "f 1/1/1/1 2 3"})
    expect_error(corners + face + "\n", "line 4: a face's corner must be v, v/vt, v//vn or v/vt/vn");
  expect_error(corners + "f 1 2\n", "line 4: a face needs at least 3 corners");
  for (const char* vertex : {"v 0 0", "v 0 0 0 1 1", "v 0 0 0 1 1 1 1"})
    expect_error(std::string(vertex) + "\n" + corners + "f 2 3 4\n", "line 1: a vertex is x y z");
  expect_error(corners + "vn 0 0\nf 1 2 3\n", "line 4: a normal is x y z");
  expect_error(corners + "vt 0\nf 1 2 3\n", "line 4: a texture coordinate is u v");
  // Every "o" a shape in the loader: 8 million took 5 GB before the
  // triangle limit was checked; now counted first.
  std::string groups = corners;
  for (int i = 0; i < 4097; ++i) groups += "o a\nf 1 2 3\n";
  expect_error(groups, "line 8196: more than 4096 objects, groups and materials");
  // What the loader keeps of a line, a material switch, a normal or a
  // texture coordinate grew with the file (200 MB of "l" lines took 4 GB):
  // refused at its line, or counted against the limits.
  expect_error(corners + "f 1 2 3\nl 1 2 3 1 2 3\n", "line 5: a line (l) is no triangle");
  expect_error(corners + "f 1 2 3\n#" + std::string(1 << 16, 'x') + "\n", "line 5: longer than 65536 bytes");
  std::string materials = corners + "f 1 2 3\n";
  for (int i = 0; i < 4097; ++i) materials += "usemtl a\n";
  expect_error(materials, "line 4101: more than 4096 objects, groups and materials");
  MeshLimits limits;
  limits.max_triangles = 2;
  limits.max_vertices = 3;
  expect_error(corners + "f 1 2 3\nf 1 2 3\nf 1 2 3\n", "line 6: more than 2 faces", limits);
  expect_error(corners + "v 0 0 1\nf 1 2 3\n", "line 4: more than 3 vertices", limits);
  expect_error(corners + "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1 2 3\n", "line 7: more than 3 normals", limits);
  expect_error(corners + "vt 0 0\nvt 0 0\nvt 0 0\nvt 0 0\nf 1 2 3\n", "line 7: more than 3 texture coordinates",
               limits);
  // What stays: relative and full corners.
  EXPECT_NO_THROW(load_obj(write("ok.obj", corners + "vn 0 0 1\nvt 0 0\nf -3/1/1 -2/1/1 -1//1\n")));
}

TEST_F(ObjFiles, RejectsColoursOutOfRangeOrOnSomeVerticesOnly) {
  expect_error("v 0 0 0 1 0 0\nv 1 0 0 1.5 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n", "line 2: the colour 1.5 is outside [0, 1]");
  expect_error("v 0 0 0 1 0 -0.1\nv 1 0 0 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n", "-0.1 is outside");
  expect_error("v 0 0 0 1 0 0\nv 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n", "line 2: this vertex has no colour");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n", "line 3: this vertex has a colour");
  expect_error("v 0 0 0 1 0 nan\nv 1 0 0 1 0 0\nv 1 1 0 0 0 1\nf 1 2 3\n", "not a finite number");
  // The same rules for a mesh built in memory.
  Mesh m = load_obj(write("square.obj", kSquare));
  m.colours.assign(3, glm::vec3(1.0f));
  EXPECT_THROW(validate_mesh(m), SceneError);
  m.colours.assign(4, glm::vec3(1.0f));
  m.colours[2].g = std::nanf("");
  EXPECT_THROW(validate_mesh(m), SceneError);
  m.colours[2].g = 0.5f;
  EXPECT_NO_THROW(validate_mesh(m));
}

TEST_F(ObjFiles, RejectsBadFiles) {
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "only triangles");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\n", "line 4: a line (l) is no triangle");
  expect_error("v 0 0 0\nv 1 0 0\n", "no triangles");
  expect_error("", "no triangles");
  expect_error("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "line 3");
  expect_error("v 0 0 0\nv 1 0 0\nv inf 1 0\nf 1 2 3\n", "not a finite number");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1e999 0\nf 1 2 3\n", "not a finite number");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 x 0\nf 1 2 3\n", "\"x\"");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n", "does not exist");
  // Triangles on a line or at a point: nothing to bend light (it was drawn black).
  expect_error("v 0 0 0\nv 1 0 0\nv 2 0 0\nvn 0 0 1\nf 1//1 2//1 3//1\n", "has no area");
  expect_error("v 5 5 5\nv 5 5 5\nv 5 5 5\nvn 0 0 1\nf 1//1 2//1 3//1\nf 3//1 2//1 1//1\n", "has no area");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", "zero or not finite");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2e7 0 0\nf 1 2 3\nf 2 3 4\n", "coordinate limit");
  // Finite, but Inf as a float: the limit and the line, not "NaN or Inf".
  expect_error("v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n", "line 2: the coordinate 1e300 lies beyond the coordinate limit");
  MeshLimits small;
  small.max_vertices = 3;
  expect_error(kSquare, "more than 3 vertices", small);
  // Statements a caustic face never needs are refused before the loader
  // acts on them: a material library would be opened (here: read forever),
  // a joint weight converted to int unchecked.
  expect_error("mtllib ../../../../../../../../dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "\"mtllib\" is not supported");
  expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 1e39 1 0.5\nf 1 2 3\n", "\"vw\" is not supported");
  // The loader ends lines at a carriage return too; so does the check.
  expect_error("o a\rmtllib ../../../../dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "\"mtllib\" is not supported");
  // A file that is no OBJ is not quoted (its first 16 bytes once were).
  expect_error("root:$y$j9T$secret:19000:0:99999:7:::\n", "line 1: this line's statement is not supported");
  // A file from Windows ends its lines with "\r\n": one line each, as an
  // editor counts them.
  expect_error("v 0 0 0\r\nv 1 0 0\r\n\r\nv 1 x 0\r\nf 1 2 3\r\n", "line 4: \"x\"");
  expect_error("# a\rv 0 0 0\nv 1 0 0\nv 0 1 0 0.5 2 0.5\nf 1 2 3\n", "line 4: the colour 2 is outside");
  // Spaces and tabs separate words, as the loader reads them: to it a form
  // feed or a vertical tab is part of a word, and a NUL ends the line, so a
  // line holding one was checked as words the loader never read (a leading
  // form feed hid a vertex and the faces named others). Refused, with its line.
  expect_error("v\t0 0 0\nv 1\f0 0\nv 0 1 0\nf 1 2 3\n", "line 2: holds a control character");
  expect_error("v 0 0 0\nv 1 0 0\nv 1 1\v0\nf 1 2 3\n", "line 3: holds a control character");
  expect_error("\fv 5 5 -3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\n", "line 1: holds a control character");
  const char with_nul[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\0 7\nf 1 2 3\n";
  expect_error(std::string(with_nul, sizeof with_nul - 1), "line 3: holds a control character");
  // The loader reads no comment after a statement's words.
  expect_error("v 0 0 0 # corner\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: a comment (#) must be a line of its own");
}

TEST_F(ObjFiles, TheTextIsHeldOnce) {
  // The loader's own string reader copied the text: a 1 GiB file held 2 GiB.
  // A child with room for 128 MiB of text once, and 96 MiB besides, loads it.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "a sanitizer's own memory counts against the address space";
#endif
  const auto path = dir_ / "padded.obj";
  {
    std::ofstream out(path);
    out << kSquare;
    const std::string comment = "#" + std::string(1022, 'x') + "\n";
    for (int i = 0; i < 128 * 1024; ++i) out << comment;
  }
  long pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  const rlim_t room = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (rlim_t{224} << 20);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlimit limit{room, room};
    setrlimit(RLIMIT_AS, &limit);
    try {
      _exit(load_obj(path).triangles.size() == 2 ? 0 : 2);
    } catch (...) {
      _exit(1);
    }
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

TEST_F(ObjFiles, MissingFileIsAnError) {
  expect_error_at(dir_ / "absent.obj", "cannot read mesh file absent.obj (No such file or directory)");
  // A folder or a device is said to be one, not "cannot read" as if missing.
  expect_error_at(dir_, "is a folder, pipe, socket, device or kernel file, not a file");
  expect_error_at("/dev/zero", "mesh file zero is a folder, pipe, socket, device");
}

TEST(Placement, FitSizeCentresAndScalesTheFootprint) {
  const Mesh m = grid_mesh(flat_face(10), 5, 5);  // 20 x 20 footprint at z = 0
  ObjectParams o;
  o.fit_size = 100.0;
  o.position = {1, 2, 3};
  const Placement p = place_object(o, m);
  EXPECT_DOUBLE_EQ(p.scale, 5.0);
  const glm::dvec3 corner = glm::dvec3(p.model * glm::dvec4(10, 10, 0, 1));
  EXPECT_NEAR(corner.x, 51.0, 1e-12);
  EXPECT_NEAR(corner.y, 52.0, 1e-12);
  EXPECT_NEAR(glm::length(p.center - glm::dvec3(1, 2, 3)), 0.0, 1e-12);
}

TEST(Placement, FitSizePlacesByThePublicBoxNotTheHiddenTop) {
  // Two faces alike in all the proxy shows (footprint, lowest point, flat
  // face) and unlike in their highest point under the flat face, which is
  // hidden. Centred on the vertices' middle, fit_size moved the first by
  // half the difference: the followed screen then told the top to 1e-7 mm.
  const Mesh a = grid_mesh(plano_convex_lens(40, 10), 11, 11);
  Mesh b = a;
  const MeshBounds bounds = mesh_bounds(a, {0, 0, 1});
  for (auto& p : b.positions) p.z = static_cast<float>(bounds.lo.z + 0.5 * (p.z - bounds.lo.z));
  ASSERT_LT(mesh_bounds(b, {0, 0, 1}).hi.z, bounds.hi.z - 1);
  ObjectParams o;
  o.fit_size = 100.0;
  o.rotation_deg = {30, 0, 0};
  o.position = {1, 2, 3};
  o.flat_face_offset = bounds.hi.z + 1;
  const Placement pa = place_object(o, a), pb = place_object(o, b);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(pa.model[c][r], pb.model[c][r], 1e-9) << c << r;
  // The box's centre (flat face to lowest vertex) is what lands on position.
  glm::dvec3 centre(0.0);
  for (const auto& corner : pa.box) centre += corner / 8.0;
  EXPECT_NEAR(glm::length(centre - o.position), 0.0, 1e-9);
}

TEST(Placement, DefaultFlatFaceTouchesTheExtremeVertex) {
  const Mesh m = grid_mesh(plano_convex_lens(40, 10), 11, 11);
  ObjectParams o;
  const Placement p = place_object(o, m);
  const double sag = 40 - std::sqrt(1600.0 - 200.0);
  EXPECT_NEAR(p.flat_offset, sag, 1e-5);
  EXPECT_NEAR(p.max_depth, sag, 1e-5);
  o.flat_face_offset = 5.0;
  o.position = {0, 0, 10};
  EXPECT_NEAR(place_object(o, m).flat_offset, 15.0, 1e-12);
}

TEST(Placement, EulerAnglesFollowThreeJsXyzOrder) {
  // three.js Matrix4.makeRotationFromEuler(new Euler(a, b, c, 'XYZ')) first
  // row: (cos b cos c, -cos b sin c, sin b).
  const double a = 0.3, b = -0.7, c = 1.1;
  const glm::dmat3 r = euler_xyz_degrees(glm::degrees(glm::dvec3(a, b, c)));
  EXPECT_NEAR(r[0][0], std::cos(b) * std::cos(c), 1e-12);  // glm: r[column][row]
  EXPECT_NEAR(r[1][0], -std::cos(b) * std::sin(c), 1e-12);
  EXPECT_NEAR(r[2][0], std::sin(b), 1e-12);
  // Third row: (sin a sin c - cos a sin b cos c, ..., cos a cos b).
  EXPECT_NEAR(r[0][2], std::sin(a) * std::sin(c) - std::cos(a) * std::sin(b) * std::cos(c), 1e-12);
  EXPECT_NEAR(r[2][2], std::cos(a) * std::cos(b), 1e-12);
}

TEST(CheckGeometry, ThePublicCheckFollowsTheBoundingBoxAndIsStricter) {
  const Mesh m = grid_mesh(plano_convex_lens(40, 10), 11, 11);
  Scene s = scene_from_json(nlohmann::json{{"mesh", "lens.obj"}, {"screen", {{"center", {0, 0, -80}}}}}, ".");
  const Placement p = place_object(s.object, m);
  // A screen tilted 40 degrees: between the lens's corner (thin there) and
  // the box's corner, the vertices pass but the box does not.
  const double a = glm::radians(40.0);
  s.screen.normal = {0, std::sin(a), std::cos(a)};
  s.screen.up = {0, std::cos(a), -std::sin(a)};
  double lowest_box = 1e300, lowest_mesh = 1e300;
  for (const auto& corner : p.box) lowest_box = std::min(lowest_box, glm::dot(corner, s.screen.normal));
  for (const glm::dvec3 v : m.positions) lowest_mesh = std::min(lowest_mesh, glm::dot(glm::dvec3(p.model * glm::dvec4(v, 1.0)), s.screen.normal));
  ASSERT_LT(lowest_box, lowest_mesh - 0.1);
  s.screen.center = {0, 0, 0.5 * (lowest_box + lowest_mesh) / s.screen.normal.z};
  EXPECT_NO_THROW(check_geometry(s, m, p));
  EXPECT_THROW(check_geometry_public(s, p), SceneError);
  s.screen.center = {0, 0, (lowest_box - 1e-6) / s.screen.normal.z};
  EXPECT_NO_THROW(check_geometry_public(s, p));
}

TEST(CheckGeometry, RejectsWhatTheRayModelCannotRepresent) {
  const Mesh m = grid_mesh(plano_convex_lens(40, 10), 11, 11);
  Scene s = scene_from_json(nlohmann::json{{"mesh", "lens.obj"},
                                           {"object", {{"flat_face_offset", 4.0}}},
                                           {"screen", {{"center", {0, 0, -80}}}}},
                            ".");
  auto expect = [&](const Scene& scene, const std::string& key) {
    caustic::testing::expect_geometry_refused(scene, m, key);
  };
  EXPECT_NO_THROW(check_geometry(s, m, place_object(s.object, m)));
  Scene crossing = s;
  crossing.screen.center = {0, 0, 1};
  expect(crossing, "screen.center");
  Scene on_plane = s;
  on_plane.light.type = LightType::point;
  on_plane.light.position = {3, 0, 4.0};
  expect(on_plane, "light.position");
  Scene inside = on_plane;
  inside.light.position = {0, 0, 2.0};
  expect(inside, "light.position");
  Scene cut = s;
  cut.object.flat_face_offset = 1.0;  // below the lens edge
  expect(cut, "object.flat_face_offset");
}
