// SPDX-License-Identifier: LGPL-2.1-or-later
// Measures one streaming session end to end on this machine: sustained
// decoded frame rate and the server's CPU use, then the time from a PATCH to
// the first frame that carries the new version (as the viewer learns it on
// the "frames" data channel). Of a scene with water, also the renders that
// overran their frame interval in the steady state and the frames from a
// drop's acceptance to the first frame that shows it. Prints a table;
// asserts nothing.
//
//   caustic-stream-bench --codec vp8 --width 1024 --height 1024 --seconds 20 --patches 100
//   caustic-stream-bench --scene pool --seconds 60 --drops 20 --patches 1 [--peer-nice 19]
//   caustic-stream-bench --scenes-dir DIR --scene pool-256 --seconds 60 --patches 1
#include "proc_stats.hpp"
#include "server_process.hpp"
#include "webrtc_peer.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include <sys/resource.h>

using caustic::testing::http;
using caustic::testing::ServerProcess;
using caustic::testing::WebRtcPeer;
using nlohmann::json;

using caustic::bench::cpu_seconds;
using caustic::bench::percentile;

int main(int argc, char** argv) {
  CLI::App app{"Streaming benchmark of causticd serve (loopback only)"};
  std::string codec = "vp8", scene = "wavy";
  int width = 1024, height = 1024, framerate = 30, patches = 100;
  double seconds = 20, spacing_ms = 200;
  app.add_option("--codec", codec)->check(CLI::IsMember({"vp8", "h264"}));
  app.add_option("--scene", scene);
  app.add_option("--width", width)->check(CLI::Range(16, 4096));
  app.add_option("--height", height)->check(CLI::Range(16, 4096));
  app.add_option("--framerate", framerate)->check(CLI::Range(1, 120));
  app.add_option("--seconds", seconds, "Length of the steady-state measurement")->check(CLI::Range(1.0, 600.0));
  app.add_option("--patches", patches, "PATCHes for the latency measurement")->check(CLI::Range(1, 10000));
  app.add_option("--spacing-ms", spacing_ms, "Pause between PATCHes")->check(CLI::Range(0.0, 10000.0));
  double drag_seconds = 0;
  int settles = 10;
  app.add_option("--settles", settles, "After the drag: 1 s drags followed by stillness, for the settle time")
      ->check(CLI::Range(1, 1000));
  app.add_option("--drag-seconds", drag_seconds, "Then patch the light at 30 Hz without waiting, this long")
      ->check(CLI::Range(0.0, 600.0));
  int drops = 0;
  app.add_option("--drops", drops, "After the steady state: drops posted 0.5 s apart (a scene with water)")
      ->check(CLI::Range(0, 1000));
  std::string scenes_dir;
  app.add_option("--scenes-dir", scenes_dir, "The server's scenes folder (default: the built-in scenes)")
      ->check(CLI::ExistingDirectory);
  int peer_nice = 0;
  app.add_option("--peer-nice", peer_nice,
                 "Niceness of the receiving peer (19: a visitor's browser elsewhere, using only idle time)")
      ->check(CLI::Range(0, 19));
  CLI11_PARSE(app, argc, argv);
  gst_init(nullptr, nullptr);

  std::vector<std::string> args{"--width", std::to_string(width), "--height", std::to_string(height),
                                "--framerate", std::to_string(framerate), "--codec", codec};
  if (!scenes_dir.empty()) args.insert(args.end(), {"--scenes-dir", scenes_dir});
  ServerProcess server(args);
  if (server.url().empty()) return 1;
  const std::string pid = g_subprocess_get_identifier(server.process());
  const json s = http("POST", server.url() + "/api/v1/sessions", json{{"scene", scene}, {"codec", codec}}.dump()).json();
  if (!s.contains("signal_url")) {
    std::fprintf(stderr, "cannot create a session: %s\n", s.dump().c_str());
    return 1;
  }
  std::string ws = server.url() + s["signal_url"].get<std::string>();
  ws.replace(0, 4, "ws");
  // Set on this thread before the peer's threads exist, which inherit it;
  // the server, already started, keeps its own.
  if (peer_nice > 0 && setpriority(PRIO_PROCESS, 0, peer_nice) != 0) std::perror("setpriority");
  WebRtcPeer peer(codec, ws);
  if (!peer.wait_for_frames(5, 60)) {
    std::fprintf(stderr, "no video: %s\n", peer.error().c_str());
    return 1;
  }
  std::printf("machine: %s\n", caustic::bench::machine().c_str());
  std::printf("session: %s, %dx%d at %d fps, scene %s, the peer at nice %d\n", codec.c_str(), width, height,
              framerate, scene.c_str(), peer_nice);

  // Steady state: parameters unchanged, frames re-sent and encoded.
  auto measure = [&](double secs, const std::function<void()>& during) {
    const int frames0 = peer.decoded();
    const double cpu0 = cpu_seconds(pid);
    const auto t0 = std::chrono::steady_clock::now();
    during();
    const int target = static_cast<int>(secs * 1000);
    while (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(target)) peer.wait_for_frames(1, 0.05);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return std::pair{(peer.decoded() - frames0) / wall, 100.0 * (cpu_seconds(pid) - cpu0) / wall};
  };
  auto counter = [&](const std::string& name) {
    const std::string text = http("GET", server.url() + "/metrics").body;
    const auto at = text.find("\n" + name + " ");
    return at == std::string::npos ? 0.0 : std::stod(text.substr(at + name.size() + 2));
  };
  std::printf("steady state: measuring %.0f s ...\n", seconds);
  const double overruns0 = counter("causticd_render_overruns_total"), sent0 = counter("causticd_frames_sent_total");
  const double rendered0 = counter("causticd_frames_rendered_total");
  const double dropped0 = counter("causticd_frames_dropped_total");
  // Mean seconds of a histogram since the marks taken here.
  const auto mean_ms = [&](const std::string& name, double sum0, double count0) {
    const double n = counter(name + "_count") - count0;
    return n > 0 ? 1000.0 * (counter(name + "_sum") - sum0) / n : 0.0;
  };
  const double render_sum0 = counter("causticd_render_seconds_sum"), render_n0 = counter("causticd_render_seconds_count");
  const double encode_sum0 = counter("causticd_encode_seconds_sum"), encode_n0 = counter("causticd_encode_seconds_count");
  const int messages0 = peer.frame_messages(), steady_previews0 = peer.previews();
  const auto [steady_fps, steady_cpu] = measure(seconds, [] {});
  std::printf("steady state: %.1f fps decoded, server CPU %.0f%% of one core\n", steady_fps, steady_cpu);
  std::printf("steady state: %.0f frames sent, %.0f caustics rendered, %.0f frames sent while a render overran\n",
              counter("causticd_frames_sent_total") - sent0, counter("causticd_frames_rendered_total") - rendered0,
              counter("causticd_render_overruns_total") - overruns0);
  std::printf("steady state: %.0f frames dropped before the encoder (still busy)\n",
              counter("causticd_frames_dropped_total") - dropped0);
  std::printf("steady state: %d of %d frame messages were previews\n", peer.previews() - steady_previews0,
              peer.frame_messages() - messages0);
  std::printf("steady state: a render %.1f ms, an encode %.1f ms (means, wall clock)\n",
              mean_ms("causticd_render_seconds", render_sum0, render_n0),
              mean_ms("causticd_encode_seconds", encode_sum0, encode_n0));
  if (drops > 0) {
    // A visitor's click: from the 202 to the first frame message whose surface holds the drop.
    const std::string url = server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/drops";
    const auto auth = std::vector<std::pair<std::string, std::string>>{{"Authorization", "Bearer " + s["token"].get<std::string>()}};
    std::vector<double> frames, ms;
    for (int i = 0; i < drops; ++i) {
      const auto r = http("POST", url, json{{"x", 0.8 * std::sin(i)}, {"y", 0.8 * std::cos(3 * i)}}.dump(), "application/json", auth);
      const auto t0 = std::chrono::steady_clock::now();
      const int before = peer.frame_messages();
      if (r.status != 202) {
        std::fprintf(stderr, "drop refused: %u %s\n", r.status, r.body.c_str());
        return 1;
      }
      if (peer.wait_for_drops(r.json()["drop"], 10.0)) {
        frames.push_back(peer.frame_messages() - before);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      peer.wait_for_frames(1000000, 0.5);
    }
    std::printf("drop accepted -> first frame showing it: median %.0f frames (%.0f ms), p95 %.0f frames (%.0f ms), "
                "%zu of %d seen\n",
                percentile(frames, 0.5), percentile(ms, 0.5), percentile(frames, 0.95), percentile(ms, 0.95),
                frames.size(), drops);
  }

  // Latency: PATCH -> first frame message with the new version.
  const auto auth =
      std::vector<std::pair<std::string, std::string>>{{"Authorization", "Bearer " + s["token"].get<std::string>()}};
  const std::string params = server.url() + "/api/v1/sessions/" + s["id"].get<std::string>() + "/params";
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<double> latency_ms;
  const int frames0 = peer.decoded();
  const double cpu0 = cpu_seconds(pid);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < patches; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = http("PATCH", params, json{{"light", {{"direction", {u(rng), u(rng), -1.0}}}}}.dump(),
                        "application/merge-patch+json", auth);
    if (r.status != 200) {
      std::fprintf(stderr, "PATCH failed: %u %s\n", r.status, r.body.c_str());
      return 1;
    }
    const std::uint64_t version = r.json()["version"];
    if (peer.wait_for_version(version, 10.0))
      latency_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if ((i + 1) % 10 == 0) std::printf("  %d/%d patches\n", i + 1, patches);
    peer.wait_for_frames(1000000, spacing_ms / 1000.0);  // keep the main loop turning
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("while patching: %.1f fps decoded, server CPU %.0f%% of one core\n", (peer.decoded() - frames0) / wall,
              100.0 * (cpu_seconds(pid) - cpu0) / wall);
  std::printf("PATCH -> first frame with the new version: median %.0f ms, p95 %.0f ms (%zu of %d seen)\n",
              percentile(latency_ms, 0.5), percentile(latency_ms, 0.95), latency_ms.size(), patches);
  if (drag_seconds <= 0) return 0;

  // A light drag: a PATCH every 33 ms whatever the frames do, then stillness.
  std::printf("drag: patching the light at 30 Hz for %.0f s ...\n", drag_seconds);
  const int drag_frames0 = peer.decoded(), previews0 = peer.previews();
  const double drag_cpu0 = cpu_seconds(pid);
  const auto drag_start = std::chrono::steady_clock::now();
  std::uint64_t last = 0;
  for (int i = 0; std::chrono::steady_clock::now() - drag_start < std::chrono::duration<double>(drag_seconds); ++i) {
    const auto due = drag_start + std::chrono::microseconds(33333LL * i);
    while (std::chrono::steady_clock::now() < due) peer.wait_for_frames(1000000, 0.002);
    const double a = 0.3 * std::sin(i * 0.05), b = 0.3 * std::cos(i * 0.031);
    const auto r = http("PATCH", params, json{{"light", {{"direction", {a, b, -1.0}}}}}.dump(),
                        "application/merge-patch+json", auth);
    if (r.status == 200) last = r.json()["version"];
    if (i % 300 == 299) std::printf("  %.0f s\n", (i + 1) / 30.0);
  }
  const auto stopped = std::chrono::steady_clock::now();
  const double drag_wall = std::chrono::duration<double>(stopped - drag_start).count();
  const bool full = peer.wait_for_version(last, 10.0, true);
  const double settle_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - stopped).count();
  std::printf("while dragging: %.1f fps decoded, server CPU %.0f%% of one core, %d of the frames previews\n",
              (peer.decoded() - drag_frames0) / drag_wall, 100.0 * (cpu_seconds(pid) - drag_cpu0) / drag_wall,
              peer.previews() - previews0);
  std::printf("last PATCH -> full-quality frame of it on the peer: %s%.0f ms\n", full ? "" : "not seen after ",
              settle_ms);

  // Settle time, repeatedly: a 1 s drag at 30 Hz, then the wait for the full frame.
  std::vector<double> settle;
  for (int k = 0; k < settles; ++k) {
    std::uint64_t v = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 30; ++i) {
      while (std::chrono::steady_clock::now() < t0 + std::chrono::microseconds(33333LL * i))
        peer.wait_for_frames(1000000, 0.002);
      const auto r = http("PATCH", params,
                          json{{"light", {{"direction", {0.2 * std::sin(k + i * 0.05), 0.1, -1.0}}}}}.dump(),
                          "application/merge-patch+json", auth);
      if (r.status == 200) v = r.json()["version"];
    }
    const auto still = std::chrono::steady_clock::now();
    if (peer.wait_for_version(v, 10.0, true))
      settle.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - still).count());
    peer.wait_for_frames(1000000, 0.5);
  }
  std::printf("last PATCH -> its full-quality frame on the peer, %d drags: median %.0f ms, p95 %.0f ms, worst %.0f ms\n",
              settles, percentile(settle, 0.5), percentile(settle, 0.95), percentile(settle, 1.0));
  return 0;
}
