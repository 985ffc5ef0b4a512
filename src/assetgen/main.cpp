// SPDX-License-Identifier: LGPL-2.1-or-later
// Generates the meshes of the built-in scenes (assets/scenes/*.json) from
// their analytic surfaces. Units are millimetres; every caustic face sits
// below a flat face with outward normal +z; a solid is closed round its
// centre. A receiver's shape (caustic/receiver_meshes.hpp) lies in its own
// frame, x and y across it, z toward the light, its atlas in the file.
#include "caustic/surfaces.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

namespace {

// A cloth laid in soft folds, 16 x 12 mm: ridges 4 mm apart, 1.6 mm high,
// bending along their length; (u, v) straight across it, so a fold's flank
// that faces the light shows brighter in the atlas than one facing away.
caustic::Mesh folded_cloth() {
  constexpr int nx = 65, ny = 49;
  constexpr double width = 16, depth = 12, rise = 1.6, period = 4;
  caustic::Mesh m;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double u = double(i) / (nx - 1), v = double(j) / (ny - 1);
      const double x = (u - 0.5) * width, y = (v - 0.5) * depth;
      const double phase = 2 * std::numbers::pi * (x / period + 0.15 * std::sin(2 * std::numbers::pi * y / depth));
      m.positions.emplace_back(x, y, rise * 0.5 * (1 + std::sin(phase)));
      m.uvs.emplace_back(u, v);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const unsigned a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      m.triangles.emplace_back(a, b, c);
      m.triangles.emplace_back(a, c, d);
    }
  m.normals = caustic::smooth_normals(m.positions, m.triangles);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Generate the built-in caustic meshes"};
  std::filesystem::path out;
  int resolution = 256;
  app.add_option("--out", out, "Folder for the OBJ files")->required();
  app.add_option("--resolution", resolution, "Vertices per side")->check(CLI::Range(2, 2048));
  CLI11_PARSE(app, argc, argv);

  using namespace caustic;
  const double k = 2.0 * std::numbers::pi / 5.0;  // 5 mm period
  const struct {
    const char* name;
    HeightField surface;
  } meshes[] = {
      // Plano-convex: R = 40 mm, n = 1.5 -> f = 80 mm; 20 mm square aperture.
      {"lens", plano_convex_lens(40.0, 10.0)},
      {"slab", flat_face(10.0)},
      {"cylinder", cylindrical_lens(40.0, 10.0)},
      // Sum of sines, amplitude 0.05 mm: folds begin at 1/((n-1) A k^2) = 25.3 mm.
      {"wavy", sine_window(0.05, k, 0.05, k, 10.0)},
      // A 35 degree prism bar, 2 mm across its dispersion, 16 mm long.
      {"prism", wedge(35.0 * std::numbers::pi / 180.0, 1.0, 8.0)},
  };
  try {
    std::filesystem::create_directories(out);
    for (const auto& m : meshes) {
      const auto file = out / (std::string(m.name) + ".obj");
      write_obj(grid_mesh(m.surface, resolution, resolution), file);
      std::cout << "wrote " << file.string() << "\n";
    }
    // Biconvex, both faces R = 40 mm, 6 mm thick on the axis, 20 mm square:
    // f = 41.03 mm, back focal length 38.97 mm from the lower apex (z = -3).
    const auto file = out / "biconvex.obj";
    write_obj(biconvex_lens(40.0, 40.0, 6.0, 10.0, resolution), file);
    std::cout << "wrote " << file.string() << "\n";
    const auto cloth = out / "cloth.obj";
    write_obj(folded_cloth(), cloth);
    std::cout << "wrote " << cloth.string() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "caustic-assetgen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
