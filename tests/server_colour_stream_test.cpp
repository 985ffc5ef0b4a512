// SPDX-License-Identifier: LGPL-2.1-or-later
// The stream carries colour: a spectral scene's video, decoded by a WebRTC
// peer, shows the hues of the session's own picture (frame.png) within what
// 4:2:0 chroma and the codec's quantisation allow.
#include "caustic/image_io.hpp"
#include "server_process.hpp"
#include "webrtc_peer.hpp"

#include <glib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

using caustic::testing::bearer;
using caustic::testing::http;
using caustic::testing::ServerProcess;
using caustic::testing::WebRtcPeer;
using nlohmann::json;

namespace {

// Hue in degrees of an RGB colour (components 0..1), and its saturation.
void hue_saturation(double r, double g, double b, double* hue, double* saturation) {
  const double hi = std::max({r, g, b}), lo = std::min({r, g, b}), c = hi - lo;
  *saturation = hi > 0 ? c / hi : 0;
  double h = 0;
  if (c > 0) h = hi == r ? std::fmod((g - b) / c + 6, 6.0) : hi == g ? (b - r) / c + 2 : (r - g) / c + 4;
  *hue = 60 * h;
}

// An image the server answered, read through a file named for its format.
caustic::RgbHdrImage read_body(const std::string& body, const std::string& extension) {
  const auto file = std::filesystem::temp_directory_path() / ("colour-stream-" + std::to_string(getpid()) + extension);
  if (std::FILE* f = std::fopen(file.c_str(), "wb")) {
    std::fwrite(body.data(), 1, body.size(), f);
    std::fclose(f);
  }
  caustic::RgbHdrImage image = caustic::read_rgb_image(file);
  std::filesystem::remove(file);
  return image;
}

}  // namespace

TEST(ColourStream, ThePrismsSpectrumArrivesInColour) {
  gst_init(nullptr, nullptr);
  ServerProcess server({"--width", "320", "--height", "240", "--framerate", "30"});
  const json s = http("POST", server.url() + "/api/v1/sessions", json{{"scene", "prism"}, {"codec", "vp8"}}.dump()).json();
  ASSERT_TRUE(s.contains("signal_url")) << s.dump();
  std::string ws = server.url() + s["signal_url"].get<std::string>();
  ws.replace(0, 4, "ws");
  WebRtcPeer peer("vp8", ws);
  ASSERT_TRUE(peer.wait_for_frames(10, 60.0)) << "decoded " << peer.decoded() << "; " << peer.error();
  peer.wait_for_frames(1000, 1.5);  // the full-quality frame after any previews
  const auto video = peer.last_picture();

  const auto png = http("GET", server.url() + s["url"].get<std::string>() + "/frame.png", "", "", bearer(s));
  ASSERT_EQ(png.status, 200u);
  const caustic::RgbHdrImage picture = read_body(png.body, ".png");
  // frame.exr carries the colour too: R, G, B channels, not one Y.
  const auto exr = http("GET", server.url() + s["url"].get<std::string>() + "/frame.exr", "", "", bearer(s));
  ASSERT_EQ(exr.status, 200u);
  const caustic::RgbHdrImage hdr = read_body(exr.body, ".exr");
  bool coloured = false;
  for (std::size_t i = 0; i < hdr.pixels.size(); i += 3) coloured = coloured || hdr.pixels[i] > 2 * hdr.pixels[i + 2] + 0.01f;
  EXPECT_TRUE(coloured) << "frame.exr of a spectral scene is grey";
  ASSERT_EQ(picture.width, peer.width());
  ASSERT_EQ(picture.height, peer.height());

  // Bright, saturated pixels of the picture whose row neighbours share their
  // hue (chroma is subsampled 2x2: an edge between stripes smears).
  int compared = 0, reds = 0, blues = 0;
  double total_difference = 0;
  const int w = picture.width;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 2; x < w - 2; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      const float* p = &picture.pixels[3 * i];
      double hue, sat;
      hue_saturation(p[0], p[1], p[2], &hue, &sat);
      if (std::max({p[0], p[1], p[2]}) < 0.4f || sat < 0.6) continue;
      bool uniform = true;
      for (int dx : {-2, 2}) {
        const float* q = &picture.pixels[3 * (i + dx)];
        double h2, s2;
        hue_saturation(q[0], q[1], q[2], &h2, &s2);
        uniform = uniform && std::abs(std::remainder(h2 - hue, 360.0)) < 10;
      }
      if (!uniform) continue;
      const guint8* v = &video[4 * i];
      double video_hue, video_sat;
      hue_saturation(v[0] / 255.0, v[1] / 255.0, v[2] / 255.0, &video_hue, &video_sat);
      total_difference += std::abs(std::remainder(video_hue - hue, 360.0));
      ++compared;
      reds += hue < 30 || hue > 330;
      blues += hue > 200 && hue < 280;
    }
  ASSERT_GT(compared, 200);
  EXPECT_GT(reds, 20) << "the spectrum's red end";
  EXPECT_GT(blues, 20) << "the spectrum's blue end";
  const double mean = total_difference / compared;
  std::printf("prism stream: %d pixels compared, mean hue difference %.1f degrees\n", compared, mean);
  EXPECT_LT(mean, 15.0);
}
