// SPDX-License-Identifier: LGPL-2.1-or-later
// shaders/optics.glsl against src/optics: the same formulas exist once in
// GLSL and once in C++; a compute shader evaluates the GLSL ones on random
// cases and this holds them to the C++ ones.
#include "gl_objects.hpp"
#include "gl_test_support.hpp"

#include "caustic/optics.hpp"

#include <fstream>
#include <random>
#include <sstream>

using namespace caustic;

namespace {

struct Case {  // mirrors tests/glsl/optics_twin.comp
  glm::vec4 incident, normal, indices, light, vertex, tri_a, tri_b, tri_c;
  glm::vec4 refracted, results, entry, pad;
};

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

class GlslTwin : public caustic::testing::GlTest {};

TEST_F(GlslTwin, RefractionFresnelEntryAndSolidAngleAgreeWithCpp) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Case> cases(4096);
  for (auto& c : cases) {
    const float glass = 2.5f + 1.5f * u(rng);  // 1 .. 4
    const bool leaving = u(rng) > 0;
    c.incident = glm::vec4(glm::normalize(glm::vec3(u(rng), u(rng), -1.2f + 0.8f * u(rng))), 0);
    c.normal = glm::vec4(glm::normalize(glm::vec3(0.5f * u(rng), 0.5f * u(rng), u(rng) > 0 ? 1.0f : -1.0f)), 0);
    c.indices = leaving ? glm::vec4(glass, 1, glass, 0) : glm::vec4(1, glass, glass, 0);
    c.light = glm::vec4(5 * u(rng), 5 * u(rng), 12 + 10 * u(rng), 0);
    c.vertex = glm::vec4(5 * u(rng), 5 * u(rng), -2.1f + 2 * u(rng), 0);
    c.tri_a = glm::vec4(u(rng), u(rng), -3, 0);
    c.tri_b = c.tri_a + glm::vec4(0.6f + 0.5f * u(rng), 0.3f * u(rng), 0.1f * u(rng), 0);
    c.tri_c = c.tri_a + glm::vec4(0.3f * u(rng), 0.6f + 0.5f * u(rng), 0.1f * u(rng), 0);
  }
  // Equal indices are no interface, grazing included: there the formulas
  // are 0 / 0, and within rounding of it they reflect everything.
  const std::size_t equal = cases.size() - 3;
  for (std::size_t k = equal; k < cases.size(); ++k) {
    const float z = k == equal ? 0.0f : k == equal + 1 ? 1e-6f : -1e-4f;
    cases[k].incident = glm::vec4(glm::normalize(glm::vec3(1, 0, z)), 0);
    cases[k].normal = glm::vec4(0, 0, 1, 0);
    cases[k].indices = glm::vec4(1, 1, 1, 0);
  }
  gl::Program kernel({{GL_COMPUTE_SHADER, {"optics.glsl"}, read_file(CAUSTIC_TEST_GLSL "/optics_twin.comp")}});
  gl::Buffer buffer;
  glNamedBufferStorage(buffer.id(), static_cast<GLsizeiptr>(cases.size() * sizeof(Case)), cases.data(),
                       GL_DYNAMIC_STORAGE_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffer.id());
  kernel.use();
  glDispatchCompute(static_cast<GLuint>(cases.size() / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<Case> out(cases.size());
  glGetNamedBufferSubData(buffer.id(), 0, static_cast<GLsizeiptr>(out.size() * sizeof(Case)), out.data());
  gl::check_errors("compute kernel");

  int tir = 0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const Case& c = out[k];
    const optics::Vec3 i(c.incident);
    const optics::Vec3 n = optics::face_against(optics::Vec3(c.normal), i);
    const double from = c.indices.x, to = c.indices.y;
    const auto t = optics::refract(i, n, from / to);
    ASSERT_EQ(c.results.x > 0.5f, t.has_value()) << "case " << k;
    if (t) {
      EXPECT_NEAR(glm::length(glm::dvec3(c.refracted) - t->direction), 0.0, 1e-5) << "case " << k;
      EXPECT_NEAR(c.results.y, optics::fresnel_transmittance(t->cos_i, from, to), 5e-5) << "case " << k;
    } else {
      ++tir;
      EXPECT_EQ(c.results.y, 0.0f) << "case " << k;
    }
    const double omega = optics::solid_angle(optics::Vec3(c.light), optics::Vec3(c.tri_a), optics::Vec3(c.tri_b),
                                             optics::Vec3(c.tri_c));
    EXPECT_NEAR(c.results.z, omega, 1e-4 * omega + 1e-7) << "case " << k;
    const auto entry = optics::point_light_entry(optics::Vec3(c.light), optics::Vec3(c.vertex), {{0, 0, 1}, 0.0},
                                                 c.indices.z);
    ASSERT_TRUE(entry);
    EXPECT_NEAR(glm::length(glm::dvec3(c.entry) - *entry), 0.0, 2e-4) << "case " << k;
  }
  EXPECT_GT(tir, 100);  // the random set reaches total internal reflection
  for (std::size_t k = equal; k < out.size(); ++k) {
    EXPECT_EQ(out[k].results.x, 1.0f) << "case " << k;
    EXPECT_EQ(out[k].results.y, 1.0f) << "case " << k << ": equal indices transmit everything";
    EXPECT_NEAR(glm::length(glm::vec3(out[k].refracted) - glm::vec3(out[k].incident)), 0.0f, 1e-6f) << "case " << k;
  }
}
