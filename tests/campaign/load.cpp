// SPDX-License-Identifier: LGPL-2.1-or-later
// Kinds "keepalive" (descriptors a server keeps for clients that asked for
// keep-alive and left) and "flood" (many concurrent clients).
#include <atomic>
#include <mutex>
#include <thread>

#include "kinds.hpp"

namespace campaign {

namespace {

// Samples the server's descriptors while workers run; stops the workers
// early if the server dies.
struct Watch {
  int max_descriptors = 0;
  bool died = false;
  std::string why;
  void run(ServerProcess& server, std::atomic<bool>& done, std::atomic<bool>& stop) {
    while (!done) {
      max_descriptors = std::max(max_descriptors, server.descriptors());
      if (!server.alive(&why)) {
        died = true;
        stop = true;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
};

bool health_answers(int port) {
  const Response r = exchange(port, make_request("GET", "/api/v1/health"), 5000);
  return r.kind == Response::Answer && r.status == 200;
}

}  // namespace

void run_keepalive(const Options& opt, KindReport& rep) {
  ServerProcess server(opt.binary, opt.folder);
  if (!server.start(base_config(), rep)) return;
  const int port = server.port();
  health_answers(port);  // warm: lazily made state is not a leak
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const int before = server.descriptors();
  const auto kinds_before = server.descriptor_kinds();
  const int total = opt.short_mode ? 2000 : 100000;
  const double budget_ms = opt.short_mode ? 40000 : 360000;
  const std::vector<std::string> targets = {"/api/v1/health", "/api/v1/scenes", "/",           "/metrics",
                                            "/index.html",    "/nope.html",     "/api/v1/nope"};
  std::atomic<int> next{0};
  std::atomic<bool> done{false}, stop{false};
  std::atomic<long> not_closed{0};
  std::mutex latency_mutex;
  std::vector<double> latencies;
  std::vector<std::thread> workers;
  const auto start = Clock::now();
  for (int t = 0; t < 4; ++t)
    workers.emplace_back([&, t] {
      for (int i; (i = next++) < total && !stop && ms_since(start) < budget_ms;) {
        // What browsers and curl send: keep-alive, then they go away.
        const std::string req = make_request("GET", targets[static_cast<size_t>(i + t) % targets.size()],
                                             {{"Connection", "keep-alive"},
                                              {"Keep-Alive", "timeout=60"},
                                              {"User-Agent", "campaign"},
                                              {"Accept", "*/*"}});
        Conn c;
        const Response r = exchange(port, req, 5000, false, false, "", &c);
        judge_common(rep, nullptr, req, r, false);
        if (r.kind == Response::Answer) {
          std::lock_guard lock(latency_mutex);
          latencies.push_back(r.ms);
        }
        // Sampled: does the server close on its own after the answer?
        if (i % 500 == 0 && r.kind == Response::Answer && !wait_closed(c, 300)) ++not_closed;
      }
    });
  Watch watch;
  std::thread watcher([&] { watch.run(server, done, stop); });
  for (auto& w : workers) w.join();
  done = true;
  watcher.join();
  const double seconds = ms_since(start) / 1000;
  rep.check("server process stays alive", !watch.died, "  " + watch.why + "\n  log: " + escape(server.log_tail(600)));
  if (watch.died) return;
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const int after = server.descriptors();
  const int sent = std::min(next.load(), total);
  rep.figure("requests", sent);
  rep.figure("requests_per_s", static_cast<long>(sent / std::max(seconds, 0.001)));
  rep.figure("descriptors_before", before);
  rep.figure("descriptors_max_during", watch.max_descriptors);
  rep.figure("descriptors_2s_after", after);
  rep.figure("descriptors_left_behind", after - before);
  rep.figure("sampled_answers_not_followed_by_close", not_closed.load());
  rep.figure("latency_p50_ms", percentile(latencies, 50));
  rep.figure("latency_p90_ms", percentile(latencies, 90));
  rep.figure("latency_p99_ms", percentile(latencies, 99));
  // A couple may be transient (a timer's socket pair, a log rotation).
  rep.check("no descriptors left behind 2 s after keep-alive clients left", after - before <= 2,
            "  before " + std::to_string(before) + ", 2 s after " + std::to_string(after) + " (max during " +
                std::to_string(watch.max_descriptors) + "); grew: " +
                descriptor_growth(kinds_before, server.descriptor_kinds()));
  rep.check("the planned number of requests fit in the time budget", sent == total,
            "  sent " + std::to_string(sent) + " of " + std::to_string(total));
  rep.check("the server still answers afterwards", health_answers(port));
}

void run_flood(const Options& opt, KindReport& rep) {
  // Four client addresses of 64 clients each. One address already holds
  // its max_connections_per_address in idle connections: its clients must
  // be shed, at once, while the other three are served.
  constexpr int kPerAddress = 16;
  Config config = base_config();
  set_key(config, "max_connections_per_address", std::to_string(kPerAddress));
  set_key(config, "header_timeout_s", "60");
  set_key(config, "connection_idle_timeout_s", "60");
  ServerProcess server(opt.binary, opt.folder);
  if (!server.start(config, rep)) return;
  const int port = server.port();
  std::vector<Conn> holders;
  for (int i = 0; i < kPerAddress; ++i) holders.push_back(connect_loopback(port, "127.0.0.20"));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double run_ms = opt.short_mode ? 3000 : 10000;
  std::mutex mutex;
  std::vector<double> ok_ms, refused_ms;
  std::atomic<long> other_5xx{0}, connect_failed{0}, requests{0};
  std::atomic<bool> done{false}, stop{false};
  std::vector<std::thread> clients;
  const auto start = Clock::now();
  const std::string req = make_request("GET", "/api/v1/scenes");
  for (int t = 0; t < 256; ++t)
    clients.emplace_back([&, t] {
      const std::string source = "127.0.0." + std::to_string(20 + t % 4);
      std::vector<double> ok, refused;
      while (!stop && ms_since(start) < run_ms) {
        const Response r = exchange(port, req, 5000, false, false, source);
        ++requests;
        judge_common(rep, nullptr, req, r, false, false, true);
        if (r.kind == Response::Answer && r.status == 200)
          ok.push_back(r.ms);
        else if ((r.kind == Response::Answer && (r.status == 429 || r.status == 503)) || r.kind == Response::Closed)
          refused.push_back(r.ms);
        else if (r.kind == Response::Answer && r.status >= 500)
          ++other_5xx;
        else if (r.kind == Response::ConnectFailed)
          ++connect_failed;
      }
      std::lock_guard lock(mutex);
      ok_ms.insert(ok_ms.end(), ok.begin(), ok.end());
      refused_ms.insert(refused_ms.end(), refused.begin(), refused.end());
    });
  Watch watch;
  std::thread watcher([&] { watch.run(server, done, stop); });
  for (auto& c : clients) c.join();
  done = true;
  watcher.join();
  const double seconds = ms_since(start) / 1000;
  rep.check("server process stays alive", !watch.died, "  " + watch.why + "\n  log: " + escape(server.log_tail(600)));
  rep.figure("clients", 256);
  rep.figure("requests", requests.load());
  rep.figure("requests_per_s", static_cast<long>(requests / std::max(seconds, 0.001)));
  rep.figure("ok_200", static_cast<long>(ok_ms.size()));
  rep.figure("ok_latency_p50_ms", percentile(ok_ms, 50));
  rep.figure("ok_latency_p99_ms", percentile(ok_ms, 99));
  rep.figure("refused_429_503_or_closed", static_cast<long>(refused_ms.size()));
  rep.figure("refused_latency_p99_ms", percentile(refused_ms, 99));
  rep.figure("other_5xx", other_5xx.load());
  rep.figure("descriptors_max_during", watch.max_descriptors);
  rep.check("no 5xx other than 503 under flood", other_5xx == 0);
  rep.goal("refusals come at once (p99 <= 100 ms)", percentile(refused_ms, 99) <= 100,
            "  p99 " + std::to_string(percentile(refused_ms, 99)) + " ms over " + std::to_string(refused_ms.size()));
  rep.check("some requests are served under flood", !ok_ms.empty());
  rep.check("clients of an address at its connection limit are shed", !refused_ms.empty(),
            "  " + std::to_string(kPerAddress) + " idle connections held from 127.0.0.20, yet no 429/503/close");
  holders.clear();
  if (watch.died) return;
  rep.check("the server still answers afterwards", health_answers(port));
}

}  // namespace campaign
