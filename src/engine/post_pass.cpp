// SPDX-License-Identifier: LGPL-2.1-or-later
#include "passes.hpp"

#include "glow.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace caustic {
namespace {

// glow_cuts.glsl's uniforms.
void set_cuts(const gl::Program& program, const GlowCuts& cuts) {
  for (const auto& [axis, values] : {std::pair{'X', &cuts.x}, std::pair{'Y', &cuts.y}}) {
    if (values->size() > kMaxGlowCuts) throw EngineError("more tile edges than glow_cuts.glsl takes");
    program.set((std::string("uCutCount") + axis).c_str(), static_cast<int>(values->size()));
    for (std::size_t k = 0; k < values->size(); ++k)
      program.set((std::string("uCuts") + axis + "[" + std::to_string(k) + "]").c_str(), (*values)[k]);
  }
}

float local_strength(const PostParams& post) {
  return post.tone_map == ToneMap::local ? static_cast<float>(post.local_strength) : 0.0f;
}

}  // namespace

PostPass::PostPass()
    : bright_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"bright.frag"}}}),
      blur_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"glow_cuts.glsl", "blur.frag"}}}),
      tonemap_({{GL_VERTEX_SHADER, {"fullscreen.vert"}},
                {GL_FRAGMENT_SHADER, {"local.glsl", "glow_cuts.glsl", "tonemap.frag"}}}),
      base_down_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"local.glsl", "base_down.frag"}}}),
      base_bilateral_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"base_bilateral.frag"}}}),
      meter_({{GL_VERTEX_SHADER, {"fullscreen.vert"}}, {GL_FRAGMENT_SHADER, {"local.glsl", "meter.frag"}}}) {}

exposure::Histogram PostPass::prepare(const PostParams& post, const gl::Texture& hdr, bool meter) {
  glDisable(GL_BLEND);
  glBindVertexArray(empty_vao_.id());
  const float strength = local_strength(post);
  if (strength > 0) {
    const int bw = std::max(1, (hdr.width() + 7) / 8), bh = std::max(1, (hdr.height() + 7) / 8);
    if (blocks_.texture.width() != bw || blocks_.texture.height() != bh) {
      blocks_ = gl::RenderTarget(GL_RG16F, bw, bh);
      base_ = gl::RenderTarget(GL_R16F, bw, bh, GL_LINEAR);
    }
    blocks_.bind();
    base_down_.use();
    glBindTextureUnit(0, hdr.id());
    base_down_.set("uHdr", 0);
    base_down_.set("uLog2Lit", exposure::kLog2Lit);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    base_.bind();
    base_bilateral_.use();
    glBindTextureUnit(0, blocks_.texture.id());
    base_bilateral_.set("uBlocks", 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  exposure::Histogram histogram{};
  if (meter) {
    const int k = exposure::meter_stride(hdr.width(), hdr.height());
    const int mw = (hdr.width() + k - 1) / k, mh = (hdr.height() + k - 1) / k;
    if (meter_target_.texture.width() != mw || meter_target_.texture.height() != mh)
      meter_target_ = gl::RenderTarget(GL_R32F, mw, mh);
    meter_target_.bind();
    meter_.use();
    glBindTextureUnit(0, hdr.id());
    glBindTextureUnit(2, base_.texture.id());
    meter_.set("uHdr", 0);
    meter_.set("uBase", 2);
    meter_.set("uLocalStrength", strength);
    meter_.set("uStride", k);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    std::vector<float> values(static_cast<std::size_t>(mw) * mh);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(meter_target_.texture.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(values.size() * sizeof(float)),
                      values.data());
    for (const float v : values) exposure::count(histogram, v);
  }
  glBindVertexArray(0);
  gl::check_errors("exposure metering");
  return histogram;
}

void PostPass::run(const PostParams& post, const gl::Texture& hdr, const gl::RenderTarget& ldr, double exposure,
                   const std::vector<AtlasTile>& tiles) {
  glDisable(GL_BLEND);
  glBindVertexArray(empty_vao_.id());
  const bool bloom = post.bloom_strength > 0 && post.bloom_radius > 0;
  const int shrink = glow_shrink(post.bloom_radius);
  if (bloom) {
    // The glow is computed on a smaller image: a full-resolution float blur
    // costs as much as the caustic itself on a CPU renderer, and a glow needs
    // no fine detail. Half, quarter or eighth size, keeping the Gaussian at
    // least 2 texels wide so that the bilinear upsampling in the tone map
    // stays smooth; each step down makes the blur ~8x cheaper.
    const int bw = std::max(1, hdr.width() / shrink), bh = std::max(1, hdr.height() / shrink);
    // A colour frame glows in colour; a grey one keeps one channel, a
    // quarter of the blur's memory traffic, in full floats: a software
    // renderer converts half floats at every fetch, which cost it more
    // than the traffic saved (the blur took 1.7 times as long).
    const GLenum format = hdr.format() == GL_R32F ? GL_R32F : GL_RGBA16F;
    if (bloom_a_.texture.width() != bw || bloom_a_.texture.height() != bh || bloom_a_.texture.format() != format) {
      bloom_a_ = gl::RenderTarget(format, bw, bh, GL_LINEAR);
      bloom_b_ = gl::RenderTarget(format, bw, bh, GL_LINEAR);
    }
    bloom_a_.bind();
    bright_.use();
    bright_.set("uThreshold", static_cast<float>(post.bloom_threshold));
    bright_.set("uShrink", shrink);
    glBindTextureUnit(0, hdr.id());
    bright_.set("uHdr", 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    const std::vector<double> weights = glow_weights(post.bloom_radius, shrink);
    const int radius = static_cast<int>(weights.size()) - 1;
    const GlowCuts cuts = glow_cuts(tiles, hdr.height(), shrink, bw, bh);
    set_cuts(blur_, cuts);
    set_cuts(tonemap_, cuts);
    blur_.use();
    blur_.set("uSource", 0);
    blur_.set("uRadius", radius);
    for (int k = 0; k <= radius; ++k)
      blur_.set(("uWeights[" + std::to_string(k) + "]").c_str(), static_cast<float>(weights[k]));
    bloom_b_.bind();
    glBindTextureUnit(0, bloom_a_.texture.id());
    blur_.set("uStep", glm::ivec2(1, 0));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    bloom_a_.bind();
    glBindTextureUnit(0, bloom_b_.texture.id());
    blur_.set("uStep", glm::ivec2(0, 1));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  ldr.bind();
  tonemap_.use();
  glBindTextureUnit(0, hdr.id());
  glBindTextureUnit(1, bloom ? bloom_a_.texture.id() : hdr.id());
  glBindTextureUnit(2, base_.texture.id());
  tonemap_.set("uHdr", 0);
  tonemap_.set("uBloom", 1);
  tonemap_.set("uBase", 2);
  tonemap_.set("uLocalStrength", local_strength(post));
  tonemap_.set("uBloomStrength", bloom ? static_cast<float>(post.bloom_strength) : 0.0f);
  tonemap_.set("uShrink", shrink);
  tonemap_.set("uExposure", static_cast<float>(exposure));
  tonemap_.set("uGamma", static_cast<float>(post.gamma));
  tonemap_.set("uOutputSize", glm::vec2(ldr.texture.width(), ldr.texture.height()));
  tonemap_.set("uGrey", hdr.format() == GL_R32F);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  gl::check_errors("post-processing");
}

}  // namespace caustic
