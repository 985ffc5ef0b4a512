// SPDX-License-Identifier: LGPL-2.1-or-later
// Kind "slow": idle, slow-loris and slow-body connections, while a probe
// measures how fast the server still answers an honest client.
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <map>
#include <thread>

#include "kinds.hpp"

namespace campaign {

namespace {

constexpr int kHeaderTimeout = 5, kBodyTimeout = 5, kIdleTimeout = 5, kGrace = 2;

struct Attacker {
  enum Group { Idle, Loris, SlowBody } group = Idle;
  Conn conn;
  Clock::time_point opened;
  double deadline_ms = 0;  // after `opened`, by which the server must have closed it
  double closed_ms = -1;   // when it did; -1 while open
  size_t sent = 0;         // bytes of `script` already out
  std::string script;
  std::string answer;  // anything the server said before closing
};

const char* group_name(Attacker::Group g) {
  return g == Attacker::Idle ? "idle" : g == Attacker::Loris ? "slow-loris" : "slow-body";
}

}  // namespace

void run_slow(const Options& opt, KindReport& rep) {
  Config config = base_config();
  set_key(config, "header_timeout_s", std::to_string(kHeaderTimeout));
  set_key(config, "body_timeout_s", std::to_string(kBodyTimeout));
  set_key(config, "connection_idle_timeout_s", std::to_string(kIdleTimeout));
  ServerProcess server(opt.binary, opt.folder);
  if (!server.start(config, rep)) return;
  const int port = server.port();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const int fds_before = server.descriptors();
  const auto kinds_before = server.descriptor_kinds();

  const int idle = opt.short_mode ? 200 : 1000, loris = opt.short_mode ? 50 : 200, bodies = 20;
  std::vector<Attacker> attackers;
  attackers.reserve(idle + loris + bodies);
  const std::string loris_script = request_text("GET", "/api/v1/health", "X-Pad: " + std::string(64, 'p') + "\r\n");
  // A length the body never reaches: it comes a byte a second.
  const std::string body_head = request_text("POST", "/api/v1/sessions",
                                             "Content-Type: application/json\r\nConnection: close\r\n"
                                             "Content-Length: 200\r\n");
  int connect_failed = 0;
  for (int i = 0; i < idle + loris + bodies; ++i) {
    // Attackers come from their own addresses: the per-address limit is
    // not what is under test here, the timeouts are.
    const std::string source = "127.0.0." + std::to_string(2 + i % 8);
    Attacker a;
    a.group = i < idle ? Attacker::Idle : i < idle + loris ? Attacker::Loris : Attacker::SlowBody;
    a.conn = connect_loopback(port, source, 2000);
    a.opened = Clock::now();
    if (!a.conn.ok()) {
      ++connect_failed;
      continue;
    }
    if (a.group == Attacker::Idle) a.deadline_ms = 1000.0 * (std::max(kHeaderTimeout, kIdleTimeout) + kGrace);
    if (a.group == Attacker::Loris) {
      a.script = loris_script;
      a.deadline_ms = 1000.0 * (kHeaderTimeout + kGrace);
    }
    if (a.group == Attacker::SlowBody) {
      // Headers at once, then the body a byte a second.
      send_all(a.conn, body_head);
      a.script = "{\"scene\":\"" + std::string(300, 'x');
      a.deadline_ms = 1000.0 * (kBodyTimeout + kGrace);
    }
    attackers.push_back(std::move(a));
  }

  // The honest client: a fresh connection every 200 ms.
  std::vector<double> probe_ms;
  std::atomic<bool> done{false};
  int probe_failures = 0;
  std::thread prober([&] {
    while (!done) {
      const auto t = Clock::now();
      const Response r = exchange(port, make_request("GET", "/api/v1/health"), 5000);
      if (r.kind == Response::Answer && r.status == 200)
        probe_ms.push_back(ms_since(t));
      else
        ++probe_failures;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });

  const double longest = 1000.0 * (std::max({kHeaderTimeout, kBodyTimeout, kIdleTimeout}) + kGrace) + 3000;
  const auto start = Clock::now();
  auto last_tick = start - std::chrono::seconds(1);
  std::vector<pollfd> fds;
  std::vector<size_t> index;
  while (ms_since(start) < longest) {
    fds.clear();
    index.clear();
    for (size_t i = 0; i < attackers.size(); ++i)
      if (attackers[i].closed_ms < 0) {
        fds.push_back({attackers[i].conn.fd, POLLIN, 0});
        index.push_back(i);
      }
    if (fds.empty()) break;
    poll(fds.data(), fds.size(), 50);
    for (size_t k = 0; k < fds.size(); ++k) {
      if (!fds[k].revents) continue;
      Attacker& a = attackers[index[k]];
      char buf[4096];
      const ssize_t n = recv(a.conn.fd, buf, sizeof buf, MSG_DONTWAIT);
      if (n > 0) {
        a.answer.append(buf, static_cast<size_t>(std::min<ssize_t>(n, 4096)));
      } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        a.closed_ms = ms_since(a.opened);
        a.conn.close();
      }
    }
    if (ms_since(last_tick) >= 1000) {
      last_tick = Clock::now();
      for (auto& a : attackers)
        if (a.closed_ms < 0 && a.sent < a.script.size() &&
            send(a.conn.fd, a.script.data() + a.sent, 1, MSG_NOSIGNAL | MSG_DONTWAIT) == 1)
          ++a.sent;
    }
  }
  done = true;
  prober.join();

  std::map<std::string, std::vector<double>> close_times;
  for (auto& a : attackers) {
    const std::string g = group_name(a.group);
    if (a.closed_ms < 0) {
      rep.outcome(g + " left open");
    } else {
      close_times[g].push_back(a.closed_ms);
      rep.outcome(g + (a.answer.empty() ? " closed without answer" : " answered, then closed"));
    }
    rep.check("attack connections are closed within their timeout + 2 s",
              a.closed_ms >= 0 && a.closed_ms <= a.deadline_ms,
              "  " + g + " connection: " +
                  (a.closed_ms < 0 ? "still open after " + std::to_string(static_cast<int>(ms_since(a.opened))) + " ms"
                                   : "closed after " + std::to_string(static_cast<int>(a.closed_ms)) + " ms") +
                  ", deadline " + std::to_string(static_cast<int>(a.deadline_ms)) + " ms");
    if (!a.answer.empty()) {
      // Whatever the server said to an attacker must still be a proper error.
      Response r;
      r.kind = Response::Answer;
      const auto eol = a.answer.find("\r\n");
      r.status = a.answer.size() > 12 ? std::atoi(a.answer.c_str() + 9) : 0;
      const auto ct = a.answer.find("Content-Type: ");
      if (ct != std::string::npos)
        r.headers.emplace_back("Content-Type", a.answer.substr(ct + 14, a.answer.find("\r\n", ct) - ct - 14));
      const auto body = a.answer.find("\r\n\r\n");
      if (body != std::string::npos) r.body = a.answer.substr(body + 4);
      rep.check("answers to slow clients are problem+json errors",
                eol != std::string::npos && r.status >= 400 && problem_defect(r).empty(),
                "  " + g + " got: " + escape(a.answer, 500));
    }
  }
  for (auto& [g, v] : close_times) {
    rep.figure(g + "_closed", static_cast<long>(v.size()));
    rep.figure(g + "_close_after_max_ms", percentile(v, 100));
  }
  rep.figure("attack_connections", static_cast<long>(attackers.size()));
  rep.figure("attack_connect_failed", connect_failed);
  rep.figure("probes", static_cast<long>(probe_ms.size()));
  rep.figure("probe_failures", probe_failures);
  rep.figure("probe_latency_p99_ms", percentile(probe_ms, 99));
  rep.figure("probe_latency_max_ms", percentile(probe_ms, 100));
  std::string why;
  rep.check("server process stays alive", server.alive(&why), "  " + why);
  rep.check("health probes all answered during the attack", probe_failures == 0,
            "  " + std::to_string(probe_failures) + " probes failed");
  rep.goal("health probe p99 latency <= 100 ms during the attack", percentile(probe_ms, 99) <= 100,
            "  p99 " + std::to_string(percentile(probe_ms, 99)) + " ms");
  for (auto& a : attackers) a.conn.close();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const int fds_after = server.descriptors();
  rep.figure("descriptors_before", fds_before);
  rep.figure("descriptors_2s_after", fds_after);
  rep.check("no descriptors left behind after the slow clients", fds_after - fds_before <= 2,
            "  before " + std::to_string(fds_before) + ", after " + std::to_string(fds_after) +
                "; grew: " + descriptor_growth(kinds_before, server.descriptor_kinds()));
}

}  // namespace campaign
