// SPDX-License-Identifier: LGPL-2.1-or-later
// The two GPU passes behind Engine: the caustic ray pass into a float
// target, and post-processing (bloom, tone mapping) into an 8-bit target.
#pragma once

#include "caustic/engine.hpp"
#include "caustic/exposure.hpp"
#include "caustic/light_grid.hpp"
#include "gl_objects.hpp"
#include "cpu_setup.hpp"

namespace caustic {

class RayPass {
 public:
  RayPass();
  void upload(const Mesh& mesh);
  /// Adds every triangle's relative irradiance, refracted with index `ior`
  /// and times `weight` and the triangle's tint, into `target` (cleared first when `clear`): one
  /// wavelength of a spectral frame, or (1, 1, 1) and object.ior for a
  /// monochrome one. `count`: this pass's triangles are what counts() reports.
  void draw(const Scene& scene, const Placement& placement, const gl::RenderTarget& target, double ior,
            glm::vec3 weight, bool clear, bool count = true);
  /// The same picture with the rays traced and the triangles set up on the
  /// CPU (cpu_setup.hpp) from `mesh`, the one last uploaded.
  void draw_on_cpu(const Scene& scene, const Placement& placement, const Mesh& mesh, const gl::RenderTarget& target,
                   double ior, glm::vec3 weight, bool clear, bool count = true);
  /// The same deposit for rays a solid's multipass tracer already followed
  /// (caustic/light_grid.hpp): their tints and Fresnel weights ride along.
  void draw_landed(const LandedGrid& grid, const Scene& scene, const Placement& placement,
                   const gl::RenderTarget& target, glm::vec3 weight, bool clear, bool count = true,
                   bool on_cpu = false);
  TriangleCounts counts() const;
  /// After the passes of a frame: what the CPU's passes added up becomes
  /// the target's whole content (whole_image()).
  void settle();
  /// The target's whole content as the CPU deposited it (rows from the
  /// bottom, whole_channels() floats a pixel) once settled, or null when the
  /// last draw left it elsewhere. It reaches the target's texture only at
  /// upload_whole_image(): a frame post-processed on the CPU (cpu_post.hpp)
  /// never needs it there.
  const std::vector<float>* whole_image() const { return whole_image_; }
  /// 1 for a grey target; 4 (RGB and an unused fourth) for a colour one.
  int whole_channels() const { return raster_.channels() == 1 ? 1 : 4; }
  /// Copies the CPU's whole image (grey or colour) into its target's
  /// texture, once, for a reader on the GL.
  void upload_whole_image();
  /// The target is gone (resized): the image is no longer its content.
  void forget_whole_image() {
    whole_image_ = nullptr;
    raster_pending_ = false;
  }

 private:
  // The splat both methods share: caustic.geom and caustic.frag's uniforms, then the draw.
  void deposit(const gl::Program& program, GLuint vao, GLsizei indices, const Scene& scene,
               const Placement& placement, const gl::RenderTarget& target, glm::vec3 weight, bool clear, bool count,
               bool clear_tint);
  // The triangles set up on the CPU and deposited into the raster, which
  // sums a frame's passes (wavelengths) as one image: every pass of a frame
  // on the CPU, the first with `clear`.
  void draw_deposited(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles,
                      const Scene& scene, const Placement& placement, const gl::RenderTarget& target,
                      glm::vec3 weight, bool clear, bool count, const PartedRays* parted = nullptr);

  // A pass on the GL: what the CPU left is uploaded first when the pass adds to it.
  void on_the_gl(bool clear);

  gl::Program program_, landed_program_;
  gl::VertexArray vao_, landed_vao_;
  gl::Buffer positions_, normals_, colours_, indices_, counters_;
  gl::Buffer landed_vertices_, landed_indices_;
  CoverageRaster raster_;  // kept: one allocation for every frame
  GLuint raster_texture_ = 0;    // the texture whose passes raster_ sums
  bool raster_pending_ = false;  // ... not yet settled
  TriangleCounts cpu_counts_;
  const std::vector<float>* whole_image_ = nullptr;  // raster_'s image, while it is the target's content
  GLuint whole_texture_ = 0;                         // ... of this texture, which has it once uploaded
  bool whole_uploaded_ = false;
  bool counted_on_cpu_ = false;  // the last counting pass set up its triangles on the CPU
  GLsizei index_count_ = 0;
  bool tinted_ = false;
};

class PostPass {
 public:
  PostPass();
  /// The local operator's base (when post.tone_map is local), then, when
  /// `meter`, the histogram of the lit pixels as the tone map will see them
  /// (exposure.hpp); otherwise an empty histogram.
  exposure::Histogram prepare(const PostParams& post, const gl::Texture& hdr, bool meter);
  /// Bright pass and blur at reduced resolution, then tone mapping into `ldr`
  /// with `exposure` (the base of the last prepare() when local). The glow
  /// stops at the edges of the atlas's `tiles` (glow.hpp).
  void run(const PostParams& post, const gl::Texture& hdr, const gl::RenderTarget& ldr, double exposure,
           const std::vector<AtlasTile>& tiles);

 private:
  gl::Program bright_, blur_, tonemap_, base_down_, base_bilateral_, meter_;
  gl::VertexArray empty_vao_;
  gl::RenderTarget bloom_a_, bloom_b_, blocks_, base_, meter_target_;
};

}  // namespace caustic
