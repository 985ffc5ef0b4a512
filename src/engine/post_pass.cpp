#include "passes.hpp"

#include <algorithm>
#include <cmath>

namespace caustic {

PostPass::PostPass()
    : bright_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"bright.frag"}}}),
      blur_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"blur.frag"}}}),
      tonemap_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"tonemap.frag"}}}) {}

void PostPass::run(const PostParams& post, const gl::Texture& hdr, const gl::RenderTarget& ldr) {
  glDisable(GL_BLEND);
  glBindVertexArray(empty_vao_.id());
  const bool bloom = post.bloom_strength > 0 && post.bloom_radius > 0;
  if (bloom) {
    // Bloom at half resolution: a full-resolution float blur costs as much as
    // the caustic itself on a CPU renderer, and a glow needs no fine detail.
    const int hw = std::max(1, hdr.width() / 2), hh = std::max(1, hdr.height() / 2);
    if (half_a_.texture.width() != hw || half_a_.texture.height() != hh) {
      half_a_ = gl::RenderTarget(GL_R16F, hw, hh, GL_LINEAR);
      half_b_ = gl::RenderTarget(GL_R16F, hw, hh, GL_LINEAR);
    }
    half_a_.bind();
    bright_.use();
    bright_.set("uThreshold", static_cast<float>(post.bloom_threshold));
    glBindTextureUnit(0, hdr.id());
    bright_.set("uHdr", 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    const float sigma = static_cast<float>(post.bloom_radius / 2.0);  // in half-resolution texels
    blur_.use();
    blur_.set("uSource", 0);
    blur_.set("uSigma", sigma);
    blur_.set("uRadius", std::clamp(static_cast<int>(std::ceil(3.0f * sigma)), 1, 48));
    half_b_.bind();
    glBindTextureUnit(0, half_a_.texture.id());
    blur_.set("uStep", glm::ivec2(1, 0));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    half_a_.bind();
    glBindTextureUnit(0, half_b_.texture.id());
    blur_.set("uStep", glm::ivec2(0, 1));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  ldr.bind();
  tonemap_.use();
  glBindTextureUnit(0, hdr.id());
  glBindTextureUnit(1, bloom ? half_a_.texture.id() : hdr.id());
  tonemap_.set("uHdr", 0);
  tonemap_.set("uBloom", 1);
  tonemap_.set("uBloomStrength", bloom ? static_cast<float>(post.bloom_strength) : 0.0f);
  tonemap_.set("uExposure", static_cast<float>(post.exposure));
  tonemap_.set("uGamma", static_cast<float>(post.gamma));
  tonemap_.set("uOutputSize", glm::vec2(ldr.texture.width(), ldr.texture.height()));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  gl::check_errors("post-processing");
}

}  // namespace caustic
