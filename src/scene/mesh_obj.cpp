// SPDX-License-Identifier: LGPL-2.1-or-later
// OBJ reading for the caustic face and receiver shapes, with the validation
// every consumer of a Mesh relies on (writing: mesh_obj_write.cpp).
#include "caustic/mesh.hpp"

#include "caustic/json_text.hpp"
#include "obj_words.hpp"

#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <streambuf>
#include <string_view>
#include <limits>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

namespace caustic {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// tinyobjloader reads a malformed or non-finite number ("nan", "1e999",
// "abc") as 0 without a word; a caustic face with a vertex silently moved
// to the origin must be an error instead, with the line that holds it.
// Only the statements a caustic face needs are read at all: "mtllib" would
// make the loader open other files (a path to /dev/zero reads forever) and
// "vw" converts an unchecked number to int.
// A vertex line with a colour has six numbers; the loader keeps colours
// only when every vertex has one, so a file that mixes the two would lose
// its tint without a word: an error names the first line that differs.
// The loader also wraps a face's index past 2^31 round to another vertex,
// reads "1.5" or "3x" as an index, and keeps every "o" and "g" as a shape
// of its own (8 million of them, 100 MB of text, took 5 GB before the
// triangle limit could be checked): indices are checked here, and the
// statements counted against the limits before the loader runs. So are
// what else it keeps as the file grows: an "l" line's corners (200 MB took
// 4 GB; refused, no triangle), a warning per "usemtl" (no library), each
// "vn" and "vt" (bounded by the vertex limit: each one a face uses makes a
// vertex of its own; a receiver's atlas needs vt, a caustic face not).
constexpr std::size_t kMaxGroups = 4096;  // "o", "g" and "usemtl" statements
constexpr std::ptrdiff_t kMaxLineBytes = 1 << 16;

void check_numbers(std::string_view text, const std::string& label, const MeshLimits& limits) {
  const double max_coordinate = limits.max_coordinate;
  std::size_t vertices = 0, faces = 0, groups = 0, normals = 0, texcoords = 0;
  static const char* const kStatements[] = {"v", "vn", "vt", "f", "o", "g", "s", "l", "usemtl"};
  // One pass over the text with no stream a line: a caustic face is
  // megabytes, and every gallery scene's is read at start-up.
  // The loader's blanks: a form feed or vertical tab is none to it, so a
  // line holding one (or a NUL, which ends its line there) is refused below.
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t'; };
  const auto fail = [&](std::size_t number, const std::string& what) {
    throw SceneError("mesh", "mesh file " + label + " line " + std::to_string(number) + ": " + what);
  };
  std::string word;  // the word being read, NUL-terminated for strtod
  int first_coloured = -1;  // whether the first vertex line has a colour; -1 before it
  detail::Named named_vertices, named_normals;
  const char* p = text.data();
  const char* const end = p + text.size();
  for (std::size_t number = 1; p < end; ++number) {
    // The loader ends a line at '\r' as well as '\n'; "\r\n" is one end.
    const char* line_end = p;
    bool control = false;  // a byte below 0x20 other than a tab, or DEL
    for (; line_end < end && *line_end != '\n' && *line_end != '\r'; ++line_end)
      control = control || (static_cast<unsigned char>(*line_end) < 0x20 && *line_end != '\t') || *line_end == 0x7f;
    const char* const next = line_end + (line_end + 1 < end && line_end[0] == '\r' && line_end[1] == '\n' ? 2 : 1);
    // The loader copies each line, growing its copy by doubling: one line
    // of 1 GiB (a comment) would take 2 GiB more. A triangle's is ~100 bytes.
    if (line_end - p > kMaxLineBytes) fail(number, "longer than " + std::to_string(kMaxLineBytes) + " bytes");
    // The words of the line, one at a time.
    const auto next_word = [&]() -> bool {
      while (p < line_end && blank(*p)) ++p;
      const char* from = p;
      while (p < line_end && !blank(*p)) ++p;
      word.assign(from, p);
      return !word.empty();
    };
    if (!next_word() || word[0] == '#') {
      p = next;
      continue;
    }
    // Not quoted: the words around it would carry it into the message.
    if (control) fail(number, "holds a control character; only spaces and tabs separate an OBJ line's words");
    const std::string tag = word;
    bool known = false;
    for (const char* statement : kStatements) known = known || tag == statement;
    if (!known) {
      // Named when it reads as a statement; a file that is no OBJ (a path
      // to another file) is not quoted.
      const bool word_like = tag.size() <= 16 && tag.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos;
      fail(number, (word_like ? "the statement \"" + tag + "\" is" : std::string("this line's statement is")) +
                       " not supported (v, vn, vt, f, o, g, s, l, usemtl)");
    }
    if (tag == "o" || tag == "g" || tag == "usemtl") {
      if (++groups > kMaxGroups)
        fail(number, "more than " + std::to_string(kMaxGroups) + " objects, groups and materials");
    } else if (tag == "l") {
      fail(number, "a line (l) is no triangle; only triangles are allowed");
    } else if (tag == "f") {
      if (++faces > limits.max_triangles)
        fail(number, "more than " + std::to_string(limits.max_triangles) + " faces");
      std::size_t corners = 0;
      for (long long index[3]; next_word(); ++corners) {
        if (!detail::face_corner(word, index))
          fail(number, "a face's corner must be v, v/vt, v//vn or v/vt/vn, each a nonzero whole number within an int");
        // Texture coordinates are read only for a receiver's atlas, which checks them.
        for (const std::string& error : {named_vertices.take(index[0], vertices, number, "vertex"),
                                         named_normals.take(index[2], normals, number, "normal")})
          if (!error.empty()) fail(number, error);
      }
      if (corners < 3) fail(number, "a face needs at least 3 corners");
      // Said here with its line: the reader keeps a face's corner count in
      // a byte, so a face of 259 corners would come out as a triangle.
      if (corners != 3)
        fail(number, "a face of " + std::to_string(corners) + " vertices; only triangles are allowed");
    }
    if (tag != "v" && tag != "vn" && tag != "vt") {
      p = next;
      continue;
    }
    if (tag == "v" && ++vertices > limits.max_vertices)
      fail(number, "more than " + std::to_string(limits.max_vertices) + " vertices");
    if ((tag == "vn" && ++normals > limits.max_vertices) || (tag == "vt" && ++texcoords > limits.max_vertices))
      fail(number, "more than " + std::to_string(limits.max_vertices) + (tag == "vn" ? " normals" : " texture coordinates") +
                       " (at most one for each vertex the limit allows)");
    double numbers[6];
    std::string colours[3];  // as written, for a colour's error
    std::size_t count = 0;
    for (; next_word(); ++count) {
      char* stop = nullptr;
      if (word[0] == '#') fail(number, "a comment (#) must be a line of its own");
      const double x = std::strtod(word.c_str(), &stop);
      if (stop != word.c_str() + word.size() || !std::isfinite(x))
        fail(number, "\"" + word + "\" is not a finite number (NaN, Inf or malformed)");
      if (!detail::decimal_number(word))
        fail(number, "\"" + word + "\" is not a decimal number (OBJ numbers are written as 12, -0.5 or 1.5e-3, "
                                    "with an exponent of at most 308; hex is not read)");
      if (count < 6) numbers[count] = x;
      if (count >= 3 && count < 6) colours[count - 3] = word;
      // Read as floats, 1e300 would become Inf: over the limit, said here with its line.
      if (tag == "v" && count < 3 && std::abs(x) > max_coordinate)
        fail(number, "the coordinate " + word + " lies beyond the coordinate limit of 1e6");
    }
    p = next;
    if (tag == "v" && count != 3 && count != 4 && count != 6)
      fail(number, "a vertex is x y z, x y z w (a weight), or x y z r g b (a colour)");
    if (tag == "vn" && count != 3) fail(number, "a normal is x y z");
    if (tag == "vt" && count != 2 && count != 3) fail(number, "a texture coordinate is u v, or u v w");
    if (tag != "v") continue;
    const int coloured = count >= 6 ? 1 : 0;
    for (std::size_t k = 3; coloured && k < 6; ++k)
      if (!(numbers[k] >= 0 && numbers[k] <= 1))
        fail(number, "the colour " + colours[k - 3] + " is outside [0, 1] (a vertex colour is the fraction of light passed)");
    if (first_coloured < 0) first_coloured = coloured;
    if (coloured != first_coloured)
      fail(number, std::string(coloured ? "this vertex has a colour but the first has none"
                                        : "this vertex has no colour but the first has one") +
                       "; give every vertex a colour (v x y z r g b) or none");
  }
  if (const std::string error = named_vertices.past(vertices, "vertex"); !error.empty())
    fail(named_vertices.line, error);
  if (const std::string error = named_normals.past(normals, "normal"); !error.empty()) fail(named_normals.line, error);
}

Mesh read_obj(const std::filesystem::path& file, const MeshLimits& limits, bool atlas);

// A read-only stream over the text in memory.
class InPlace : public std::streambuf {
 public:
  explicit InPlace(std::string_view text) {
    char* begin = const_cast<char*>(text.data());  // only ever read: no put area
    setg(begin, begin, begin + text.size());
  }
};

}  // namespace

std::vector<glm::vec3> smooth_normals(const std::vector<glm::vec3>& positions,
                                      const std::vector<glm::uvec3>& triangles) {
  std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
  glm::dvec3 total(0.0);
  for (const auto& t : triangles) {
    const glm::dvec3 a = positions[t.x], b = positions[t.y], c = positions[t.z];
    const glm::dvec3 area_vector = glm::cross(b - a, c - a);  // length = twice the area: area weighting
    for (int k = 0; k < 3; ++k) sum[t[k]] += area_vector;
    total += area_vector;
  }
  const glm::dvec3 fallback = glm::length(total) > 0 ? glm::normalize(total) : glm::dvec3(0, 0, 1);
  std::vector<glm::vec3> normals(positions.size());
  for (std::size_t i = 0; i < sum.size(); ++i)
    normals[i] = glm::vec3(glm::length(sum[i]) > 0 ? glm::normalize(sum[i]) : fallback);
  return normals;
}

void validate_mesh(const Mesh& mesh, const MeshLimits& limits) {
  if (mesh.triangles.empty()) throw SceneError("mesh", "has no triangles");
  if (mesh.positions.size() > limits.max_vertices)
    throw SceneError("mesh", "has " + std::to_string(mesh.positions.size()) + " vertices, more than the limit of " +
                                 std::to_string(limits.max_vertices));
  if (mesh.triangles.size() > limits.max_triangles)
    throw SceneError("mesh", "has " + std::to_string(mesh.triangles.size()) + " triangles, more than the limit of " +
                                 std::to_string(limits.max_triangles));
  if (mesh.normals.size() != mesh.positions.size()) throw SceneError("mesh", "needs exactly one normal per vertex");
  if (tinted(mesh) && mesh.colours.size() != mesh.positions.size())
    throw SceneError("mesh", "needs exactly one colour per vertex, or none");
  for (std::size_t i = 0; i < mesh.colours.size(); ++i) {
    const auto& c = mesh.colours[i];
    if (!(glm::all(glm::greaterThanEqual(c, glm::vec3(0))) && glm::all(glm::lessThanEqual(c, glm::vec3(1)))))
      throw SceneError("mesh", "colour of vertex " + std::to_string(i + 1) + " is outside [0, 1]");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    if (!finite(p)) throw SceneError("mesh", "vertex " + std::to_string(i + 1) + " is not finite (NaN or Inf)");
    if (std::abs(p.x) > limits.max_coordinate || std::abs(p.y) > limits.max_coordinate ||
        std::abs(p.z) > limits.max_coordinate)
      throw SceneError("mesh", "vertex " + std::to_string(i + 1) + " lies beyond the coordinate limit of 1e6");
    const auto& n = mesh.normals[i];
    if (!finite(n) || std::abs(glm::length(n) - 1.0f) > 1e-3f)
      throw SceneError("mesh", "normal of vertex " + std::to_string(i + 1) + " is not a finite unit vector");
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[i][k] >= mesh.positions.size())
        throw SceneError("mesh", "triangle " + std::to_string(i + 1) + " refers to a vertex that does not exist");
  // Triangles that all lie on a line or a point bend no light: such a glass
  // would be shown black, as if the scene were wrong in some other way.
  // Measured against the bounding box, so that units do not matter.
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const auto& p : mesh.positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
  double area = 0;
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const double span = glm::length(hi - lo);
  if (!(area > 1e-9 * span * span)) throw SceneError("mesh", "has no area: every triangle lies on a line or a point");
}

Mesh load_obj(const std::filesystem::path& file, const MeshLimits& limits) { return read_obj(file, limits, false); }

Mesh load_atlas_obj(const std::filesystem::path& file, const MeshLimits& limits) { return read_obj(file, limits, true); }

namespace {

// `atlas`: keep each corner's vt (Mesh::uvs), a vertex per (position, normal, vt).
Mesh read_obj(const std::filesystem::path& file, const MeshLimits& limits, bool atlas) {
  // Messages name the file by its base name only: the full path of a
  // protected mesh is not something to echo back to a client. Read as a
  // regular file alone (a pipe swapped in is not waited on), bounded.
  const std::string label = file.filename().string();
  const FileText read = read_file_text(file, limits.max_file_bytes);
  if (read.not_a_file) throw SceneError("mesh", "mesh file " + label + " is a folder, pipe, socket, device or kernel file, not a file");
  if (!read.opened) throw SceneError("mesh", "cannot read mesh file " + label + why_unread(read));
  if (read.too_large) throw SceneError("mesh", "mesh file " + label + " is larger than the limit");
  // A byte order mark, which some editors write first, is no statement.
  std::string_view text = read.text;
  if (text.substr(0, 3) == "\xef\xbb\xbf") text.remove_prefix(3);
  check_numbers(text, label, limits);
  // From memory, with no material reader: the loader never opens a file of
  // its own, whatever the text names. The text is read where it lies (the
  // loader's ParseFromString copies it: a 1 GiB file held 2 GiB).
  InPlace buffer(text);
  std::istream stream(&buffer);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr, false, false)) {
    while (!err.empty() && err.back() == '\n') err.pop_back();
    throw SceneError("mesh", "mesh file " + label + " is not a valid OBJ: " + (err.empty() ? "parse error" : err));
  }
  const std::size_t vertex_count = attrib.vertices.size() / 3;
  // check_numbers made sure every vertex has a colour or none does.
  const bool coloured = attrib.colors.size() == attrib.vertices.size() && !attrib.colors.empty();
  if (vertex_count > limits.max_vertices)
    throw SceneError("mesh", "mesh file " + label + " has more than " + std::to_string(limits.max_vertices) + " vertices");

  Mesh mesh;
  bool all_normals = true;
  // (position, normal, vt) -> vertex: most positions come with one normal
  // and vt, held beside the position; the others (a crease, an atlas seam)
  // go to a map.
  struct Made {
    int normal, uv;
    unsigned vertex;
  };
  constexpr unsigned kNone = ~0u;
  std::vector<Made> first_made(vertex_count, Made{0, 0, kNone});
  std::map<std::tuple<int, int, int>, unsigned> other_made;
  const auto made = [&](int position, int normal, int uv) -> std::pair<unsigned*, bool> {
    Made& first = first_made[static_cast<std::size_t>(position)];
    if (first.vertex == kNone) {
      first = {normal, uv, static_cast<unsigned>(mesh.positions.size())};
      return {&first.vertex, true};
    }
    if (first.normal == normal && first.uv == uv) return {&first.vertex, false};
    auto [it, inserted] = other_made.try_emplace({position, normal, uv}, static_cast<unsigned>(mesh.positions.size()));
    return {&it->second, inserted};
  };
  for (const auto& shape : shapes) {
    if (!shape.lines.indices.empty() || !shape.points.indices.empty())
      throw SceneError("mesh", "mesh file " + label + " holds lines or points; only triangles are allowed");
    const auto& m = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      const unsigned fv = m.num_face_vertices[f];
      if (fv != 3)
        throw SceneError("mesh", "mesh file " + label + ": face " + std::to_string(f + 1) + " of \"" + shape.name +
                                     "\" has " + std::to_string(fv) + " vertices; only triangles are allowed");
      glm::uvec3 tri;
      for (unsigned k = 0; k < 3; ++k) {
        const auto& idx = m.indices[offset + k];
        if (idx.vertex_index < 0 || static_cast<std::size_t>(idx.vertex_index) >= vertex_count)
          throw SceneError("mesh", "mesh file " + label + ": a face refers to a vertex that does not exist");
        if (idx.normal_index < 0) all_normals = false;
        if (idx.normal_index >= 0 && static_cast<std::size_t>(idx.normal_index) >= attrib.normals.size() / 3)
          throw SceneError("mesh", "mesh file " + label + ": a face refers to a normal that does not exist");
        if (atlas && (idx.texcoord_index < 0 || static_cast<std::size_t>(idx.texcoord_index) >= attrib.texcoords.size() / 2))
          throw SceneError("mesh", "mesh file " + label + ": face " + std::to_string(f + 1) + " of \"" + shape.name +
                                       "\" has a corner without a texture coordinate (vt); a receiver's shape needs "
                                       "its atlas on every corner");
        const auto [vertex, inserted] = made(idx.vertex_index, idx.normal_index, atlas ? idx.texcoord_index : -1);
        if (inserted) {
          const float* p = &attrib.vertices[3 * idx.vertex_index];
          mesh.positions.emplace_back(p[0], p[1], p[2]);
          if (coloured) {
            const float* c = &attrib.colors[3 * idx.vertex_index];
            mesh.colours.emplace_back(c[0], c[1], c[2]);
          }
          if (idx.normal_index >= 0) {
            const float* n = &attrib.normals[3 * idx.normal_index];
            const glm::vec3 normal(n[0], n[1], n[2]);
            const float len = glm::length(normal);
            if (!finite(normal) || !(len > 0))
              throw SceneError("mesh", "mesh file " + label + ": normal " + std::to_string(idx.normal_index + 1) +
                                           " is zero or not finite");
            mesh.normals.push_back(normal / len);
          } else {
            mesh.normals.emplace_back(0.0f);
          }
          if (atlas) {
            const glm::vec2 uv(attrib.texcoords[2 * idx.texcoord_index], attrib.texcoords[2 * idx.texcoord_index + 1]);
            if (!(uv.x >= 0 && uv.x <= 1 && uv.y >= 0 && uv.y <= 1))
              throw SceneError("mesh", "mesh file " + label + ": texture coordinate " +
                                           std::to_string(idx.texcoord_index + 1) + " lies outside [0, 1]");
            mesh.uvs.push_back(uv);
          }
          if (mesh.positions.size() > limits.max_vertices)
            throw SceneError("mesh", "mesh file " + label + " has more than " + std::to_string(limits.max_vertices) +
                                         " vertices");
        }
        tri[k] = *vertex;
      }
      mesh.triangles.push_back(tri);
      if (mesh.triangles.size() > limits.max_triangles)
        throw SceneError("mesh", "mesh file " + label + " has more than " + std::to_string(limits.max_triangles) +
                                     " triangles");
      offset += 3;
    }
  }
  if (mesh.triangles.empty()) throw SceneError("mesh", "mesh file " + label + " holds no triangles");
  for (const auto& p : mesh.positions)
    if (!finite(p)) throw SceneError("mesh", "mesh file " + label + " has a vertex that is NaN or Inf");
  if (!all_normals) mesh.normals = smooth_normals(mesh.positions, mesh.triangles);
  validate_mesh(mesh, limits);
  return mesh;
}

}  // namespace

}  // namespace caustic
