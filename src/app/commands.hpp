// Subcommands of the causticd executable. Each registers itself on the CLI
// and returns the exit status when it runs.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace caustic::app {

/// Exit statuses shared by every subcommand.
enum Exit : int { ok = 0, runtime_failure = 1, bad_input = 2 };

/// `causticd render`: one scene to EXR (HDR) and/or PNG (tone-mapped).
std::function<int()> add_render_command(CLI::App& app);

/// `causticd reference`: the photon tracer.
std::function<int()> add_reference_command(CLI::App& app);

/// `causticd bench`: accuracy against speed.
std::function<int()> add_bench_command(CLI::App& app);

/// `causticd serve`: the streaming server.
std::function<int()> add_serve_command(CLI::App& app);

}  // namespace caustic::app
