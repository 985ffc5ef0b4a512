// SPDX-License-Identifier: LGPL-2.1-or-later
// Runs the session cycle of `causticd serve` many times against one server
// and watches what the server keeps: create a session, signal and stream
// until the viewer decoded frames, then end it (DELETE on odd cycles; on even
// ones the viewer only drops its WebSocket and the server must reclaim the
// session itself), and wait until /api/v1/health counts no session. Prints
// the server's RSS, descriptors and threads after cycles 1, 10 and every 100.
// Fails when RSS after the last cycle exceeds RSS after cycle 10 by more than
// --rss-slack-mib, when descriptors or threads stay above their cycle-10
// values by more than --slack, when a cycle fails, or when the server does
// not exit 0 on SIGTERM (under AddressSanitizer, leaks found at exit make it
// exit non-zero). Loopback only; every wait is bounded.
//
//   session_cycles --causticd build/bin/causticd --cycles 1000 --report cycles.json
#include "proc_stats.hpp"
#include "webrtc_peer.hpp"

#include <CLI/CLI.hpp>
#include <gio/gio.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

using caustic::testing::WebRtcPeer;
using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Reply {
  guint status = 0;
  std::string body;
  json parsed() const { return json::parse(body, nullptr, false); }
};

// One synchronous request; the session times out after 10 s.
Reply http(SoupSession* session, const std::string& method, const std::string& url, const std::string& body = "",
           const std::string& token = "") {
  Reply r;
  SoupMessage* msg = soup_message_new(method.c_str(), url.c_str());
  if (!msg) return r;
  if (!token.empty())
    soup_message_headers_replace(soup_message_get_request_headers(msg), "Authorization", ("Bearer " + token).c_str());
  if (!body.empty()) {
    GBytes* bytes = g_bytes_new(body.data(), body.size());
    soup_message_set_request_body_from_bytes(msg, "application/json", bytes);
    g_bytes_unref(bytes);
  }
  GError* error = nullptr;
  GBytes* reply = soup_session_send_and_read(session, msg, nullptr, &error);
  if (error) {
    r.body = error->message;
    g_error_free(error);
  } else {
    r.status = soup_message_get_status(msg);
  }
  if (reply) {
    gsize size = 0;
    const auto* data = static_cast<const char*>(g_bytes_get_data(reply, &size));
    r.body.assign(data, size);
    g_bytes_unref(reply);
  }
  g_object_unref(msg);
  return r;
}

struct Sample {
  int cycle = 0;
  double rss_mib = 0;
  int fds = 0;
  int threads = 0;
  double seconds = 0;  // since the first cycle began
};

Sample sample_of(const std::string& pid, int cycle) {
  Sample s;
  s.cycle = cycle;
  std::ifstream status("/proc/" + pid + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) s.rss_mib = std::stod(line.substr(6)) / 1024.0;  // kB
    if (line.rfind("Threads:", 0) == 0) s.threads = std::stoi(line.substr(8));
  }
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/" + pid + "/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++s.fds;
  return s;
}

// health counts a session as gone when it leaves the table; its pipeline
// may still be tearing down (threads joining, sockets closing). Samples are
// taken once two readings 200 ms apart agree, or after `seconds`.
Sample settled_sample(const std::string& pid, int cycle, double seconds) {
  Sample s = sample_of(pid, cycle);
  for (const auto t0 = Clock::now(); since(t0) < seconds;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const Sample next = sample_of(pid, cycle);
    const bool same = next.fds == s.fds && next.threads == s.threads;
    s = next;
    if (same) break;
  }
  return s;
}

// The server under test; SIGTERM (then SIGKILL after `exit_timeout_s`) when done.
class Server {
 public:
  Server(const std::vector<std::string>& args, double start_timeout_s) {
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    GError* error = nullptr;
    // stderr stays the bench's: the server's log and sanitizer reports land there.
    process_ = g_subprocess_newv(argv.data(), G_SUBPROCESS_FLAGS_STDOUT_PIPE, &error);
    if (!process_) {
      std::fprintf(stderr, "cannot start %s: %s\n", args[0].c_str(), error->message);
      g_error_free(error);
      return;
    }
    pid_ = g_subprocess_get_identifier(process_);
    // The first line names the port; a sanitized server can take a while to get there.
    out_ = g_data_input_stream_new(g_subprocess_get_stdout_pipe(process_));
    GCancellable* cancel = g_cancellable_new();
    std::atomic<bool> read{false};
    std::thread watchdog([&] {
      for (const auto t0 = Clock::now(); !read && since(t0) < start_timeout_s;)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      g_cancellable_cancel(cancel);
    });
    gchar* line = g_data_input_stream_read_line(out_, nullptr, cancel, nullptr);
    read = true;
    watchdog.join();
    g_object_unref(cancel);
    const std::string text = line ? line : "";
    g_free(line);
    const std::string prefix = "listening on ";
    if (text.rfind(prefix, 0) != 0) {
      std::fprintf(stderr, "the server did not start: \"%s\"\n", text.c_str());
      return;
    }
    url_ = text.substr(prefix.size());
    if (!url_.empty() && url_.back() == '/') url_.pop_back();
  }

  /// Exit status after SIGTERM; -1 when it had to be killed or died of a signal.
  int stop(double exit_timeout_s) {
    if (!process_) return -1;
    g_subprocess_send_signal(process_, SIGTERM);
    for (const auto t0 = Clock::now(); !exited() && since(t0) < exit_timeout_s;)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const bool clean = exited();
    if (!clean) {
      std::fprintf(stderr, "the server ignored SIGTERM for %.0f s: killed\n", exit_timeout_s);
      g_subprocess_force_exit(process_);
    }
    g_subprocess_wait(process_, nullptr, nullptr);
    int status = -1;
    if (clean && g_subprocess_get_if_exited(process_)) status = g_subprocess_get_exit_status(process_);
    else if (g_subprocess_get_if_signaled(process_))
      std::fprintf(stderr, "the server died of signal %d\n", g_subprocess_get_term_sig(process_));
    g_clear_object(&out_);
    g_clear_object(&process_);
    return status;
  }

  ~Server() { stop(10); }

  const std::string& url() const { return url_; }
  const std::string& pid() const { return pid_; }

 private:
  bool exited() {
    while (g_main_context_iteration(nullptr, FALSE)) {
    }
    return g_subprocess_get_identifier(process_) == nullptr;  // no pid once it was reaped
  }

  GSubprocess* process_ = nullptr;
  GDataInputStream* out_ = nullptr;  // kept open: the server's stdout must not see a closed pipe
  std::string url_, pid_;
};

// Polls the health endpoint until it counts no session; false after `seconds`.
bool wait_idle(SoupSession* http_session, const std::string& url, double seconds, int* sessions) {
  for (const auto t0 = Clock::now();;) {
    const Reply r = http(http_session, "GET", url + "/api/v1/health");
    const json h = r.parsed();
    *sessions = h.is_object() ? h.value("sessions", -1) : -1;
    if (*sessions == 0) return true;
    if (since(t0) > seconds) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Session create/stream/delete cycles against causticd serve: RSS, descriptors, threads"};
  std::string causticd, codec = "vp8", scene = "slab", report;
  int cycles = 1000, size = 256, slack = 4, frames = 3;
  double rss_slack_mib = 20, frame_timeout_s = 30, idle_timeout_s = 30, start_timeout_s = 120, exit_timeout_s = 10;
  double settle_s = 30;
  int sanitizer_status = 0;
  std::vector<std::string> server_args;
  app.add_option("--causticd", causticd, "The causticd binary to run")->required()->check(CLI::ExistingFile);
  app.add_option("--cycles", cycles)->check(CLI::Range(1, 1000000));
  app.add_option("--codec", codec)->check(CLI::IsMember({"vp8", "h264"}));
  app.add_option("--scene", scene);
  app.add_option("--size", size, "Video width and height (a multiple of 8)")->check(CLI::Range(16, 4096));
  app.add_option("--frames", frames, "Frames the viewer must decode in each cycle")->check(CLI::Range(1, 1000));
  app.add_option("--report", report, "Also write the figures to this JSON file");
  app.add_option("--rss-slack-mib", rss_slack_mib, "Allowed RSS growth from cycle 10 to the last");
  app.add_option("--slack", slack, "Allowed descriptors and threads above their cycle-10 values");
  app.add_option("--frame-timeout", frame_timeout_s, "Seconds a cycle may wait for its frames");
  app.add_option("--idle-timeout", idle_timeout_s, "Seconds a cycle may wait for the session to be gone");
  app.add_option("--start-timeout", start_timeout_s, "Seconds the server may take to listen");
  app.add_option("--exit-timeout", exit_timeout_s, "Seconds the server may take to exit after SIGTERM");
  app.add_option("--settle", settle_s, "Seconds idle pool threads get to go after the last cycle");
  app.add_option("--server-arg", server_args, "One more argument for causticd serve (repeatable)");
  app.add_option("--sanitizer-exit-status", sanitizer_status,
                 "Exit status the server's sanitizer gives after a report (its exitcode option): left to the "
                 "caller, who reads the report")
      ->check(CLI::Range(1, 255));
  CLI11_PARSE(app, argc, argv);
  if (size % 8 != 0) {
    std::fprintf(stderr, "--size must be a multiple of 8\n");
    return 2;
  }
  gst_init(nullptr, nullptr);

  // Per-address limits would refuse a thousand sessions from 127.0.0.1 in minutes.
  std::vector<std::string> args = {causticd, "serve", "--port", "0", "--ice-address", "127.0.0.1", "--width",
                                   std::to_string(size), "--height", std::to_string(size), "--codec", codec,
                                   "--max-sessions", "8", "--set", "max_sessions_per_address=1000", "--set",
                                   "rate_limit_per_s=100000", "--set", "rate_limit_burst=100000"};
  args.insert(args.end(), server_args.begin(), server_args.end());
  Server server(args, start_timeout_s);
  if (server.url().empty()) return 1;
  SoupSession* http_session = soup_session_new_with_options("timeout", 10, nullptr);
  const json health = http(http_session, "GET", server.url() + "/api/v1/health").parsed();
  const std::string renderer = health.is_object() ? health.value("renderer", "not reported") : "not reported";
  const Sample baseline = settled_sample(server.pid(), 0, 5);

  std::printf("machine: %u cores (nproc), %s; renderer %s\n", std::thread::hardware_concurrency(),
              caustic::bench::cpu_model().c_str(),
              renderer.c_str());
  std::printf("server: %s, %dx%d %s, scene %s; %d cycles, odd ones DELETE, even ones drop the WebSocket\n",
              causticd.c_str(), size, size, codec.c_str(), scene.c_str(), cycles);
  std::printf("%8s %10s %6s %8s %10s\n", "cycle", "RSS MiB", "fds", "threads", "elapsed s");
  std::printf("%8s %10.1f %6d %8d %10s\n", "start", baseline.rss_mib, baseline.fds, baseline.threads, "-");
  std::fflush(stdout);

  std::vector<Sample> samples;
  std::vector<double> cycle_s;
  int failures = 0;
  const auto start = Clock::now();
  for (int cycle = 1; cycle <= cycles; ++cycle) {
    const auto t0 = Clock::now();
    std::string failure;
    const Reply created = http(http_session, "POST", server.url() + "/api/v1/sessions",
                               json{{"scene", scene}, {"codec", codec}}.dump());
    const json s = created.parsed();
    if (created.status != 201 || !s.is_object() || !s.contains("signal_url")) {
      failure = "POST /api/v1/sessions: " + std::to_string(created.status) + " " + created.body;
    } else {
      std::string ws = server.url() + s["signal_url"].get<std::string>();
      ws.replace(0, 4, "ws");
      {
        WebRtcPeer peer(codec, ws);
        if (!peer.wait_for_frames(frames, frame_timeout_s))
          failure = "no " + std::to_string(frames) + " frames in " + std::to_string(frame_timeout_s) +
                    " s (decoded " + std::to_string(peer.decoded()) + ") " + peer.error();
        if (cycle % 2 == 1) {
          const Reply deleted = http(http_session, "DELETE",
                                     server.url() + "/api/v1/sessions/" + s["id"].get<std::string>(), "",
                                     s["token"].get<std::string>());
          if (deleted.status != 204 && failure.empty())
            failure = "DELETE: " + std::to_string(deleted.status) + " " + deleted.body;
        }
      }  // the peer hangs up and stops its pipeline here
      int sessions = -1;
      if (!wait_idle(http_session, server.url(), idle_timeout_s, &sessions) && failure.empty())
        failure = "still " + std::to_string(sessions) + " sessions " + std::to_string(idle_timeout_s) + " s after the end";
    }
    cycle_s.push_back(since(t0));
    if (!failure.empty()) {
      ++failures;
      std::fprintf(stderr, "cycle %d failed: %s\n", cycle, failure.c_str());
      // Left sessions would count against the next cycles: give the server time to reclaim them.
      int sessions = -1;
      wait_idle(http_session, server.url(), idle_timeout_s, &sessions);
    }
    if (cycle == 1 || cycle == 10 || cycle % 100 == 0 || cycle == cycles) {
      Sample smp = settled_sample(server.pid(), cycle, 5);
      smp.seconds = since(start);
      samples.push_back(smp);
      std::printf("%8d %10.1f %6d %8d %10.1f\n", smp.cycle, smp.rss_mib, smp.fds, smp.threads, smp.seconds);
      std::fflush(stdout);
    }
  }
  const double total_s = since(start);
  // Cycle 10 is the reference: by then the one-time allocations (plugins,
  // the GL context, caches) are made, so growth after it is per session.
  // GLib and GStreamer keep idle pool threads for a while (GLib: 15 s)
  // after the last session: give them time to go before the final reading.
  const Sample ref = *std::find_if(samples.begin(), samples.end(),
                                   [&](const Sample& s) { return s.cycle == std::min(10, cycles); });
  for (const auto t0 = Clock::now();
       (samples.back().threads > ref.threads + slack || samples.back().fds > ref.fds + slack) && since(t0) < settle_s;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    samples.back() = sample_of(server.pid(), cycles);
    samples.back().seconds = since(start);
    if (samples.back().threads <= ref.threads + slack && samples.back().fds <= ref.fds + slack)
      std::printf("%8s %10.1f %6d %8d %10.1f  (idle %.0f s)\n", "idle", samples.back().rss_mib, samples.back().fds,
                  samples.back().threads, samples.back().seconds, since(t0));
  }
  g_object_unref(http_session);
  const int exit_status = server.stop(exit_timeout_s);

  std::vector<double> sorted = cycle_s;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2], worst = sorted.back();
  std::printf("%d cycles in %.0f s: %.2f s per cycle (median %.2f s, worst %.2f s), %d failed\n", cycles, total_s,
              total_s / cycles, median, worst, failures);
  std::printf("server exit status after SIGTERM: %d\n", exit_status);

  const Sample last = samples.back();
  std::vector<std::string> problems;
  if (failures > 0) problems.push_back(std::to_string(failures) + " cycles failed");
  if (last.rss_mib - ref.rss_mib > rss_slack_mib)
    problems.push_back("RSS grew " + std::to_string(last.rss_mib - ref.rss_mib) + " MiB after cycle " +
                       std::to_string(ref.cycle));
  if (last.fds > ref.fds + slack)
    problems.push_back("descriptors " + std::to_string(ref.fds) + " -> " + std::to_string(last.fds));
  if (last.threads > ref.threads + slack)
    problems.push_back("threads " + std::to_string(ref.threads) + " -> " + std::to_string(last.threads));
  if (exit_status != 0 && exit_status != sanitizer_status)
    problems.push_back("server exit status " + std::to_string(exit_status));
  if (exit_status != 0 && exit_status == sanitizer_status)
    std::printf("the server's sanitizer reported at exit (status %d): judge its report\n", exit_status);
  for (const auto& p : problems) std::printf("FAIL: %s\n", p.c_str());
  if (problems.empty())
    std::printf("ok: RSS %+.1f MiB from cycle %d to %d, descriptors %+d, threads %+d\n", last.rss_mib - ref.rss_mib,
                ref.cycle, last.cycle, last.fds - ref.fds, last.threads - ref.threads);

  if (!report.empty()) {
    json j = {{"machine",
               {{"nproc", std::thread::hardware_concurrency()}, {"cpu", caustic::bench::cpu_model()}, {"renderer", renderer}}},
              {"causticd", causticd},
              {"codec", codec},
              {"size", size},
              {"cycles", cycles},
              {"failed", failures},
              {"seconds", total_s},
              {"seconds_per_cycle", {{"mean", total_s / cycles}, {"median", median}, {"worst", worst}}},
              {"exit_status", exit_status},
              {"baseline", {{"rss_mib", baseline.rss_mib}, {"fds", baseline.fds}, {"threads", baseline.threads}}},
              {"samples", json::array()},
              {"problems", problems}};
    for (const auto& s : samples)
      j["samples"].push_back(
          {{"cycle", s.cycle}, {"rss_mib", s.rss_mib}, {"fds", s.fds}, {"threads", s.threads}, {"seconds", s.seconds}});
    std::ofstream(report) << j.dump(2) << "\n";
  }
  return problems.empty() ? 0 : 1;
}
