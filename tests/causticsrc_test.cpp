// SPDX-License-Identifier: LGPL-2.1-or-later
// causticsrc in a pipeline: frames at the configured size and rate, a patch
// visible in the next frames with its version, each frame taking the newest
// picture when it is due, and no rendering while the parameters stand still.
#include "causticsrc_fixture.hpp"

#include <gst/app/gstappsink.h>
#include <gst/video/video.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include "caustic/engine.hpp"
#include "caustic/gl_context.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace caustic::testing;

TEST_F(CausticSrc, DeliversFramesAtTheConfiguredSizeAndRate) {
  start("causticsrc name=src scene=" + scene("lens") + " width=96 height=64 framerate=20/1 ! appsink name=sink");
  std::vector<Frame> frames;
  for (int i = 0; i < 10; ++i) {
    GstSample* s = pull();
    ASSERT_NE(s, nullptr) << "no frame " << i;
    frames.push_back(take(s));
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].width, 96);
    EXPECT_EQ(frames[i].height, 64);
    EXPECT_EQ(frames[i].pixels.size(), 96u * 64u * 4u);
    // Running times: the first frame is stamped when it became ready, then one every 50 ms.
    EXPECT_EQ(frames[i].pts - frames[0].pts, i * GST_SECOND / 20) << i;
    EXPECT_EQ(frames[i].version, 1u);
  }
  EXPECT_EQ(renders(), 1u);  // ten frames, one caustic pass
}

TEST_F(CausticSrc, PatchShowsInTheNextFramesWithItsVersion) {
  start("causticsrc name=src scene=" + scene("wavy") +
        " width=64 height=64 framerate=30/1 progressive=false ! appsink name=sink");
  const Frame first = take(pull());
  auto params = caustic::gst::param_store(src_);
  ASSERT_TRUE(params);
  const std::uint64_t version = params->apply_patch({{"light", {{"direction", {0.15, 0.05, -1}}}}});
  EXPECT_EQ(version, 2u);
  // The render thread draws it while frames keep going out: it shows a few
  // frames later (how many depends on the machine's load; 300 is 10 s).
  Frame later = take(pull());
  for (int i = 0; i < 300 && later.version != version; ++i) later = take(pull());
  EXPECT_EQ(later.version, version);
  EXPECT_NE(later.pixels, first.pixels);
  EXPECT_EQ(renders(), 2u);
}

TEST_F(CausticSrc, EachFrameTakesThePictureNewestWhenItIsDue) {
  // A patch made 30 ms after a frame left (when the element has already
  // been asked for the next one) and drawn before the next frame is due
  // must be in that next frame, not a picture taken when the previous one
  // left. Whether the drawing makes it in time depends on the machine's
  // load, so each try checks only when it did (picture-version says when).
  start("causticsrc name=src scene=" + scene("slab") +
        " width=64 height=64 framerate=2/1 ! appsink name=sink sync=false");
  auto params = caustic::gst::param_store(src_);
  ASSERT_TRUE(params);
  ASSERT_NE(running_time(), GST_CLOCK_TIME_NONE) << "no clock";
  int checked = 0;
  for (int k = 0; k < 60 && checked < 3; ++k) {
    const Frame left = take(pull());
    g_usleep(30'000);
    const GstClockTime due = left.pts + GST_SECOND / 2;
    const std::uint64_t version = params->apply_patch({{"light", {{"direction", {0.01 * (k + 1), 0.0, -1.0}}}}});
    guint64 drawn = 0;
    while (running_time() < due) {
      g_object_get(src_, "picture-version", &drawn, nullptr);
      if (drawn >= version) break;
      g_usleep(1000);
    }
    // Ready with a margin before the frame was due: that frame must show it.
    const bool in_time = drawn >= version && running_time() + 20 * GST_MSECOND < due;
    const Frame next = take(pull());
    if (!in_time) continue;
    EXPECT_EQ(next.version, version) << k;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

TEST_F(CausticSrc, NoRenderWhileTheParametersStandStill) {
  start("causticsrc name=src scene=" + scene("slab") + " width=32 height=32 framerate=60/1 ! appsink name=sink");
  for (int i = 0; i < 12; ++i) gst_sample_unref(pull());
  EXPECT_EQ(renders(), 1u);
  caustic::gst::param_store(src_)->apply_patch({{"post", {{"exposure", 2.0}}}});
  for (int i = 0; i < 4; ++i) gst_sample_unref(pull());
  EXPECT_EQ(renders(), 1u);  // post-processing only: no new caustic pass
}

TEST_F(CausticSrc, PreviewsWhilePatchesArriveThenTheFullFrame) {
  start("causticsrc name=src scene=" + scene("lens") +
        " width=128 height=128 framerate=30/1 settle-ms=150 ! appsink name=sink sync=true");
  auto params = caustic::gst::param_store(src_);
  ASSERT_TRUE(params);
  std::vector<Frame> frames{take(pull())};
  EXPECT_EQ(frames[0].level, 0u);  // the first picture is a full one
  const std::uint64_t first_patch = params->version() + 1;
  // A light drag: one patch per frame interval (30 Hz) for 60 frames. How
  // many of its frames show previews depends on how fast this machine
  // draws (a benchmark figure); which pictures are previews does not.
  using Clock = std::chrono::steady_clock;
  int pauses = 0;  // gaps between patches long enough to count as stillness
  Clock::time_point last_patch{};
  for (int i = 0; i < 60; ++i) {
    params->apply_patch({{"light", {{"direction", {0.002 * i, 0.0, -1.0}}}}});
    const auto published = params->snapshot().published;
    if (i > 0 && published - last_patch >= std::chrono::milliseconds(150)) ++pauses;
    last_patch = published;
    GstSample* s = pull();
    ASSERT_NE(s, nullptr) << "frame " << i;
    frames.push_back(take(s));
  }
  const std::uint64_t last = params->version();
  // Then stillness: the full frame of the last parameters follows.
  Frame settled{};
  const auto give_up = Clock::now() + std::chrono::seconds(30);
  while (Clock::now() < give_up && !(settled.version == last && settled.level == 0)) {
    frames.push_back(take(pull()));
    settled = frames.back();
  }
  ASSERT_EQ(settled.version, last);
  ASSERT_EQ(settled.level, 0u);
  // Every frame came, one frame interval apart: no gaps, no repeats.
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].pts - frames[i - 1].pts, gst_util_uint64_scale(i, GST_SECOND, 30) -
                                                     gst_util_uint64_scale(i - 1, GST_SECOND, 30)) << i;
  // The pictures drawn for the drag's versions: previews, except the first
  // change (a click until proven a drag), any change after a pause in the
  // patches, and the settled last one.
  int drawn_full = 0, drawn_previews = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const bool new_picture = frames[i].version != frames[i - 1].version || frames[i].level != frames[i - 1].level;
    if (!new_picture || frames[i].version < first_patch || (frames[i].version == last && frames[i].level == 0)) continue;
    (frames[i].level == 0 ? drawn_full : drawn_previews) += 1;
  }
  EXPECT_GE(drawn_previews, 1) << "the drag was never shown as a preview";
  EXPECT_LE(drawn_full, 1 + pauses) << "full pictures drawn while the patches kept coming";

  // The settled frame is exactly a full-quality render of the same parameters.
  caustic::GlContext context(caustic::egl_platform_from_environment());
  caustic::Engine engine;
  caustic::Scene s = params->snapshot().scene;
  s.render.width = s.render.height = 128;
  engine.set_scene(s, std::make_shared<const caustic::Mesh>(caustic::load_obj(s.mesh_path())));
  engine.render();
  const caustic::Rgba8Image full = engine.read_ldr();
  ASSERT_EQ(full.pixels.size(), settled.pixels.size());
  // Automatic exposure eases from the previews' metering to the full
  // frame's (post-processing only, the same version): the stream lands on
  // the full render once it has settled (bounded: a few seconds of frames).
  int worst = 256;
  for (int i = 0; i < 300; ++i) {
    worst = 0;
    for (std::size_t p = 0; p < full.pixels.size(); ++p)
      worst = std::max(worst, std::abs(full.pixels[p] - settled.pixels[p]));
    if (worst <= 1) break;
    settled = take(pull());
    ASSERT_EQ(settled.version, last);
  }
  EXPECT_LE(worst, 1);
  // A preview differs from it (half the resolution, upsampled), but not by much.
  EXPECT_NE(frames[30].pixels, settled.pixels);

  // After a still spell, a lone change (a click) is drawn in full at once: no preview of it.
  // Stillness counts in real time, however late the frames come.
  while (Clock::now() - params->snapshot().published < std::chrono::milliseconds(400)) gst_sample_unref(pull());
  const std::uint64_t click = params->apply_patch({{"light", {{"direction", {-0.05, 0.0, -1.0}}}}});
  Frame shown = take(pull());
  for (int i = 0; i < 300 && shown.version != click; ++i) shown = take(pull());
  ASSERT_EQ(shown.version, click);
  EXPECT_EQ(shown.level, 0u);
}

TEST_F(CausticSrc, ASlowRenderNeverHoldsUpTheStream) {
  // However fast the machine, each render here takes more than six 60 fps
  // frame intervals: the frame observer runs on the render thread inside
  // the render, and it sleeps. A patch every frame keeps the thread busy.
  constexpr auto kRender = std::chrono::milliseconds(100);
  start("causticsrc name=src scene=" + scene("lens") +
            " width=64 height=64 framerate=60/1 progressive=false ! appsink name=sink sync=true",
        [&](const caustic::FrameStats&, std::uint64_t) { std::this_thread::sleep_for(kRender); });
  auto params = caustic::gst::param_store(src_);
  std::vector<Frame> frames{take(pull())};
  const std::uint64_t renders_before = renders();
  for (int i = 0; i < 90; ++i) {
    params->apply_patch({{"light", {{"direction", {0.001 * i, 0.0, -1.0}}}}});
    GstSample* s = pull();
    ASSERT_NE(s, nullptr) << "frame " << i;
    frames.push_back(take(s));
  }
  // Every frame went out, each one interval after the last ...
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].pts - frames[i - 1].pts, gst_util_uint64_scale(i, GST_SECOND, 60) -
                                                     gst_util_uint64_scale(i - 1, GST_SECOND, 60)) << i;
  // ... while far fewer renders finished than frames were sent (1.5 s of
  // frames hold at most 15 renders of 100 ms, and a loaded machine only
  // makes that fewer): frames did not wait for renders, and the element
  // counted the frames sent while a render had run past its interval.
  guint64 overruns = 0;
  g_object_get(src_, "overruns", &overruns, nullptr);
  const std::uint64_t drawn = renders() - renders_before;
  std::printf("90 frames at 60 fps, renders of %lld ms: %llu renders, %llu overruns\n",
              static_cast<long long>(kRender.count()), static_cast<unsigned long long>(drawn),
              static_cast<unsigned long long>(overruns));
  EXPECT_GE(drawn, 1u);
  EXPECT_LE(drawn, 16u);
  EXPECT_GT(overruns, 0u);
  std::uint64_t versions_shown = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) versions_shown += frames[i].version != frames[i - 1].version;
  EXPECT_LE(versions_shown, drawn + 1);  // + one render already under way when counting began
  EXPECT_GE(versions_shown, 1u);         // the newest finished picture does go out
}

// still-interval-ms: a still scene's unchanged picture goes out only at
// the keep-alive rate, a change goes out at the next frame due, and a key
// frame request from downstream sends a frame at once.
TEST_F(CausticSrc, AnUnchangedPictureIsSentOnlyAtTheKeepAliveRate) {
  start("causticsrc name=src scene=" + scene("slab") +
        " width=32 height=32 framerate=30/1 still-interval-ms=300 ! appsink name=sink");
  std::vector<Frame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(take(pull()));
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].pts - frames[i - 1].pts, 300 * GST_MSECOND) << i;  // nine frame slots
  guint64 skipped = 0;
  g_object_get(src_, "skipped", &skipped, nullptr);
  EXPECT_GE(skipped, 3u * 8u);
}

TEST_F(CausticSrc, AChangeIsSentAtOnceNotAtTheNextKeepAlive) {
  start("causticsrc name=src scene=" + scene("wavy") +
        " width=64 height=64 framerate=30/1 progressive=false still-interval-ms=5000 ! appsink name=sink");
  const Frame first = take(pull());
  const std::uint64_t version =
      caustic::gst::param_store(src_)->apply_patch({{"light", {{"direction", {0.15, 0.05, -1}}}}});
  const Frame next = take(pull());
  EXPECT_EQ(next.version, version);
  EXPECT_LT(next.pts - first.pts, 5 * GST_SECOND);
  EXPECT_NE(next.pixels, first.pixels);
}

// early-frames: a picture drawn while the stream stands still leaves when
// it is ready, not at the next frame time, yet never within an interval of
// the frame before. At 2 frames a second a change made 50 ms after a frame
// time would wait 450 ms for the next one; whether its drawing is done well
// before then depends on the machine's load, so each try checks only when
// it was (picture-version says when).
TEST_F(CausticSrc, AChangeAfterAStillSpellLeavesWhenDrawnNotAtTheNextFrameTime) {
  start("causticsrc name=src scene=" + scene("slab") +
        " width=32 height=32 framerate=2/1 progressive=false still-interval-ms=60000 ! appsink name=sink sync=false");
  auto params = caustic::gst::param_store(src_);
  ASSERT_TRUE(params);
  ASSERT_NE(running_time(), GST_CLOCK_TIME_NONE) << "no clock";
  constexpr GstClockTime interval = GST_SECOND / 2;
  Frame last = take(pull());
  int checked = 0;
  for (int k = 0; k < 20 && checked < 3; ++k) {
    // Just past the frame time after `last`, which left nothing (unchanged).
    while (running_time() < last.pts + interval + 50 * GST_MSECOND) g_usleep(2000);
    const std::uint64_t version = params->apply_patch({{"light", {{"direction", {0.01 * (k + 1), 0.0, -1.0}}}}});
    const GstClockTime next_time = last.pts + 2 * interval;
    guint64 drawn = 0;
    while (running_time() < next_time) {
      g_object_get(src_, "picture-version", &drawn, nullptr);
      if (drawn >= version) break;
      g_usleep(1000);
    }
    // Drawn well before the frame time: more than the quarter interval in
    // which the grid frame is left to go, plus 100 ms for the streaming
    // thread to wake on a loaded machine.
    const bool in_time = drawn >= version && running_time() + interval / 4 + 100 * GST_MSECOND < next_time;
    GstSample* sample = pull();
    ASSERT_NE(sample, nullptr) << k;
    const Frame next = take(sample);
    EXPECT_GE(next.pts, last.pts + interval) << k;  // never within an interval of the last frame
    last = next;
    if (!in_time) continue;
    EXPECT_EQ(next.version, version) << k;
    EXPECT_LT(next.pts, next_time) << k;  // it did not wait for the frame time
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

// While changes keep coming, frames keep the frame rate: none leaves within
// an interval of the one before, however soon a picture is ready.
TEST_F(CausticSrc, FramesNeverComeCloserThanTheFrameInterval) {
  start("causticsrc name=src scene=" + scene("slab") +
        " width=32 height=32 framerate=10/1 still-interval-ms=60000 ! appsink name=sink sync=false");
  auto params = caustic::gst::param_store(src_);
  ASSERT_TRUE(params);
  std::vector<Frame> frames{take(pull())};
  for (int k = 0; k < 40; ++k) {
    params->apply_patch({{"light", {{"direction", {0.005 * (k % 7), 0.0, -1.0}}}}});
    g_usleep(((k % 5) * 20 + 15) * 1000);  // 15 to 95 ms apart: some inside an interval, some past it
    GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink_), 0);
    if (sample) frames.push_back(take(sample));
  }
  for (GstSample* sample; (sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink_), 0));)
    frames.push_back(take(sample));
  ASSERT_GE(frames.size(), 4u);
  for (std::size_t i = 1; i < frames.size(); ++i) EXPECT_GE(frames[i].pts - frames[i - 1].pts, GST_SECOND / 10) << i;
}

TEST_F(CausticSrc, AKeyFrameRequestSendsTheUnchangedPictureAtOnce) {
  start("causticsrc name=src scene=" + scene("slab") +
        " width=32 height=32 framerate=30/1 still-interval-ms=20000 ! appsink name=sink");
  const Frame first = take(pull());
  GstPad* pad = gst_element_get_static_pad(sink_, "sink");
  ASSERT_TRUE(gst_pad_push_event(pad, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 1)));
  gst_object_unref(pad);
  GstSample* sample = pull();
  ASSERT_NE(sample, nullptr) << "no frame after the key frame request";
  const Frame next = take(sample);
  EXPECT_LT(next.pts - first.pts, 20 * GST_SECOND);
  EXPECT_EQ(next.pixels, first.pixels);
}

TEST_F(CausticSrc, ASpectralPictureLeftStandingIsDrawnOnceMoreWithItsStillWavelengths) {
  // The prism traces 16 wavelengths a frame; half a second after its last
  // change the stream draws it once more at render.still_wavelengths (32),
  // then nothing more while it stands; a change starts over.
  std::mutex lock;
  std::vector<int> wavelengths;  // each change of the count drawn (exposure easing redraws the tone map alone)
  start("causticsrc name=src scene=" + scene("prism") + " width=64 height=64 framerate=30/1 ! appsink name=sink",
        [&](const caustic::FrameStats& stats, std::uint64_t) {
          std::lock_guard hold(lock);
          if (wavelengths.empty() || wavelengths.back() != stats.wavelengths) wavelengths.push_back(stats.wavelengths);
        });
  const auto drawn = [&] {
    std::lock_guard hold(lock);
    return wavelengths;
  };
  // Pulls frames for `seconds` of wall time, or until `done` holds.
  const auto stream_for = [&](double seconds, const std::function<bool()>& done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until && !done()) gst_sample_unref(pull());
  };
  stream_for(30, [&] { return drawn().size() >= 2; });
  ASSERT_EQ(drawn(), (std::vector<int>{16, 32}));
  const std::uint64_t passes = renders();
  stream_for(1.5, [] { return false; });
  EXPECT_EQ(renders(), passes) << "a picture standing is drawn once more, not again and again";
  caustic::gst::param_store(src_)->apply_patch({{"light", {{"direction", {0.02, 0.0, -1.0}}}}});
  stream_for(30, [&] { return drawn().size() >= 4; });
  ASSERT_EQ(drawn().size(), 4u);
  EXPECT_EQ(drawn()[2], 16) << "a lone change is drawn in full at once";
  EXPECT_EQ(drawn()[3], 32);
}
