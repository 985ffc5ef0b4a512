// SPDX-License-Identifier: LGPL-2.1-or-later
// causticd: renders caustics of refractive and reflective objects.
#include "commands.hpp"

#include "caustic/gl_context.hpp"

#include <csignal>
#include <iostream>

int main(int argc, char** argv) {
  // A file size limit (RLIMIT_FSIZE) reached makes the write fail (EFBIG),
  // said as such, rather than end the process with a truncated file.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"causticd: server-side caustic renderer"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("causticd ") + CAUSTICD_VERSION);
  const std::function<int()> commands[] = {caustic::app::add_render_command(app),
                                           caustic::app::add_reference_command(app),
                                           caustic::app::add_bench_command(app),
                                           caustic::app::add_calibrate_command(app),
                                           caustic::app::add_serve_command(app),
                                           caustic::app::add_design_command(app),
                                           caustic::app::add_check_config_command(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : caustic::app::bad_input;
  }
  // The environment is input too: a GL platform no one offers is said at
  // once, before a command starts and fails on each context it makes.
  try {
    (void)caustic::egl_platform_from_environment();
  } catch (const std::exception& e) {
    std::cerr << "causticd: " << e.what() << "\n";
    return caustic::app::bad_input;
  }
  // What a command does not turn into its status itself (memory, threads
  // or a library's device refused while the scene's levels are built) is a
  // runtime failure said in a line, not an abort with a core dump.
  try {
    for (const auto& command : commands)
      if (const int status = command(); status >= 0) return status;
  } catch (const std::exception& e) {
    const auto chosen = app.get_subcommands();
    std::cerr << "causticd" << (chosen.empty() ? "" : " " + chosen.front()->get_name()) << ": "
              << caustic::app::failure_text(e) << "\n";
    return caustic::app::runtime_failure;
  }
  return caustic::app::bad_input;
}
