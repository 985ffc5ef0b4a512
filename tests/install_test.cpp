// SPDX-License-Identifier: LGPL-2.1-or-later
// `cmake --install` into a temporary prefix: the installed binary finds its
// data under that prefix and serves the gallery; the installed systemd units
// pass `systemd-analyze verify`, and their exposure score is printed.
#include "server_process.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <unistd.h>

using caustic::testing::http;
using caustic::testing::ServerProcess;
namespace fs = std::filesystem;

namespace {

int run(const std::string& command, std::string* output) {
  gchar *out = nullptr, *err = nullptr;
  gint status = 0;
  GError* error = nullptr;
  if (!g_spawn_command_line_sync(command.c_str(), &out, &err, &status, &error)) {
    *output = error->message;
    g_error_free(error);
    return -1;
  }
  *output = std::string(out ? out : "") + (err ? err : "");
  g_free(out);
  g_free(err);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class Installed : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One prefix per test process: ctest runs the cases of this file side by side.
    prefix_ = fs::temp_directory_path() / ("causticd_install_test_" + std::to_string(getpid()));
    fs::remove_all(prefix_);
    std::string output;
    const int status = run(std::string(CMAKE_COMMAND) + " --install " + CAUSTIC_BUILD_DIR + " --prefix " +
                               prefix_.string(), &output);
    ASSERT_EQ(status, 0) << output;
  }
  static void TearDownTestSuite() { fs::remove_all(prefix_); }
  static inline fs::path prefix_;
};

}  // namespace

TEST_F(Installed, FhsLayoutHoldsEverythingTheServerNeeds) {
  for (const char* file : {"bin/causticd", "share/causticd/assets/scenes/lens.json",
                           "share/causticd/assets/scenes/lens.calibration.json", "share/causticd/assets/meshes/lens.obj",
                           "share/causticd/pipelines/vp8.pipeline", "share/causticd/pipelines/h264.pipeline",
                           "share/causticd/web/index.html", "share/causticd/web/vendor/three/build/three.module.js",
                           "lib/systemd/system/causticd.service", "lib/systemd/system/causticd@.service",
                           "etc/causticd/causticd.conf", "share/doc/causticd/operations.md",
                           "share/doc/causticd/scaling.md", "share/doc/causticd/examples/haproxy.cfg",
                           "share/doc/causticd/examples/nginx.conf", "lib/systemd/system/causticd-janus.service",
                           "share/causticd/janus/janus.jcfg", "share/causticd/janus/setup-broadcast"})
    EXPECT_TRUE(fs::is_regular_file(prefix_ / file)) << file;
}

TEST_F(Installed, TheInstalledBinaryServesTheGalleryFromThePrefix) {
  // Nothing of the build tree is reachable: the data comes from <prefix>/share/causticd.
  ServerProcess server({"--config", (prefix_ / "etc/causticd/causticd.conf").string()},
                       {{"CAUSTICD_DATA_DIR", ""}}, (prefix_ / "bin/causticd").string());
  ASSERT_FALSE(server.url().empty());
  const auto scenes = http("GET", server.url() + "/api/v1/scenes").json()["scenes"];
  // Every installed scene: the four optics scenes and the designed ones the build made.
  std::size_t installed = 0;
  for (const auto& entry : fs::directory_iterator(prefix_ / "share/causticd/assets/scenes")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".json" && !name.ends_with(".calibration.json")) ++installed;
  }
  EXPECT_GE(installed, 4u);
  EXPECT_EQ(scenes.size(), installed);
  const auto page = http("GET", server.url() + "/");
  EXPECT_EQ(page.status, 200u);
  EXPECT_NE(page.body.find("<html"), std::string::npos);
  std::string output;
  EXPECT_EQ(run((prefix_ / "bin/causticd").string() + " check-config " + (prefix_ / "etc/causticd/causticd.conf").string(),
                &output),
            0)
      << output;
}

TEST_F(Installed, SystemdUnitsVerifyAndReportTheirExposure) {
  const fs::path units = prefix_ / "lib/systemd/system";
  // A template is verified through an instance of it.
  fs::create_symlink(units / "causticd@.service", units / "causticd@8081-gpu1.service");
  std::string output;
  const int status = run("systemd-analyze verify --man=no " + (units / "causticd.service").string() + " " +
                             (units / "causticd@8081-gpu1.service").string() + " " +
                             (units / "causticd-janus.service").string(),
                         &output);
  EXPECT_EQ(status, 0) << output;
  // Anything verify says is a problem with the units (it stays quiet on good ones).
  EXPECT_EQ(output.find("causticd"), std::string::npos) << output;

  ASSERT_EQ(run("systemd-analyze security --offline=true --no-pager " + (units / "causticd.service").string(), &output), 0)
      << output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m, std::regex("Overall exposure level for causticd.service: ([0-9.]+)"))) << output;
  const double exposure = std::stod(m[1]);
  std::printf("systemd-analyze security: exposure %.1f\n", exposure);
  EXPECT_LT(exposure, 2.0) << output;
  // docs/operations.md states the rating: it must be the measured one.
  const std::string text = read_text(std::string(CAUSTIC_SOURCE_DIR) + "/docs/operations.md");
  ASSERT_TRUE(std::regex_search(text, m, std::regex("rates the unit \\*\\*([0-9.]+) ")))
      << "docs/operations.md does not state the exposure";
  EXPECT_EQ(m[1].str(), output.substr(output.find(": ", output.find("Overall exposure level")) + 2, m[1].length()));
  // Janus faces the viewers: hardened as far as it runs.
  ASSERT_EQ(run("systemd-analyze security --offline=true --no-pager " + (units / "causticd-janus.service").string(),
                &output),
            0)
      << output;
  ASSERT_TRUE(std::regex_search(output, m, std::regex("Overall exposure level for causticd-janus.service: ([0-9.]+)")))
      << output;
  std::printf("systemd-analyze security causticd-janus.service: exposure %s\n", m[1].str().c_str());
  EXPECT_LT(std::stod(m[1]), 2.0) << output;
}

// The secrets causticd and its Janus share: made once, random, the same in
// both places, readable by their owner alone, kept by a second run (an
// upgrade), and no placeholder left in Janus's files.
TEST_F(Installed, SetupBroadcastMakesSharedSecretsOnceForRootAlone) {
  const fs::path conf = prefix_ / "etc/causticd-broadcast-test";
  const std::string script = (prefix_ / "share/causticd/janus/setup-broadcast").string();
  std::string output;
  ASSERT_EQ(run(script + " " + conf.string() + " 2>&1", &output), 0) << output;
  const std::string env = read_text(conf / "broadcast.env");
  std::map<std::string, std::string> secrets;
  std::smatch m;
  for (auto it = env.cbegin(); std::regex_search(it, env.cend(), m, std::regex("\n(CAUSTICD_JANUS_[A-Z_]+)=([^\n]*)"));
       it = m[0].second)
    secrets[m[1]] = m[2];
  ASSERT_EQ(secrets.size(), 3u) << env;
  for (const auto& [key, value] : secrets) {
    EXPECT_TRUE(std::regex_match(value, std::regex("[A-Za-z0-9+/]{32}"))) << key << "=" << value;
    for (const auto& [other, v] : secrets) EXPECT_TRUE(key == other || v != value) << key << " and " << other;
  }
  const std::string janus = read_text(conf / "janus/janus.jcfg");
  EXPECT_NE(janus.find("admin_secret = \"" + secrets["CAUSTICD_JANUS_ADMIN_SECRET"] + "\""), std::string::npos);
  EXPECT_NE(janus.find("token_auth_secret = \"" + secrets["CAUSTICD_JANUS_TOKEN_SECRET"] + "\""), std::string::npos);
  EXPECT_NE(read_text(conf / "janus/janus.plugin.streaming.jcfg")
                .find("admin_key = \"" + secrets["CAUSTICD_JANUS_STREAMING_KEY"] + "\""),
            std::string::npos);
  for (const auto& file : fs::directory_iterator(conf / "janus")) {
    EXPECT_EQ(read_text(file.path()).find("@JANUS_"), std::string::npos) << file.path();
    EXPECT_EQ(fs::status(file.path()).permissions() & (fs::perms::group_all | fs::perms::others_all), fs::perms::none)
        << file.path();
  }
  EXPECT_EQ(fs::status(conf / "broadcast.env").permissions() & (fs::perms::group_all | fs::perms::others_all),
            fs::perms::none);
  // Again: nothing changes; a removed Janus file comes back with the same secrets.
  fs::remove(conf / "janus/janus.jcfg");
  ASSERT_EQ(run(script + " " + conf.string() + " 2>&1", &output), 0) << output;
  EXPECT_EQ(read_text(conf / "broadcast.env"), env);
  EXPECT_EQ(read_text(conf / "janus/janus.jcfg"), janus);
  fs::remove_all(conf);
}

TEST_F(Installed, UnitsGiveTheServerTheDescriptorsItsLimitsNeed) {
  // The shipped configuration's connections and sessions (about 64
  // descriptors a session) must fit under the unit's LimitNOFILE, or the
  // server runs out of descriptors before it reaches its own limits.
  std::ifstream conf(prefix_ / "etc/causticd/causticd.conf");
  std::string line;
  long connections = 0, sessions = 0;
  std::smatch m;
  while (std::getline(conf, line)) {
    if (std::regex_match(line, m, std::regex("max_connections = ([0-9]+)"))) connections = std::stol(m[1]);
    if (std::regex_match(line, m, std::regex("max_sessions = ([0-9]+)"))) sessions = std::stol(m[1]);
  }
  ASSERT_GT(connections, 0);
  ASSERT_GT(sessions, 0);
  for (const char* unit : {"causticd.service", "causticd@.service"}) {
    const std::string text = read_text(prefix_ / "lib/systemd/system" / unit);
    ASSERT_TRUE(std::regex_search(text, m, std::regex("\nLimitNOFILE=([0-9]+)"))) << unit;
    EXPECT_GE(std::stol(m[1]), connections + 64 * sessions + 64) << unit;
  }
}

TEST(InstalledWithDestdir, EveryFileLandsOnceUnderDestdirAndTheUnitsNameTheRealPaths) {
  // How a package is staged: --prefix /usr with DESTDIR. Each file lands
  // under DESTDIR exactly once (not $DESTDIR$DESTDIR/etc/...), and what the
  // units name is the path on the target system, without DESTDIR.
  const fs::path stage = fs::temp_directory_path() / ("causticd_destdir_test_" + std::to_string(getpid()));
  fs::remove_all(stage);
  std::string output;
  ASSERT_EQ(run("env DESTDIR=" + stage.string() + " " + CMAKE_COMMAND + " --install " + CAUSTIC_BUILD_DIR +
                    " --prefix /usr",
                &output),
            0)
      << output;
  for (const char* file : {"usr/bin/causticd", "etc/causticd/causticd.conf", "usr/lib/systemd/system/causticd.service",
                           "usr/lib/systemd/system/causticd@.service", "usr/lib/sysusers.d/causticd.conf",
                           "usr/share/causticd/web/index.html"})
    EXPECT_TRUE(fs::is_regular_file(stage / file)) << file;
  const std::string doubled = stage.relative_path().string();
  for (const auto& entry : fs::recursive_directory_iterator(stage))
    EXPECT_EQ(fs::relative(entry.path(), stage).string().find(doubled), std::string::npos) << entry.path();
  const std::string unit = read_text(stage / "usr/lib/systemd/system/causticd.service");
  EXPECT_NE(unit.find("ExecStart=/usr/bin/causticd serve --config /etc/causticd/causticd.conf"), std::string::npos)
      << unit;
  EXPECT_EQ(unit.find(stage.string()), std::string::npos) << unit;
  fs::remove_all(stage);
}

TEST_F(Installed, UnitsCanBeEnabledAndDoNotRestartForeverOrAssumeAHostsGroupsAndGpus) {
  for (const char* name : {"causticd.service", "causticd@.service"}) {
    const std::string unit = read_text(prefix_ / "lib/systemd/system" / name);
    // `systemctl enable` needs an [Install] section to act on.
    EXPECT_NE(unit.find("\n[Install]\nWantedBy=multi-user.target"), std::string::npos) << name;
    // A configuration error (exit 2) is not restarted; anything else stops
    // at a start limit that RestartSec=2 can reach (5 starts within 300 s).
    EXPECT_NE(unit.find("\nRestartPreventExitStatus=2\n"), std::string::npos) << name;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(unit, m, std::regex("\nStartLimitIntervalSec=([0-9]+)\nStartLimitBurst=([0-9]+)")))
        << name;
    ASSERT_TRUE(std::regex_search(unit, m, std::regex("\nRestartSec=([0-9]+)"))) << name;
    // Device rules by driver class, so that any GPU index is covered.
    EXPECT_FALSE(std::regex_search(unit, std::regex("DeviceAllow=/dev/nvidia[0-9]"))) << name;
    EXPECT_NE(unit.find("DeviceAllow=char-nvidia-frontend rw"), std::string::npos) << name;
    // The dynamic user gets a home for GLib and GStreamer's registry.
    EXPECT_NE(unit.find("HOME=%C/causticd"), std::string::npos) << name;
  }
  // Janus: the appliance's own configuration, every file of it handed over
  // as a credential (root-only files, a dynamic user), never Debian's
  // janus.service beside it; causticd reads the shared secrets.
  const std::string janus = read_text(prefix_ / "lib/systemd/system/causticd-janus.service");
  EXPECT_NE(janus.find("\nConflicts=janus.service\n"), std::string::npos) << janus;
  EXPECT_NE(janus.find("\nExecStart=/usr/bin/janus -F %d -C %d/janus.jcfg"), std::string::npos) << janus;
  EXPECT_NE(janus.find("\nDynamicUser=yes\n"), std::string::npos) << janus;
  EXPECT_NE(janus.find("\n[Install]\nWantedBy=multi-user.target"), std::string::npos) << janus;
  int templates = 0;
  for (const auto& file : fs::directory_iterator(prefix_ / "share/causticd/janus"))
    if (file.path().extension() == ".jcfg") {
      ++templates;
      const std::string name = file.path().filename();
      EXPECT_NE(janus.find("\nLoadCredential=" + name + ":" + (prefix_ / "etc/causticd/janus" / name).string() + "\n"),
                std::string::npos)
          << name << " is not handed to Janus";
    }
  EXPECT_EQ(templates, 4);
  for (const char* name : {"causticd.service", "causticd@.service"})
    EXPECT_NE(read_text(prefix_ / "lib/systemd/system" / name)
                  .find("\nEnvironmentFile=-" + (prefix_ / "etc/causticd/broadcast.env").string() + "\n"),
              std::string::npos)
        << name;
  // The groups the units ask for are created where they are missing.
  const std::string sysusers = read_text(prefix_ / "lib/sysusers.d/causticd.conf");
  const std::string unit = read_text(prefix_ / "lib/systemd/system/causticd.service");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(unit, m, std::regex("\nSupplementaryGroups=([^\n]*)")));
  std::istringstream groups(m[1].str());
  for (std::string group; groups >> group;)
    EXPECT_TRUE(std::regex_search(sysusers, std::regex("\ng " + group + " "))) << group << " is not in sysusers.d";
}
