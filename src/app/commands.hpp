// SPDX-License-Identifier: LGPL-2.1-or-later
// Subcommands of the causticd executable. Each registers itself on the CLI
// and returns the exit status when it runs.
#pragma once

#include "caustic/fidelity.hpp"
#include "caustic/mesh.hpp"

#include <optional>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace caustic::app {

/// A random seed: digits alone, 0 to 2^64 - 1 (CLI11 took "-1" as
/// 2^64 - 1 and wrapped larger numbers).
inline CLI::Validator seed_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        errno = 0;
        const bool digits = !text.empty() && text.size() <= 20 && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits) std::strtoull(text.c_str(), nullptr, 10);
        return digits && errno == 0 ? "" : "must be a whole number in [0, 2^64 - 1]";
      },
      "UINT64");
}

/// An integer flag in decimal digits alone, leading zeros dropped: CLI11
/// read "064" as octal (52 pixels) and "0x40" as hex, where the scene's keys
/// and the server's settings take decimal only. A minus is left to the
/// flag's range to refuse. Used as ->transform(decimal()) before the range.
inline CLI::Validator decimal() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (!text.empty() && text[0] == '+') text.erase(0, 1);
        const std::size_t sign = !text.empty() && text[0] == '-' ? 1 : 0;
        if (text.size() == sign || text.find_first_not_of("0123456789", sign) != std::string::npos)
          return "must be a whole number in decimal digits, got \"" + text + "\"";
        const std::size_t first = std::min(text.find_first_not_of('0', sign), text.size() - 1);
        text.erase(sign, first - sign);
        return "";
      },
      "");
}

/// A real-valued flag in decimal notation alone (digits, a point, an
/// exponent): CLI11 read C's hex floats too, "--size 0x10" as 16 mm.
inline CLI::Validator decimal_real() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return !text.empty() && text.find_first_not_of("0123456789.eE+-") == std::string::npos
                   ? ""
                   : "must be a number in decimal notation, got \"" + text + "\"";
      },
      "");
}

/// A file named on the command line: "" is refused, not taken as left out
/// (calibrate -o "" wrote over the calibration beside the scene).
inline CLI::Validator not_empty() {
  return CLI::Validator([](std::string& text) { return text.empty() ? std::string("must not be empty") : std::string(); },
                        "NOT EMPTY");
}

/// Exit statuses shared by every subcommand.
enum Exit : int { ok = 0, runtime_failure = 1, bad_input = 2 };

/// CLI::Range(lo, hi) for a floating-point option, refusing NaN too: every
/// comparison with NaN is false, so the range alone let "nan" through.
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Range(lo, hi) & CLI::Validator(
                                  [](std::string& text) -> std::string {
                                    char* end = nullptr;
                                    const double x = std::strtod(text.c_str(), &end);
                                    return end != text.c_str() && std::isfinite(x) ? "" : "Value is not a finite number";
                                  },
                                  "FINITE");
}

/// A scene file with `--set key.path=value` overrides applied in order, and
/// its mesh; prints "causticd <command>: <file>: <problem>" and returns
/// false on bad input. `flags[i]`, where given and not empty, is the flag
/// the user wrote for assignments[i] ("--width 32" for render.width=32):
/// a warning quotes what was written, not the assignment made of it.
bool load_scene_and_mesh(const char* command, const std::filesystem::path& file,
                         const std::vector<std::string>& assignments, Scene* scene, Mesh* mesh,
                         const std::vector<std::string>& flags = {});

/// Whether `out` (the file of `flag`) can be written: its folder exists, it
/// is no folder, nothing else than a regular file (a device, a pipe), none
/// of the command's `inputs`, and it opens for writing (tried, and left as
/// it was). When not, says so as "causticd <command>: <flag> <out>: ..."
/// before the command renders or writes anything.
bool output_writable(const char* command, const std::filesystem::path& out, const char* flag = "--output",
                     const std::vector<std::filesystem::path>& inputs = {});

/// Writes each of `outputs` through `write(final_name, temporary)` under a
/// temporary name beside it (hidden, keeping the extension the writer picks
/// its format by) and renames them over the final names once every one is
/// complete; when one fails, the temporaries are removed and the error goes
/// on: a full disk or a file size limit leaves no truncated file, nor one
/// file of a set.
void write_complete(const std::vector<std::filesystem::path>& outputs,
                    const std::function<void(const std::filesystem::path&, const std::filesystem::path&)>& write);

/// `text` written to `file`; a write that fails throws, naming the file and
/// the reason (errno's words; the close is checked too).
void write_text(const std::filesystem::path& file, const std::string& text);

/// Each (file, text) written whole through write_complete: a write that
/// fails (a full disk, a file size limit) throws, naming the file, and
/// leaves none of them. For what a command collects as it goes (a bench's
/// rows) and writes at its end.
void write_text_files(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

/// The files a scene was read from: the scene file, its mesh and the
/// receivers' meshes it names.
std::vector<std::filesystem::path> scene_inputs(const std::filesystem::path& file, const Scene& scene);

/// What a runtime failure says: e.what(), and for a failed allocation that
/// memory ran out (its what() is only "std::bad_alloc").
std::string failure_text(const std::exception& e);

/// The bytes this process can still have, the least of what the machine
/// offers (MemAvailable), its cgroup (memory.max, or v1's
/// memory.limit_in_bytes, less what it uses, at each level) and its limits
/// (RLIMIT_DATA, RLIMIT_AS less what it maps), with the bound that sets it;
/// nullopt where none can be read.
struct MemoryRoom {
  std::uint64_t bytes = 0;
  std::string bound;
};
std::optional<MemoryRoom> memory_room();

/// The peak memory of an engine frame of w x h, grey or in colour (a
/// spectral scene or a tinted face), with its read-back and its files; and
/// of the reference tracer's image on `threads` threads (a tinted face's in
/// three channels). Measured, rounded up (scene_args.cpp).
std::uint64_t frame_bytes(int w, int h, bool colour);
std::uint64_t reference_bytes(int w, int h, bool colour, bool tinted, int threads);

/// The threads the reference tracer runs for `asked` (0: all cores).
int reference_threads(int asked);

/// Whether `needed` bytes fit in memory_room(); when not, says so as
/// "causticd <command>: <named>: <what> needs about X GB of memory, ..."
/// (`named`: the flags or keys that set the size), then `advice`, and
/// returns false.
bool memory_suffices(const char* command, const std::string& named, const std::string& what, std::uint64_t needed,
                     const char* advice = "give a smaller size");

/// Runs `body` and turns what it throws into the exit status: a SceneError
/// is bad input (the message names `scene`), anything else a runtime failure.
/// The message goes to stderr as "causticd <command>: ...", after `prefix`
/// (a newline when a progress bar may be on the line). Returns ok otherwise.
int run_reporting(const char* command, const std::filesystem::path& scene, const std::function<void()>& body,
                  const char* prefix = "");

/// What render.fidelity needs beside the scene: the mesh levels (the loaded
/// mesh, the coarser grids and any level the scene names) and the scene
/// file's calibration when one matches it.
struct SceneLevels {
  MeshLevels levels;
  std::optional<Calibration> calibration;
  /// The light grid as the scene (and its --set) wrote it, before auto
  /// chose one: what a calibration must measure up to, whatever the last
  /// calibration let auto choose.
  int written_light_grid = 0;
};

/// load_scene_and_mesh, then the levels, then the calibration beside the
/// scene file; `scene` comes back resolved (fidelity "auto" applied).
/// Prints the problem and returns false on bad input.
bool load_scene_levels(const char* command, const std::filesystem::path& file,
                       const std::vector<std::string>& assignments, Scene* scene, SceneLevels* out,
                       const std::vector<std::string>& flags = {});

/// One line saying what fidelity renders and why.
std::string describe_choice(const Scene& scene, const SceneLevels& levels);

/// `causticd render`: one scene to EXR (HDR) and/or PNG (tone-mapped).
std::function<int()> add_render_command(CLI::App& app);

/// `causticd reference`: the photon tracer.
std::function<int()> add_reference_command(CLI::App& app);

/// `causticd bench`: accuracy against speed.
std::function<int()> add_bench_command(CLI::App& app);

/// `causticd calibrate`: the calibration fidelity "auto" chooses from.
std::function<int()> add_calibrate_command(CLI::App& app);

/// `causticd serve`: the streaming server.
std::function<int()> add_serve_command(CLI::App& app);

/// `causticd design`: target picture -> freeform face, scene and checks.
/// Without CAUSTICD_WITH_DESIGN it only says that design is not built in.
std::function<int()> add_design_command(CLI::App& app);

/// `causticd check-config`: validates a configuration file.
std::function<int()> add_check_config_command(CLI::App& app);

}  // namespace caustic::app
