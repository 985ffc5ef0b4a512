// SPDX-License-Identifier: LGPL-2.1-or-later
#include "passes.hpp"

#include "caustic/receivers.hpp"
#include "caustic/vertex_rays.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <cstddef>
#include <string>

namespace caustic {
namespace {

// uName[i] of a uniform array.
std::string element(const char* name, std::size_t i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

// One float attribute of an interleaved vertex: its components and offset.
struct Attribute {
  GLint size;
  std::size_t offset;
};

// Attributes 0, 1, ... of `vao`, in order, all from its buffer binding 0.
void describe(GLuint vao, std::initializer_list<Attribute> attributes) {
  GLuint index = 0;
  for (const Attribute& a : attributes) {
    glEnableVertexArrayAttrib(vao, index);
    glVertexArrayAttribFormat(vao, index, a.size, GL_FLOAT, GL_FALSE, static_cast<GLuint>(a.offset));
    glVertexArrayAttribBinding(vao, index, 0);
    ++index;
  }
}

// Overlapping (folded) sheets add up as light does: no depth test, no
// culling, additive blending.
void add_up() {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
}

// Draws into `target`, black first when `clear`.
void bind(const gl::RenderTarget& target, bool clear) {
  target.bind();
  const float black[4] = {0, 0, 0, 0};
  if (clear) glClearNamedFramebufferfv(target.framebuffer.id(), GL_COLOR, 0, black);
}

}  // namespace

RayPass::RayPass()
    : program_({{GL_VERTEX_SHADER, {"optics.glsl", "caustic.vert"}},
                {GL_GEOMETRY_SHADER, {"optics.glsl", "caustic.geom"}},
                {GL_FRAGMENT_SHADER, {"caustic.frag"}}}),
      landed_program_({{GL_VERTEX_SHADER, {"caustic_landed.vert"}},
                       {GL_GEOMETRY_SHADER, {"optics.glsl", "caustic.geom"}},
                       {GL_FRAGMENT_SHADER, {"caustic.frag"}}}) {
  glNamedBufferStorage(counters_.id(), sizeof(TriangleCounts), nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
}

void RayPass::upload(const Mesh& mesh) {
  // Immutable storage cannot be resized: a new mesh gets new buffers.
  positions_ = gl::Buffer();
  normals_ = gl::Buffer();
  colours_ = gl::Buffer();
  indices_ = gl::Buffer();
  vao_ = gl::VertexArray();
  glNamedBufferStorage(positions_.id(), static_cast<GLsizeiptr>(mesh.positions.size() * sizeof(glm::vec3)),
                       mesh.positions.data(), 0);
  glNamedBufferStorage(normals_.id(), static_cast<GLsizeiptr>(mesh.normals.size() * sizeof(glm::vec3)),
                       mesh.normals.data(), 0);
  glNamedBufferStorage(indices_.id(), static_cast<GLsizeiptr>(mesh.triangles.size() * sizeof(glm::uvec3)),
                       mesh.triangles.data(), 0);
  const GLuint vao = vao_.id();
  glVertexArrayVertexBuffer(vao, 0, positions_.id(), 0, sizeof(glm::vec3));
  glVertexArrayVertexBuffer(vao, 1, normals_.id(), 0, sizeof(glm::vec3));
  for (GLuint attrib = 0; attrib < 2; ++attrib) {
    glEnableVertexArrayAttrib(vao, attrib);
    glVertexArrayAttribFormat(vao, attrib, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, attrib, attrib);
  }
  tinted_ = tinted(mesh);
  if (tinted_) {
    glNamedBufferStorage(colours_.id(), static_cast<GLsizeiptr>(mesh.colours.size() * sizeof(glm::vec3)),
                         mesh.colours.data(), 0);
    glVertexArrayVertexBuffer(vao, 2, colours_.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao, 2);
    glVertexArrayAttribFormat(vao, 2, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 2, 2);
  }
  glVertexArrayElementBuffer(vao, indices_.id());
  index_count_ = static_cast<GLsizei>(mesh.triangles.size() * 3);
  gl::check_errors("mesh upload");
}

void RayPass::draw(const Scene& scene, const Placement& placement, const gl::RenderTarget& target, double ior,
                   glm::vec3 weight, bool clear, bool count) {
  on_the_gl(clear);
  const auto& p = program_;
  const auto& screen = scene.screen;
  p.set("uModel", glm::mat4(placement.model));
  p.set("uRotation", glm::mat3(placement.rotation));
  p.set("uFlatNormal", glm::vec3(placement.flat_normal));
  p.set("uFlatOffset", static_cast<float>(placement.flat_offset));
  p.set("uIor", static_cast<float>(ior));
  p.set("uReflective", scene.object.material == Material::reflective);
  p.set("uFlatFirst", flat_face_first(scene, placement));
  p.set("uImmersed", scene.object.shape == Shape::surface);
  p.set("uExactPointModel", scene.light.point_model == PointModel::exact);
  p.set("uFresnel", scene.render.fresnel);
  p.set("uScreenCenter", glm::vec3(screen.center));
  p.set("uScreenNormal", glm::vec3(screen.normal));
  p.set("uScreenRight", glm::vec3(screen_right(screen)));
  p.set("uScreenUp", glm::vec3(screen.up));
  p.set("uReportPlaneDistance", static_cast<float>(scene.render.report_plane_distance));
  const auto surfaces = receiving_surfaces(scene);
  p.set("uSurfaceCount", static_cast<int>(surfaces.size()));
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    p.set(element("uSurfaceCenter", i).c_str(), glm::vec3(surfaces[i].center));
    p.set(element("uSurfaceNormal", i).c_str(), glm::vec3(surfaces[i].normal));
    p.set(element("uSurfaceRight", i).c_str(), glm::vec3(screen_right(surfaces[i])));
    p.set(element("uSurfaceUp", i).c_str(), glm::vec3(surfaces[i].up));
  }
  deposit(program_, vao_.id(), index_count_, scene, placement, target, weight, clear, count, !tinted_);
}

void RayPass::draw_on_cpu(const Scene& scene, const Placement& placement, const Mesh& mesh,
                          const gl::RenderTarget& target, double ior, glm::vec3 weight, bool clear, bool count) {
  // A scene with a shaped receiver lands here whatever the renderer, so
  // its parted triangles can be sampled finer than caustic.geom's corners;
  // a scene of rectangles keeps the corners, drawing what the GL draws.
  const PartedRays parted = has_shaped_receiver(scene) ? parted_rays(scene, placement, mesh, ior) : nullptr;
  draw_deposited(land_vertices(scene, placement, mesh, ior), mesh.triangles, scene, placement, target, weight, clear,
                 count, parted ? &parted : nullptr);
}

void RayPass::draw_deposited(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles,
                             const Scene& scene, const Placement& placement, const gl::RenderTarget& target,
                             glm::vec3 weight, bool clear, bool count, const PartedRays* parted) {
  if (clear) {
    raster_.reset(target.texture.width(), target.texture.height(), target.texture.format() == GL_R32F ? 1 : 3);
    raster_texture_ = target.texture.id();
  } else if (!raster_pending_ || raster_texture_ != target.texture.id()) {
    throw EngineError("a pass set up on the CPU adds only to the CPU's passes before it");
  } else {
    raster_.flush();  // the passes before, deposited: the next may set other triangles up
  }
  whole_image_ = nullptr;
  deposit_on_cpu(rays, triangles, scene, placement, glm::dvec3(weight), &raster_, count ? &cpu_counts_ : nullptr,
                 parted);
  if (count) counted_on_cpu_ = true;
  raster_pending_ = true;
}

void RayPass::on_the_gl(bool clear) {
  if (!clear) upload_whole_image();  // added to: the texture must hold what is there
  whole_image_ = nullptr;
  raster_pending_ = false;
}

void RayPass::settle() {
  if (!raster_pending_) return;
  // The passes summed on the CPU are the target's whole content, uploaded
  // when a reader on the GL needs it (a full-size pass less on a software
  // renderer; none at all for a grey frame post-processed on the CPU).
  whole_image_ = &raster_.resolve(true);
  whole_texture_ = raster_texture_;
  whole_uploaded_ = false;
  raster_pending_ = false;
}

void RayPass::upload_whole_image() {
  settle();
  if (!whole_image_ || whole_uploaded_) return;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(whole_texture_, 0, 0, 0, raster_.width(), raster_.height(),
                      raster_.channels() == 1 ? GL_RED : GL_RGBA, GL_FLOAT, whole_image_->data());
  gl::check_errors("caustic pass (CPU deposit upload)");
  whole_uploaded_ = true;
}

void RayPass::draw_landed(const LandedGrid& grid, const Scene& scene, const Placement& placement,
                          const gl::RenderTarget& target, glm::vec3 weight, bool clear, bool count, bool on_cpu) {
  if (on_cpu) return draw_deposited(grid.vertices, grid.triangles, scene, placement, target, weight, clear, count);
  on_the_gl(clear);
  if (grid.triangles.empty()) {  // no light through the solid: GL allows no empty storage
    const TriangleCounts zero{};
    if (count) {
      glNamedBufferSubData(counters_.id(), 0, sizeof zero, &zero);
      counted_on_cpu_ = false;
    }
    bind(target, clear);
    return;
  }
  // A new grid each frame: fresh buffers (immutable storage), one interleaved.
  landed_vertices_ = gl::Buffer();
  landed_indices_ = gl::Buffer();
  landed_vao_ = gl::VertexArray();
  glNamedBufferStorage(landed_vertices_.id(), static_cast<GLsizeiptr>(grid.vertices.size() * sizeof(LandedVertex)),
                       grid.vertices.data(), 0);
  glNamedBufferStorage(landed_indices_.id(), static_cast<GLsizeiptr>(grid.triangles.size() * sizeof(glm::uvec3)),
                       grid.triangles.data(), 0);
  const GLuint vao = landed_vao_.id();
  glVertexArrayVertexBuffer(vao, 0, landed_vertices_.id(), 0, sizeof(LandedVertex));
  describe(vao, {{2, offsetof(LandedVertex, screen)},        {2, offsetof(LandedVertex, plane)},
                 {3, offsetof(LandedVertex, footprint)},     {1, offsetof(LandedVertex, transmittance)},
                 {1, offsetof(LandedVertex, valid)},         {3, offsetof(LandedVertex, tint)},
                 {1, offsetof(LandedVertex, share)},         {1, offsetof(LandedVertex, surface)}});
  glVertexArrayElementBuffer(vao, landed_indices_.id());
  gl::check_errors("landed grid upload");
  deposit(landed_program_, vao, static_cast<GLsizei>(grid.triangles.size() * 3), scene, placement, target, weight,
          clear, count, false);
}

void RayPass::deposit(const gl::Program& p, GLuint vao, GLsizei indices, const Scene& scene,
                      const Placement& placement, const gl::RenderTarget& target, glm::vec3 weight, bool clear,
                      bool count, bool clear_tint) {
  p.set("uWeight", weight);
  p.set("uCount", count);
  p.set("uPointLight", scene.light.type == LightType::point);
  p.set("uLightDir", glm::vec3(scene.light.direction));
  p.set("uLightPos", glm::vec3(scene.light.position));
  p.set("uReferenceDistance2", static_cast<float>(reference_distance2(scene, placement)));
  p.set("uReportIntensity", scene.render.intensity == IntensityMode::report);
  const int width = target.texture.width(), height = target.texture.height();
  p.set("uResolution", glm::vec2(width, height));
  const auto surfaces = receiving_surfaces(scene);
  const auto tiles = atlas_layout(width, height, surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    // Both stages read the half sizes (the vertex stage bounds the rectangles).
    p.set(element("uSurfaceHalf", i).c_str(), glm::vec2(surfaces[i].width / 2, surfaces[i].height / 2));
    p.set(element("uTileOrigin", i).c_str(), glm::vec2(tiles[i].x, height - tiles[i].y - tiles[i].height));
    p.set(element("uTileSize", i).c_str(), glm::vec2(tiles[i].width, tiles[i].height));
  }

  const TriangleCounts zero{};
  if (count) {
    glNamedBufferSubData(counters_.id(), 0, sizeof zero, &zero);
    counted_on_cpu_ = false;
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counters_.id());

  bind(target, clear);
  add_up();
  p.use();
  glBindVertexArray(vao);
  // A clear face reads the tint attribute's constant value: pass everything.
  if (clear_tint) glVertexAttrib3f(2, 1.0f, 1.0f, 1.0f);
  glDrawElements(GL_TRIANGLES, indices, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  gl::check_errors("caustic pass");
}

TriangleCounts RayPass::counts() const {
  if (counted_on_cpu_) return cpu_counts_;
  TriangleCounts c;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(counters_.id(), 0, sizeof c, &c);
  return c;
}

}  // namespace caustic
