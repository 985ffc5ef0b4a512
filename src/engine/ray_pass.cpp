// SPDX-License-Identifier: LGPL-2.1-or-later
#include "passes.hpp"

#include "caustic/vertex_rays.hpp"

#include <cmath>

namespace caustic {

RayPass::RayPass()
    : program_({{GL_VERTEX_SHADER, {"optics.glsl", "caustic.vert"}},
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
  const auto& p = program_;
  const auto& screen = scene.screen;
  const bool point = scene.light.type == LightType::point;
  const bool flat_first = flat_face_first(scene, placement);
  // Relative irradiance of a point light is normalised to what it delivers
  // at the object's centre (docs/physics.md ch. 1).
  const double reference_distance = glm::length(scene.light.position - placement.center);

  p.set("uModel", glm::mat4(placement.model));
  p.set("uRotation", glm::mat3(placement.rotation));
  p.set("uFlatNormal", glm::vec3(placement.flat_normal));
  p.set("uFlatOffset", static_cast<float>(placement.flat_offset));
  p.set("uIor", static_cast<float>(ior));
  p.set("uWeight", weight);
  p.set("uCount", count);
  p.set("uReflective", scene.object.material == Material::reflective);
  p.set("uFlatFirst", flat_first);
  p.set("uPointLight", point);
  p.set("uExactPointModel", scene.light.point_model == PointModel::exact);
  p.set("uLightDir", glm::vec3(scene.light.direction));
  p.set("uLightPos", glm::vec3(scene.light.position));
  p.set("uReferenceDistance2", static_cast<float>(reference_distance * reference_distance));
  p.set("uFresnel", scene.render.fresnel);
  p.set("uScreenCenter", glm::vec3(screen.center));
  p.set("uScreenNormal", glm::vec3(screen.normal));
  p.set("uScreenRight", glm::vec3(screen_right(screen)));
  p.set("uScreenUp", glm::vec3(screen.up));
  p.set("uReportPlaneDistance", static_cast<float>(scene.render.report_plane_distance));
  p.set("uReportIntensity", scene.render.intensity == IntensityMode::report);
  p.set("uHalfSize", glm::vec2(screen.width / 2, screen.height / 2));
  p.set("uResolution", glm::vec2(target.texture.width(), target.texture.height()));

  const TriangleCounts zero{};
  if (count) glNamedBufferSubData(counters_.id(), 0, sizeof zero, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counters_.id());

  target.bind();
  const float black[4] = {0, 0, 0, 0};
  if (clear) glClearNamedFramebufferfv(target.framebuffer.id(), GL_COLOR, 0, black);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  program_.use();
  glBindVertexArray(vao_.id());
  // A clear face reads the tint attribute's constant value: pass everything.
  if (!tinted_) glVertexAttrib3f(2, 1.0f, 1.0f, 1.0f);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  gl::check_errors("caustic pass");
}

TriangleCounts RayPass::counts() const {
  TriangleCounts c;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(counters_.id(), 0, sizeof c, &c);
  return c;
}

}  // namespace caustic
