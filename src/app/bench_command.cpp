// `causticd bench`: the engine's frame time and its error against a
// converged reference, over methods x mesh resolutions x render sizes, on a
// few lens set-ups. Errors are taken at 128x128 after box filtering both
// images. Writes results.csv and an error-against-time chart
// (gnuplot, PNG and SVG) into the output folder; prints progress.
#include "commands.hpp"

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/reference.hpp"
#include "caustic/resample.hpp"
#include "caustic/surfaces.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

namespace caustic::app {
namespace {

struct BenchOptions {
  std::filesystem::path out;
  std::uint64_t photons = 50'000'000;
  int frames = 5;
  std::vector<int> meshes{64, 128, 256, 512};
  std::vector<int> sizes{256, 512, 1024};
};

struct Setup {
  std::string name;
  nlohmann::json patch;                                    // on top of the lens scene
  std::vector<std::pair<std::string, nlohmann::json>> methods;  // name -> patch
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Box-filters a square image down to `side` pixels (side divides its size),
// keeping the mean: errors are compared at one resolution, where the
// reference's photon noise is small next to the methods' differences.
HdrImage box_down(const HdrImage& img, int side) {
  const int f = img.width / side;
  HdrImage out{side, side, std::vector<float>(static_cast<std::size_t>(side) * side, 0.0f)};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      out.pixels[static_cast<std::size_t>(y / f) * side + x / f] += img.at(x, y) / static_cast<float>(f * f);
  return out;
}

std::pair<double, double> errors(const HdrImage& full, const HdrImage& full_ref) {
  const HdrImage a = box_down(full, 128), ref = box_down(full_ref, 128);
  double diff = 0, sum = 0, sq = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = a.pixels[i] - ref.pixels[i];
    diff += std::abs(d);
    sum += std::abs(ref.pixels[i]);
    sq += d * d;
  }
  const double mean = sum / ref.pixels.size();
  return {diff / sum, std::sqrt(sq / a.pixels.size()) / mean};  // RMSE relative to the mean
}

Scene lens_scene() {
  Scene s;
  s.mesh = "generated";
  s.object.flat_face_offset = 4.0;
  s.screen.center = {0, 0, -40};
  s.screen.width = s.screen.height = 16;
  s.render.fresnel = true;
  s.post.bloom_strength = 0;
  return s;
}

int run_bench(const BenchOptions& opt) {
  std::filesystem::create_directories(opt.out);
  const std::vector<Setup> setups = {
      {"directional", {}, {{"energy", {}}, {"report", {{"render", {{"intensity", "report"}}}}},
                          {"no-fresnel", {{"render", {{"fresnel", false}}}}}}},
      {"point-near",
       {{"light", {{"type", "point"}, {"position", {2, 1, 40}}}}},
       {{"exact", {}}, {"approximate", {{"light", {{"point_model", "approximate"}}}}}}},
      {"tilted", {{"object", {{"rotation_deg", {12, -8, 0}}}}, {"light", {{"direction", {0.15, 0.1, -1}}}}},
       {{"energy", {}}}},
  };
  const Mesh source = grid_mesh(plano_convex_lens(40.0, 10.0), 1024, 1024);
  std::map<int, std::shared_ptr<const Mesh>> meshes;
  for (int n : opt.meshes) meshes[n] = std::make_shared<const Mesh>(resample_face(source, {0, 0, 1}, n));
  GlContext context(egl_platform_from_environment());
  Engine engine;
  std::ofstream csv(opt.out / "results.csv");
  csv << "setup,method,mesh,pixels,ray_ms,post_ms,relative_l1,relative_rmse\n";
  std::printf("renderer: %s; reference: %llu photons on the 1024^2 surface\n", context.renderer().c_str(),
              static_cast<unsigned long long>(opt.photons));
  for (const auto& setup : setups) {
    for (int size : opt.sizes) {
      Scene base = apply_merge_patch(lens_scene(), setup.patch.is_null() ? nlohmann::json::object() : setup.patch);
      base.render.width = base.render.height = size;
      ReferenceOptions ro;
      ro.photons = opt.photons;
      const ReferenceResult ref = trace_reference(base, source, ro);
      std::printf("%s %d^2: reference %.1f s (%.1f M photons/s)\n", setup.name.c_str(), size, ref.seconds,
                  ref.photons / ref.seconds / 1e6);
      for (const auto& [method, patch] : setup.methods) {
        const Scene scene = apply_merge_patch(base, patch.is_null() ? nlohmann::json::object() : patch);
        for (const auto& [n, mesh] : meshes) {
          std::vector<double> ray, post;
          for (int f = 0; f < opt.frames + 2; ++f) {
            engine.set_scene(scene, std::make_shared<const Mesh>(*mesh));  // a new handle forces a full frame
            engine.render();
            if (f >= 2) ray.push_back(engine.stats().ray_ms), post.push_back(engine.stats().post_ms);
          }
          const auto [l1, rmse] = errors(engine.read_hdr(), ref.image);
          csv << setup.name << ',' << method << ',' << n << ',' << size << ',' << median(ray) << ',' << median(post)
              << ',' << l1 << ',' << rmse << '\n';
          std::printf("  %-11s %-11s mesh %4d^2: %7.1f ms  L1 %.4f  RMSE %.4f\n", setup.name.c_str(),
                      method.c_str(), n, median(ray), l1, rmse);
          std::fflush(stdout);
        }
      }
    }
  }
  csv.close();
  // The chart: error on a log axis against frame time, one series per method and set-up.
  std::ofstream plot(opt.out / "chart.gp");
  plot << "set datafile separator ','\nset logscale xy\nset xlabel 'caustic pass (ms, llvmpipe)'\n"
          "set ylabel 'relative L1 against the reference'\nset key outside right\nset grid\n"
          "files = 'png svg'\ndo for [f in files] {\n"
          "  if (f eq 'png') { set terminal pngcairo size 1100,650 } else { set terminal svg size 1100,650 }\n"
          "  set output 'accuracy.'.f\n"
          "  plot for [s in 'directional:energy directional:report directional:no-fresnel point-near:exact "
          "point-near:approximate tilted:energy'] 'results.csv' using (strcol(1).':'.strcol(2) eq s ? $5 : 1/0):7 "
          "with points pointsize 1.2 title s\n}\n";
  plot.close();
  const std::string command = "cd '" + opt.out.string() + "' && gnuplot chart.gp";
  if (std::system(command.c_str()) != 0) std::cerr << "causticd bench: gnuplot failed; results.csv is complete\n";
  std::printf("wrote %s/results.csv, accuracy.png, accuracy.svg\n", opt.out.string().c_str());
  return ok;
}

}  // namespace

std::function<int()> add_bench_command(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Frame time and error against the reference over methods and sizes");
  cmd->add_option("--out", opt->out, "Folder for results.csv and the charts")->required();
  cmd->add_option("--photons", opt->photons, "Photons for each reference")->check(CLI::Range(1000, 2'000'000'000));
  cmd->add_option("--frames", opt->frames, "Timed frames per configuration (median)")->check(CLI::Range(1, 100));
  cmd->add_option("--meshes", opt->meshes, "Mesh resolutions (vertices per side)")->check(CLI::Range(8, 2048));
  cmd->add_option("--sizes", opt->sizes, "Render sizes (pixels per side, multiples of 128)")
      ->check(CLI::Range(128, 4096) & CLI::Validator([](std::string& v) {
                return std::stoi(v) % 128 ? std::string("must be a multiple of 128") : std::string();
              }, "MULTIPLE OF 128"));
  return [cmd, opt] {
    if (!cmd->parsed()) return -1;
    try {
      return run_bench(*opt);
    } catch (const std::exception& e) {
      std::cerr << "causticd bench: " << e.what() << "\n";
      return static_cast<int>(runtime_failure);
    }
  };
}

}  // namespace caustic::app
