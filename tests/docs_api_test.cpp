// SPDX-License-Identifier: LGPL-2.1-or-later
// The routes the documents name are the ones docs/openapi.json describes
// (which the REST tests hold to the server's answers), and api.md's table
// lists every one of them with the statuses openapi.json gives it.
#include "doc_text.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

const fs::path kRoot = CAUSTIC_SOURCE_DIR;

// "POST /api/v1/sessions", "GET /metrics" as openapi.json has them.
std::set<std::string> described() {
  const auto doc = nlohmann::json::parse(read_doc(kRoot / "docs" / "openapi.json"));
  std::set<std::string> routes;
  for (const auto& [path, operations] : doc["paths"].items())
    for (const auto& [method, operation] : operations.items()) {
      std::string upper = method;
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      routes.insert(upper + " " + path);
    }
  return routes;
}

// Every "METHOD /path" in `text`, its query left out ("GET /<file>", the
// static files, is no route).
std::vector<std::string> named_routes(const std::string& text) {
  static const std::regex route("(GET|POST|PATCH|DELETE|PUT) (/[A-Za-z0-9_{}.-][A-Za-z0-9_/{}.-]*)");
  std::vector<std::string> routes;
  for (std::sregex_iterator it(text.begin(), text.end(), route), end; it != end; ++it)
    routes.push_back(std::string((*it)[1]) + " " + std::string((*it)[2]));
  return routes;
}

}  // namespace

TEST(DocsApi, EveryRouteNamedIsDescribed) {
  const auto routes = described();
  ASSERT_GT(routes.size(), 10u);
  std::vector<fs::path> docs = {kRoot / "README.md"};
  for (const auto& entry : fs::directory_iterator(kRoot / "docs"))
    if (entry.path().extension() == ".md") docs.push_back(entry.path());
  int checked = 0;
  for (const fs::path& doc : docs)
    for (const std::string& route : named_routes(read_doc(doc))) {
      EXPECT_TRUE(routes.count(route)) << doc.filename().string() << " names " << route
                                       << ", which docs/openapi.json does not describe";
      ++checked;
    }
  EXPECT_GT(checked, 20);
}

TEST(DocsApi, TheApiTableListsEveryRoute) {
  std::set<std::string> listed;
  for (const auto& cells : doc_table(read_doc(kRoot / "docs" / "api.md"), "## Endpoints"))
    for (const std::string& route : named_routes(cells.at(0))) listed.insert(route);
  EXPECT_EQ(listed, described());
}

TEST(DocsApi, TheApiTableStatesEachRoutesStatuses) {
  // "201 `{id, ...}`; 400 malformed JSON, 413, ...": each status the row
  // names is one openapi.json describes for the route, and the other way round.
  const auto doc = nlohmann::json::parse(read_doc(kRoot / "docs" / "openapi.json"));
  static const std::regex status("(^|[^\\w.])([1-5][0-9]{2})(?![\\w.])");
  int checked = 0;
  for (const auto& cells : doc_table(read_doc(kRoot / "docs" / "api.md"), "## Endpoints")) {
    const auto routes = named_routes(cells.at(0));
    if (routes.empty()) continue;
    const std::string text = cells.at(1) + " " + cells.at(2);
    std::set<std::string> stated, described;
    for (std::sregex_iterator it(text.begin(), text.end(), status), end; it != end; ++it) stated.insert((*it)[2]);
    const std::string& route = routes[0];
    const auto space = route.find(' ');
    std::string method = route.substr(0, space);
    for (char& c : method) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const auto& [code, response] : doc["paths"][route.substr(space + 1)][method]["responses"].items())
      described.insert(code);
    EXPECT_EQ(stated, described) << route;
    ++checked;
  }
  EXPECT_GT(checked, 10);
}
