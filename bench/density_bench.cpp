// SPDX-License-Identifier: LGPL-2.1-or-later
// Sessions per host: for each count N, a fresh causticd holds N one-viewer
// sessions (each viewer a WebRTC peer in this process, decoding). It
// measures the server's CPU and memory while every scene is still; the
// time from a PATCH of a still session to the first frame of it on its
// viewer (one probe every --probe-ms, round robin); then, while
// `--dragging` of them are patched at 30 Hz, the dragging viewers' decoded
// frame rate and the probes' latency on the others. A
// count "holds" when every dragging viewer decodes at least 29 fps and the
// probes' p95 stays within --latency-ms. Prints a table; asserts nothing.
// The viewers' decoding shares this machine's cores with the server, as a
// second host's would not: the figures are a lower bound.
//
//   caustic-density-bench --counts 1,2,4,8,12,16 --seconds 10 --dragging 1
#include "proc_stats.hpp"
#include "server_process.hpp"
#include "webrtc_peer.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

using caustic::bench::cpu_seconds;
using caustic::bench::percentile;
using caustic::bench::rss_mib;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using caustic::testing::WebRtcPeer;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

struct Viewer {
  std::string params_url;
  std::vector<std::pair<std::string, std::string>> auth;
  std::unique_ptr<WebRtcPeer> peer;
};

struct Phase {
  double cpu_percent = 0, min_fps = 0, p50_ms = 0, p95_ms = 0;
  int probes = 0, seen = 0;
};

std::uint64_t patch(const Viewer& v, double a, double b) {
  const auto r = http("PATCH", v.params_url, json{{"light", {{"direction", {a, b, -1.0}}}}}.dump(),
                      "application/merge-patch+json", v.auth);
  return r.status == 200 ? r.json().value("version", std::uint64_t{0}) : 0;
}

// `seconds` of the last `dragging` viewers patched at 30 Hz, with a latency
// probe on one of the others every `probe_ms` (0: none).
Phase run_phase(std::vector<Viewer>& viewers, int dragging, double seconds, double probe_ms, const std::string& pid) {
  Phase out;
  std::vector<int> decoded0;
  for (auto& v : viewers) decoded0.push_back(v.peer->decoded());
  const double cpu0 = cpu_seconds(pid);
  const auto start = Clock::now();
  struct Probe {
    std::size_t viewer;
    std::uint64_t version;
    Clock::time_point sent;
  };
  std::vector<Probe> open;
  std::vector<double> latency;
  int tick = 0, probe_tick = 0;
  const std::size_t still = viewers.size() - static_cast<std::size_t>(dragging);
  while (Clock::now() - start < std::chrono::duration<double>(seconds)) {
    const auto now = Clock::now();
    if (now >= start + std::chrono::microseconds(33333LL * tick)) {
      for (int d = 0; d < dragging; ++d)
        patch(viewers[still + d], 0.3 * std::sin(tick * 0.05 + d), 0.3 * std::cos(tick * 0.031));
      ++tick;
    }
    if (still > 0 && probe_ms > 0 && now >= start + std::chrono::duration<double, std::milli>(probe_ms * probe_tick)) {
      const std::size_t i = probe_tick % still;
      const std::uint64_t version = patch(viewers[i], 0.1 * std::sin(probe_tick), 0.1 * std::cos(probe_tick));
      if (version) open.push_back({i, version, Clock::now()});
      ++out.probes;
      ++probe_tick;
    }
    viewers.front().peer->wait_for_frames(1000000, 0.002);  // turns the shared main loop
    for (auto it = open.begin(); it != open.end();) {
      if (viewers[it->viewer].peer->version() >= it->version) {
        latency.push_back(std::chrono::duration<double, std::milli>(Clock::now() - it->sent).count());
        it = open.erase(it);
      } else {
        ++it;
      }
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  out.cpu_percent = 100.0 * (cpu_seconds(pid) - cpu0) / wall;
  out.min_fps = 1e9;
  for (int d = 0; d < dragging; ++d) {
    const std::size_t i = still + d;
    out.min_fps = std::min(out.min_fps, (viewers[i].peer->decoded() - decoded0[i]) / wall);
  }
  if (dragging == 0) out.min_fps = 0;
  out.seen = static_cast<int>(latency.size());
  out.p50_ms = percentile(latency, 0.5);
  out.p95_ms = percentile(latency, 0.95);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Sessions per host of causticd serve (loopback only)"};
  std::string codec = "vp8", scene = "wavy";
  std::vector<int> counts{1, 2, 4, 8, 12, 16};
  int size = 1024, dragging = 1;
  double seconds = 10, latency_ms = 150, probe_ms = 1000;
  app.add_option("--codec", codec)->check(CLI::IsMember({"vp8", "h264"}));
  app.add_option("--scene", scene);
  app.add_option("--size", size, "Width and height of each stream")->check(CLI::Range(64, 4096));
  app.add_option("--counts", counts, "Session counts to try")->delimiter(',')->check(CLI::Range(1, 200));
  app.add_option("--seconds", seconds, "Length of each phase")->check(CLI::Range(2.0, 600.0));
  app.add_option("--dragging", dragging, "Sessions patched at 30 Hz in the second phase")->check(CLI::Range(0, 200));
  app.add_option("--probe-ms", probe_ms, "Pause between latency probes")->check(CLI::Range(50.0, 10000.0));
  app.add_option("--latency-ms", latency_ms, "p95 PATCH-to-frame bound for 'holds'")->check(CLI::Range(1.0, 10000.0));
  CLI11_PARSE(app, argc, argv);
  gst_init(nullptr, nullptr);

  std::printf("machine: %s\n", caustic::bench::machine().c_str());
  std::printf("%dx%d %s at 30 fps, scene %s; phases of %.0f s; a count holds when dragging viewers decode >= 29 fps "
              "and the p95 PATCH-to-frame of still sessions is <= %.0f ms\n",
              size, size, codec.c_str(), scene.c_str(), seconds, latency_ms);
  std::printf("%4s | %9s %8s %8s %11s | %9s %8s %11s %5s\n", "N", "still CPU", "RSS MiB", "MiB/sess",
              "p50/p95 ms", "drag CPU", "drag fps", "p50/p95 ms", "holds");
  double idle_rss = 0;
  for (const int n : counts) {
    const std::string cap = std::to_string(n);
    ServerProcess server({"--width", std::to_string(size), "--height", std::to_string(size), "--framerate", "30",
                          "--codec", codec, "--max-sessions", cap, "--set", "max_sessions_per_address=" + cap});
    if (server.url().empty()) return 1;
    const std::string pid = g_subprocess_get_identifier(server.process());
    if (idle_rss == 0) idle_rss = rss_mib(pid);
    std::vector<Viewer> viewers;
    for (int i = 0; i < n; ++i) {
      const json s = http("POST", server.url() + "/api/v1/sessions", json{{"scene", scene}, {"codec", codec}}.dump()).json();
      if (!s.contains("signal_url")) {
        std::fprintf(stderr, "session %d of %d refused: %s\n", i + 1, n, s.dump().c_str());
        return 1;
      }
      std::string ws = server.url() + s["signal_url"].get<std::string>();
      ws.replace(0, 4, "ws");
      viewers.push_back({server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/params",
                         {{"Authorization", "Bearer " + s["token"].get<std::string>()}},
                         std::make_unique<WebRtcPeer>(codec, ws)});
    }
    for (auto& v : viewers)
      if (!v.peer->wait_for_frames(1, 120)) {
        std::fprintf(stderr, "N=%d: a viewer got no video: %s\n", n, v.peer->error().c_str());
        return 1;
      }
    viewers.front().peer->wait_for_frames(1000000, 2.0);  // past start-up
    const Phase idle = run_phase(viewers, 0, seconds, 0, pid);
    const double rss = rss_mib(pid);
    const Phase still = run_phase(viewers, 0, seconds, probe_ms, pid);
    const int drag = std::min(dragging, n);
    const Phase moving = run_phase(viewers, drag, seconds, probe_ms, pid);
    const bool holds = (drag == 0 || moving.min_fps >= 29) && still.p95_ms <= latency_ms &&
                       (drag == n || moving.p95_ms <= latency_ms) && still.seen >= still.probes - 1;
    std::printf("%4d | %8.1f%% %8.0f %8.1f %5.0f/%5.0f | %8.1f%% %8.1f %5.0f/%5.0f %5s\n", n, idle.cpu_percent, rss,
                (rss - idle_rss) / n, still.p50_ms, still.p95_ms, moving.cpu_percent, drag ? moving.min_fps : 0.0,
                moving.p50_ms, moving.p95_ms, holds ? "yes" : "no");
    std::fflush(stdout);
  }
  std::printf("(CPU: %% of one core, server process only; RSS after the still phase; MiB/sess beyond an idle server)\n");
  return 0;
}
