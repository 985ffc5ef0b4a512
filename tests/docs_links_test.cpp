// SPDX-License-Identifier: LGPL-2.1-or-later
// Every relative link in the documents leads somewhere: the file exists and
// a #anchor names a heading of it, as GitHub makes anchors (a heading that
// grew a list of files once left every link to it dangling); and every file
// of the tree a document names in code is there.
#include "doc_text.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

namespace fs = std::filesystem;
using namespace caustic::testing;

namespace {

std::vector<fs::path> documents() {
  const fs::path root = CAUSTIC_SOURCE_DIR;
  std::vector<fs::path> docs = {root / "README.md", root / "THIRD-PARTY-NOTICES.md", root / "assets" / "README.md"};
  for (const auto& entry : fs::directory_iterator(root / "docs"))
    if (entry.path().extension() == ".md") docs.push_back(entry.path());
  return docs;
}

// "" when `target`, written in `doc`, resolves; else why not.
std::string broken(const fs::path& doc, const std::string& target) {
  if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) return "";
  const auto hash = target.find('#');
  const std::string path = target.substr(0, hash);
  const fs::path file = path.empty() ? doc : doc.parent_path() / path;
  if (!fs::exists(file)) return "no file " + file.lexically_normal().string();
  if (hash == std::string::npos || file.extension() != ".md") return "";
  const std::string anchor = target.substr(hash + 1);
  return heading_anchors(read_doc(file)).count(anchor) ? "" : "no heading makes #" + anchor;
}

}  // namespace

TEST(DocsLinks, EveryRelativeLinkAndAnchorResolves) {
  int checked = 0;
  for (const fs::path& doc : documents()) {
    for (const DocLink& link : doc_links(read_doc(doc))) {
      ++checked;
      const std::string why = broken(doc, link.target);
      EXPECT_EQ(why, "") << doc.filename().string() << ":" << link.line << ": (" << link.target << ")";
    }
  }
  // The reader found the links there are, not none.
  EXPECT_GT(checked, 100);
}

TEST(DocsLinks, EveryFileOfTheTreeNamedExists) {
  // `src/gst/include/caustic/gst/stop_pipeline.hpp`, `tests/engine_*_test.cpp`:
  // a path into the tree's folders in a code span, from the root or from
  // the document's folder (docs/bench/...), a '*' matching one name or more.
  static const std::regex path(
      "(^|[^A-Za-z0-9_/.-])((src|tests|tools|bench|web|docs|systemd|janus|proxy|packaging|assets|pipelines|shaders)"
      "/[A-Za-z0-9_./*-]*[A-Za-z0-9_*])");
  const auto exists = [](const fs::path& p) {
    const std::string text = p.lexically_normal().string();
    const auto star = text.find('*');
    if (star == std::string::npos) return fs::exists(p);
    // One star: some file of its folder matches both sides of it.
    const fs::path folder = fs::path(text.substr(0, star)).parent_path();
    const std::string head = fs::path(text.substr(0, star)).filename().string(), tail = text.substr(star + 1);
    if (!fs::is_directory(folder) || tail.find('/') != std::string::npos) return false;
    for (const auto& entry : fs::directory_iterator(folder)) {
      const std::string name = entry.path().filename().string();
      if (name.size() > head.size() + tail.size() && name.rfind(head, 0) == 0 &&
          name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
        return true;
    }
    return false;
  };
  int checked = 0;
  for (const fs::path& doc : documents()) {
    const auto lines = prose_lines(read_doc(doc));
    for (std::size_t i = 0; i < lines.size(); ++i)
      for (const std::string& span : code_spans(lines[i]))
        for (std::sregex_iterator it(span.begin(), span.end(), path), end; it != end; ++it) {
          const std::string named = (*it)[2];
          ++checked;
          EXPECT_TRUE(exists(fs::path(CAUSTIC_SOURCE_DIR) / named) || exists(doc.parent_path() / named))
              << doc.filename().string() << ":" << i + 1 << " names " << named << ", which is not in the tree";
        }
  }
  EXPECT_GT(checked, 50);
}

TEST(DocsLinks, AnchorsAreGitHubs) {
  const auto anchors = heading_anchors("# Top\n## 12. Solids: light through every face\n```\n# not a heading\n```\n"
                                       "## The pool's `water` (src/water)\n## Top\n");
  EXPECT_EQ(anchors, (std::set<std::string>{"top", "12-solids-light-through-every-face", "the-pools-water-srcwater",
                                            "top-1"}));
  const auto links = doc_links("[a](x.md#y) `[b](code.md)`\n```\n[c](fenced.md)\n```\n[d](../LICENSE)\n");
  ASSERT_EQ(links.size(), 2u);
  EXPECT_EQ(links[0].target, "x.md#y");
  EXPECT_EQ(links[1].target, "../LICENSE");
  EXPECT_EQ(links[1].line, 5);
}
