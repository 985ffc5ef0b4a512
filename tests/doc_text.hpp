// SPDX-License-Identifier: LGPL-2.1-or-later
// Reading the project's Markdown as GitHub shows it: its links, the anchors
// its headings make, and its tables, for the tests that hold the documents
// to the code they describe.
#pragma once

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace caustic::testing {

inline std::string read_doc(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The lines outside fenced code blocks, numbered from 1 (a fenced line is
/// left empty, so that numbers stay those of the file).
inline std::vector<std::string> prose_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  bool fenced = false;
  for (std::string line; std::getline(in, line);) {
    const bool fence = line.rfind("```", 0) == 0;
    if (fence) fenced = !fenced;
    out.push_back(fence || fenced ? "" : line);
  }
  return out;
}

/// GitHub's anchor for a heading: lower case, every ASCII character but
/// letters, digits, '_', '-' and spaces dropped, spaces made '-' (bytes
/// beyond ASCII kept: the headings here have none); a repeated one gets
/// -1, -2, ...
inline std::set<std::string> heading_anchors(const std::string& text) {
  std::set<std::string> anchors;
  static const std::regex heading("^#{1,6} +(.*?) *$");
  for (const std::string& line : prose_lines(text)) {
    std::smatch m;
    if (!std::regex_match(line, m, heading)) continue;
    std::string slug;
    for (unsigned char c : std::string(m[1])) {
      if (c >= 0x80 || std::isalnum(c) || c == '_' || c == '-')
        slug += static_cast<char>(c >= 0x80 ? c : std::tolower(c));
      else if (c == ' ')
        slug += '-';
    }
    std::string unique = slug;
    for (int n = 1; anchors.count(unique); ++n) unique = slug + "-" + std::to_string(n);
    anchors.insert(unique);
  }
  return anchors;
}

struct DocLink {
  std::string target;  ///< as written: "physics.md#12-solids", "#receivers", "../LICENSE"
  int line;
};

/// Inline links `[text](target)` in prose, code spans left out.
inline std::vector<DocLink> doc_links(const std::string& text) {
  std::vector<DocLink> links;
  static const std::regex code_span("`[^`]*`");
  static const std::regex link("\\]\\(([^()\\s]+)\\)");
  const auto lines = prose_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string line = std::regex_replace(lines[i], code_span, "``");
    for (std::sregex_iterator it(line.begin(), line.end(), link), end; it != end; ++it)
      links.push_back({(*it)[1], static_cast<int>(i + 1)});
  }
  return links;
}

/// The cells of each row of the first table after the heading `heading`
/// (the whole line, "## `object`"), header and rule left out; an escaped
/// "\|" is a '|' within a cell.
inline std::vector<std::vector<std::string>> doc_table(const std::string& text, const std::string& heading) {
  std::vector<std::vector<std::string>> rows;
  const auto lines = prose_lines(text);
  std::size_t i = 0;
  while (i < lines.size() && lines[i] != heading) ++i;
  while (i < lines.size() && lines[i].rfind("|", 0) != 0) ++i;
  for (i += 2; i < lines.size() && lines[i].rfind("|", 0) == 0; ++i) {
    std::vector<std::string> cells;
    std::string cell;
    const std::string& line = lines[i];
    for (std::size_t k = 1; k < line.size(); ++k) {
      if (line[k] == '\\' && k + 1 < line.size() && line[k + 1] == '|') {
        cell += '|';
        ++k;
      } else if (line[k] == '|') {
        const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
        cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
        cell.clear();
      } else {
        cell += line[k];
      }
    }
    rows.push_back(cells);
  }
  return rows;
}

/// The `code spans` of a cell, in order.
inline std::vector<std::string> code_spans(const std::string& cell) {
  std::vector<std::string> spans;
  static const std::regex span("`([^`]*)`");
  for (std::sregex_iterator it(cell.begin(), cell.end(), span), end; it != end; ++it) spans.push_back((*it)[1]);
  return spans;
}

}  // namespace caustic::testing
