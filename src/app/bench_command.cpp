// SPDX-License-Identifier: LGPL-2.1-or-later
// `causticd bench`: the engine's frame time and its error against a
// converged reference, over methods x mesh resolutions x render sizes, on a
// few lens set-ups, and how the reference and the engine converge. Errors
// are taken at 128x128 after box filtering both images. Writes CSV files and
// charts (gnuplot, PNG and SVG) into the output folder; prints progress.
#include "commands.hpp"
#include "perf_bench.hpp"

#include "caustic/engine.hpp"
#include "caustic/exposure.hpp"
#include "caustic/gl_context.hpp"
#include "caustic/image_compare.hpp"
#include "caustic/reference.hpp"
#include "caustic/resample.hpp"
#include "caustic/surfaces.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>
#include <type_traits>

namespace caustic::app {
namespace {

struct BenchOptions {
  std::filesystem::path out;
  std::uint64_t photons = 50'000'000;
  int frames = 5;
  int source = 2048;  // vertices per side of the lens surface everything is resampled from
  std::vector<int> meshes{64, 128, 256, 512, 1024};
  std::vector<int> sizes{256, 512, 1024, 2048};
};

struct Setup {
  std::string name;
  nlohmann::json patch;                                    // on top of the lens scene
  std::vector<std::pair<std::string, nlohmann::json>> methods;  // name -> patch
};

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

// Error of the three measures at 128 x 128 after box filtering both images.
ImageError errors_at_128(const HdrImage& image, const HdrImage& reference, const Scene& scene) {
  const int f = image.width / 128;
  const HdrImage small_reference = box_down(reference, f);
  return compare(box_down(image, f), small_reference, exposure::settled_exposure(scene.post, small_reference),
                 scene.post.gamma);
}

void write_charts(const std::filesystem::path& out, const std::vector<Setup>& setups,
                  const std::vector<std::string>& engine_series) {
  std::string series;
  for (const auto& setup : setups)
    for (const auto& [method, patch] : setup.methods) series += (series.empty() ? "" : " ") + setup.name + ":" + method;
  std::string convergence;
  for (const auto& s : engine_series) convergence += (convergence.empty() ? "" : " ") + s;
  std::ostringstream plot;
  plot << "set datafile separator ','\nset key outside right\nset grid\nset logscale xy\n"
          "set fit quiet\nset fit logfile '/dev/null'\n"
          "files = 'png svg'\ndo for [f in files] {\n"
          "  if (f eq 'png') { set terminal pngcairo size 1100,650 } else { set terminal svg size 1100,650 }\n"
          "  set output 'accuracy.'.f\n"
          "  set xlabel 'caustic pass (ms)'\n  set ylabel 'relative L1 against the reference'\n"
          "  plot for [s in '"
       << series
       << "'] 'results.csv' using (strcol(1).':'.strcol(2) eq s ? $5 : 1/0):7 with points pointsize 1.2 title s\n"
          "  set output 'convergence.'.f\n  set multiplot layout 1,2\n  set key inside top right\n"
          "  set format x '10^{%T}'\n  set format y '10^{%T}'\n"
          "  set xlabel 'reference photons'\n  set ylabel 'relative L1 against the converged reference'\n"
          "  fit_a = 1\n  fit fit_a/sqrt(x) 'convergence.csv' using (strcol(1) eq 'reference' ? $2 : 1/0):3 via fit_a\n"
          "  plot 'convergence.csv' using (strcol(1) eq 'reference' ? $2 : 1/0):3 with linespoints title 'reference', "
          "fit_a/sqrt(x) title 'a / sqrt(N)' dashtype 2\n"
          "  set xlabel 'mesh vertices'\n  set ylabel 'engine relative L1 (energy)'\n"
          "  plot for [s in '"
       << convergence
       << "'] 'convergence.csv' using (strcol(1) eq s ? $2 : 1/0):3 with linespoints title s.' px'\n"
          "  unset multiplot\n  set format x '%g'\n  set format y '%g'\n  set key outside right\n}\n";
  write_text_files({{out / "chart.gp", plot.str()}});
  if (!run_gnuplot(out, "chart.gp", "gnuplot.log"))
    std::cerr << "causticd bench: gnuplot failed (see gnuplot.log); the CSV files are complete\n";
}

int run_bench(const BenchOptions& opt) {
  const std::vector<Setup> setups = {
      {"directional", {}, {{"energy", {}}, {"report", {{"render", {{"intensity", "report"}}}}},
                          {"no-fresnel", {{"render", {{"fresnel", false}}}}}}},
      {"point-near",
       {{"light", {{"type", "point"}, {"position", {2, 1, 40}}}}},
       {{"exact", {}}, {"approximate", {{"light", {{"point_model", "approximate"}}}}}}},
      {"tilted", {{"object", {{"rotation_deg", {12, -8, 0}}}}, {"light", {{"direction", {0.15, 0.1, -1}}}}},
       {{"energy", {}}}},
      // 8 mm before the focus, zoomed in: sharp structure, where vertices count.
      {"focus", {{"screen", {{"center", {0, 0, -72}}, {"width", 4}, {"height", 4}}}}, {{"energy", {}}}},
  };
  const Mesh source = grid_mesh(plano_convex_lens(40.0, 10.0), opt.source, opt.source);
  std::map<int, std::shared_ptr<const Mesh>> meshes;
  for (int n : opt.meshes) meshes[n] = std::make_shared<const Mesh>(resample_face(source, {0, 0, 1}, n));
  GlContext context(egl_platform_from_environment());
  Engine engine;
  std::ostringstream csv, conv;  // written whole at the end
  csv << "setup,method,mesh,pixels,ray_ms,post_ms,relative_l1,relative_rmse,ssim\n";
  conv << "series,x,relative_l1\n";
  std::vector<std::string> engine_series;
  std::printf("renderer: %s; reference: %llu photons on the %d^2 surface\n", context.renderer().c_str(),
              static_cast<unsigned long long>(opt.photons), opt.source);
  for (const auto& setup : setups) {
    for (int size : opt.sizes) {
      Scene base = apply_merge_patch(lens_scene(), setup.patch.is_null() ? nlohmann::json::object() : setup.patch);
      base.render.width = base.render.height = size;
      ReferenceOptions ro;
      ro.photons = opt.photons;
      const ReferenceResult ref = trace_reference(base, source, ro);
      std::printf("%s %d^2: reference %.1f s (%.1f M photons/s)\n", setup.name.c_str(), size, ref.seconds,
                  ref.photons / ref.seconds / 1e6);
      if (setup.name == "directional" && size == opt.sizes.front())
        for (std::uint64_t n = opt.photons / 512; n <= opt.photons / 8; n *= 4) {  // the reference's own convergence
          ReferenceOptions fewer;
          fewer.photons = n;
          fewer.seed = 2;
          const double l1 = errors_at_128(trace_reference(base, source, fewer).image, ref.image, base).relative_l1;
          conv << "reference," << n << ',' << l1 << '\n';
          std::printf("  reference with %llu photons: L1 %.5f\n", static_cast<unsigned long long>(n), l1);
        }
      for (const auto& [method, patch] : setup.methods) {
        const Scene scene = apply_merge_patch(base, patch.is_null() ? nlohmann::json::object() : patch);
        for (const auto& [n, mesh] : meshes) {
          std::vector<double> ray, post;
          for (int f = 0; f < opt.frames + 2; ++f) {
            engine.set_scene(scene, std::make_shared<const Mesh>(*mesh));  // a new handle forces a full frame
            engine.render();
            if (f >= 2) ray.push_back(engine.stats().ray_ms), post.push_back(engine.stats().post_ms);
          }
          const ImageError e = errors_at_128(engine.read_hdr(), ref.image, scene);
          csv << setup.name << ',' << method << ',' << n << ',' << size << ',' << middle_sample(ray) << ','
              << middle_sample(post) << ',' << e.relative_l1 << ',' << e.relative_rmse << ',' << e.ssim << '\n';
          if (method == "energy" && (setup.name == "focus" || (setup.name == "directional" && size == 1024)))
          {
            const std::string series = setup.name + ':' + std::to_string(size);
            if (std::find(engine_series.begin(), engine_series.end(), series) == engine_series.end())
              engine_series.push_back(series);
            conv << series << ',' << mesh->positions.size() << ',' << e.relative_l1 << '\n';
          }
          std::printf("  %-11s %-11s %4d^2 px, mesh %4d^2: %7.1f ms  L1 %.4f  RMSE %.4f  SSIM %.4f\n",
                      setup.name.c_str(), method.c_str(), size, n, middle_sample(ray), e.relative_l1, e.relative_rmse,
                      e.ssim);
          std::fflush(stdout);
        }
      }
    }
  }
  write_text_files({{opt.out / "results.csv", csv.str()}, {opt.out / "convergence.csv", conv.str()}});
  write_charts(opt.out, setups, engine_series);
  std::printf("wrote %s/results.csv, convergence.csv, accuracy.png/.svg, convergence.png/.svg\n",
              opt.out.string().c_str());
  return ok;
}

// A list flag's values once each, in the order given; "" when they fit, else
// why not, naming the flag. Bounded: at most 8 values, and the meshes (built
// before any timing) at most twice the largest's vertices in all.
template <typename T>
std::string fit_list(const char* flag, std::vector<T>& values, long long max_vertices = 0) {
  std::vector<T> once;
  for (const T& v : values)
    if (std::find(once.begin(), once.end(), v) == once.end()) once.push_back(v);
  values = once;
  if (values.size() > 8) return std::string(flag) + ": at most 8 values";
  long long vertices = 0;
  if constexpr (std::is_same_v<T, int>)
    for (int v : values) vertices += static_cast<long long>(v) * v;
  if (max_vertices > 0 && vertices > max_vertices)
    return std::string(flag) + ": at most " + std::to_string(max_vertices) + " vertices in all (" +
           std::to_string(vertices) + " asked; the meshes are built before the timing)";
  return "";
}

}  // namespace

std::function<int()> add_bench_command(CLI::App& app) {
  auto opt = std::make_shared<BenchOptions>();
  auto perf = std::make_shared<bool>(false);
  auto spectral = std::make_shared<bool>(false);
  auto multipass = std::make_shared<bool>(false);
  auto water = std::make_shared<bool>(false);
  auto water_opt = std::make_shared<WaterBenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Frame time and error against the reference over methods and sizes");
  cmd->add_option("--out", opt->out, "Folder for results.csv and the charts")->required();
  cmd->add_flag("--perf", *perf, "Frame costs instead (caustic, post, read-back, I420) over --meshes and --sizes: perf.csv");
  cmd->add_flag("--spectral", *spectral,
                "Grey against spectral frames (3, 8, 16 wavelengths) over --meshes and --sizes: spectral.csv; "
                "the prism's error against the wavelength count (reference: --photons, default 16 M here)")
      ->excludes("--perf");
  cmd->add_flag("--multipass", *multipass,
                "A biconvex solid by the multipass method at light grids 64..512: multipass.csv (faces: --meshes, "
                "default 256; sizes: --sizes, default 1024; reference: --photons, default 16 M here)")
      ->excludes("--perf")
      ->excludes("--spectral");
  CLI::Option* water_flag = cmd->add_flag("--water", *water,
                "A rainy pool's frames (simulation, mesh, caustic, post, I420) for each --grids and --sizes "
                "(default 1024) over --seconds of water: water.csv")
      ->excludes("--perf")
      ->excludes("--spectral")
      ->excludes("--multipass");
  cmd->add_option("--grids", water_opt->grids, "--water: water grids (vertices per side)")
      ->delimiter(',')
      ->transform(decimal())
      ->check(CLI::Range(16, 512))
      ->needs(water_flag);
  cmd->add_option("--seconds", water_opt->seconds, "--water: seconds of water to time, 30 frames each")
      ->check(decimal_real())
      ->check(finite_range(0.1, 120.0))
      ->needs(water_flag);
  cmd->add_option("--setups", water_opt->setups,
                  "--water: where the caustic pass sets up its triangles, a row each: auto (the CPU under a "
                  "software renderer), gpu (vertex and geometry stages), cpu")
      ->delimiter(',')
      ->transform(CLI::CheckedTransformer(kTriangleSetups, CLI::ignore_case))
      ->needs(water_flag);
  cmd->add_option("--divisors", water_opt->divisors,
                  "--water: the caustic at 1/N of the size per side, a row each: 1 full frames, 2 or more the "
                  "stream's previews (no bloom, the surface on every Nth post)")
      ->delimiter(',')
      ->transform(decimal())
      ->check(CLI::Range(1, 8))
      ->needs(water_flag);
  cmd->add_option("--photons", opt->photons, "Photons for each reference")
      ->transform(decimal())
      ->check(CLI::Range(1000, 2'000'000'000));
  cmd->add_option("--frames", opt->frames, "Timed frames per configuration (median)")
      ->transform(decimal())
      ->check(CLI::Range(1, 100));
  cmd->add_option("--source", opt->source, "Vertices per side of the surface the meshes are resampled from")
      ->transform(decimal())
      ->check(CLI::Range(16, 4096));
  cmd->add_option("--meshes", opt->meshes, "Mesh resolutions (vertices per side)")
      ->delimiter(',')->transform(decimal())->check(CLI::Range(8, 2048));
  cmd->add_option("--sizes", opt->sizes, "Render sizes (pixels per side, multiples of 128)")
      ->delimiter(',')
      ->transform(decimal())
      ->check(CLI::Range(128, 4096) & CLI::Validator([](std::string& v) {
                // Run even when the range check failed: it must not throw on a value that is no number.
                int n = 0;
                const auto [end, error] = std::from_chars(v.data(), v.data() + v.size(), n);
                return error == std::errc() && end == v.data() + v.size() && n % 128 == 0
                           ? std::string()
                           : std::string("must be a multiple of 128");
              }, "MULTIPLE OF 128"));
  return [cmd, opt, perf, spectral, multipass, water, water_opt] {
    if (!cmd->parsed()) return -1;
    for (const std::string& why : {fit_list("--meshes", opt->meshes, 2LL * 2048 * 2048), fit_list("--sizes", opt->sizes),
                                   fit_list("--grids", water_opt->grids), fit_list("--divisors", water_opt->divisors),
                                   fit_list("--setups", water_opt->setups)})
      if (!why.empty()) {
        std::cerr << "causticd bench: " << why << "\n";
        return static_cast<int>(bad_input);
      }
    // A flag the chosen bench never reads would seem to have shaped its rows: said.
    const char* mode = *perf ? "--perf" : *water ? "--water" : *multipass ? "--multipass" : "--spectral";
    std::vector<const char*> unread;
    if (*perf) unread = {"--photons", "--source"};
    else if (*water) unread = {"--photons", "--source", "--meshes", "--frames"};
    else if (*multipass || *spectral) unread = {"--source"};
    for (const char* flag : unread)
      if (cmd->count(flag)) std::cerr << "causticd bench: warning: " << flag << ": has no effect with " << mode << "\n";
    if (!bench_folder_ready(opt->out)) return static_cast<int>(bad_input);
    try {
      if (*perf) return run_perf_bench({opt->out, opt->frames, opt->meshes, opt->sizes});
      if (*water) {
        const auto sizes = cmd->count("--sizes") ? opt->sizes : std::vector<int>{1024};
        return run_water_bench({opt->out, opt->frames, opt->meshes, sizes}, *water_opt);
      }
      if (*multipass) {
        const std::uint64_t photons = cmd->count("--photons") ? opt->photons : 16'000'000;
        const auto meshes = cmd->count("--meshes") ? opt->meshes : std::vector<int>{256};
        const auto sizes = cmd->count("--sizes") ? opt->sizes : std::vector<int>{1024};
        return run_multipass_bench({opt->out, opt->frames, meshes, sizes, photons});
      }
      if (*spectral) {
        // The prism's reference traces 32 bands: a third of the lens bench's photons is plenty.
        const std::uint64_t photons = cmd->count("--photons") ? opt->photons : 16'000'000;
        return run_spectral_bench({opt->out, opt->frames, opt->meshes, opt->sizes, photons});
      }
      return run_bench(*opt);
    } catch (const std::exception& e) {
      std::cerr << "causticd bench: " << e.what() << "\n";
      return static_cast<int>(runtime_failure);
    }
  };
}

}  // namespace caustic::app
