// SPDX-License-Identifier: LGPL-2.1-or-later
// Fault campaign against a running causticd: attacks it over loopback as an
// outsider would and fails on any crash, 5xx (other than 503 load shedding),
// error that is not problem+json, state change by a refused request, or
// resource (connection, descriptor, session) the server does not reclaim.
//
//   campaign --causticd BIN [--short] [--seed N] [--only KIND] [--report FILE.json]
//
// Kinds: malformed, keepalive, slow, flood, sessions. Each starts its own
// server with a generated config and stops it afterwards.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "kinds.hpp"

namespace {

void usage() {
  std::cerr << "usage: campaign --causticd BIN [--short] [--seed N] [--only KIND] [--report FILE.json]\n"
               "kinds: malformed keepalive slow flood sessions\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace campaign;
  Options opt;
  std::string only, report_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--causticd")
      opt.binary = value();
    else if (a == "--short")
      opt.short_mode = true;
    else if (a == "--seed")
      opt.seed = static_cast<unsigned>(std::stoul(value()));
    else if (a == "--only")
      only = value();
    else if (a == "--report")
      report_file = value();
    else {
      usage();
      return 2;
    }
  }
  if (opt.binary.empty() || access(opt.binary.c_str(), X_OK) != 0) {
    std::cerr << "campaign: --causticd must name an executable causticd\n";
    usage();
    return 2;
  }
  // A peer that resets must cost an EPIPE, not the campaign.
  signal(SIGPIPE, SIG_IGN);
  const long fds = raise_descriptor_limit();
  char folder[] = "/tmp/causticd-campaign-XXXXXX";
  if (!mkdtemp(folder)) {
    std::perror("mkdtemp");
    return 2;
  }
  opt.folder = folder;

  struct Entry {
    const char* name;
    void (*run)(const Options&, KindReport&);
  };
  const Entry kinds[] = {{"malformed", run_malformed},
                         {"keepalive", run_keepalive},
                         {"slow", run_slow},
                         {"flood", run_flood},
                         {"sessions", run_sessions}};
  std::vector<std::unique_ptr<KindReport>> reports;
  bool known = only.empty();
  const auto start = Clock::now();
  for (const auto& k : kinds) {
    if (!only.empty() && only != k.name) continue;
    known = true;
    std::printf("running %s%s ...\n", k.name, opt.short_mode ? " (short)" : "");
    std::fflush(stdout);
    reports.push_back(std::make_unique<KindReport>(k.name));
    const auto kind_start = Clock::now();
    k.run(opt, *reports.back());
    reports.back()->figure("kind_seconds", static_cast<long>(ms_since(kind_start) / 1000));
    // Latency goals mean little on a machine busy with other work: say how busy.
    double load = 0;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
      if (std::fscanf(f, "%lf", &load) != 1) load = 0;
      std::fclose(f);
    }
    reports.back()->figure("loadavg_1m_after", load);
    reports.back()->figure("cpus", static_cast<long>(sysconf(_SC_NPROCESSORS_ONLN)));
    reports.back()->print();
    std::fflush(stdout);
  }
  if (!known) {
    std::cerr << "campaign: unknown kind \"" << only << "\"\n";
    usage();
    return 2;
  }

  int passed = 0, failed = 0;
  nlohmann::json out = {{"seed", opt.seed},
                        {"short", opt.short_mode},
                        {"descriptor_limit", fds},
                        {"seconds", static_cast<long>(ms_since(start) / 1000)},
                        {"kinds", nlohmann::json::object()}};
  for (const auto& r : reports) {
    passed += r->checks_passed();
    failed += r->checks_failed();
    out["kinds"][r->name()] = r->to_json();
  }
  out["passed"] = passed;
  out["failed"] = failed;
  if (!report_file.empty()) std::ofstream(report_file) << out.dump(2) << "\n";
  if (failed == 0) {
    std::error_code ec;
    std::filesystem::remove_all(opt.folder, ec);
  } else {
    std::printf("\nserver logs kept in %s\n", opt.folder.c_str());
  }
  std::printf("\n%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
