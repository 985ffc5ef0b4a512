// SPDX-License-Identifier: LGPL-2.1-or-later
// The render thread's water clock (frame_source.cpp): a frame of water
// starts when the stream asks for a frame, moved on by the time since the
// last advance, so that it is drawn by the next due time; an ask within
// half an interval of the last advance waits; without asks the water keeps
// whole intervals of its own clock. The asks are set here, so nothing
// depends on how fast this machine draws. A full frame of water still on
// its way out, or not yet asked for, is shown before a preview takes its
// place.
#include "frame_source.hpp"

#include "caustic/param_store.hpp"
#include "caustic/pool.hpp"
#include "caustic/scene.hpp"

#include <gst/gst.h>
#include <gtest/gtest.h>

#include "caustic/gst/frame_meta.hpp"

#include <memory>

namespace {

using Clock = std::chrono::steady_clock;

struct Buffer {
  GstBuffer* buffer;
  ~Buffer() {
    if (buffer) gst_buffer_unref(buffer);
  }
};

// The pool scene's water, drawn by a source of its own.
class FrameSourceWater : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { gst_init(nullptr, nullptr); }
  void SetUp() override {
    ASSERT_TRUE(scene.water);
    source.pool = std::make_shared<caustic::water::Pool>(*scene.water);
  }
  void TearDown() override { caustic::gst::release(source); }
  // No full frame fits, and the blind try is an hour away: after the first
  // picture, moving water comes as previews.
  void never_fits() {
    source.progressive.water_budget = 1e-9;
    source.progressive.water_retry = source.progressive.water_retry_max = std::chrono::hours(1);
  }

  const caustic::Scene scene = caustic::load_scene(std::string(CAUSTIC_ASSET_DIR) + "/scenes/pool.json");
  const caustic::ParamStore params{scene};
  const caustic::MeshLevels meshes;  // water draws its own surface
  caustic::gst::FrameSource source;
};

}  // namespace

TEST_F(FrameSourceWater, AFrameOfWaterStartsWhenTheStreamAsksForIt) {
  const auto interval = std::chrono::duration_cast<Clock::duration>(source.frame_interval);
  auto frame = [&] { return Buffer{caustic::gst::produce_frame(source, params, meshes, 32, 32, true)}; };

  { const Buffer first = frame(); }
  // The last advance set well ahead of now, so that the clock's own
  // fallback (an interval and a half without asks) cannot act below,
  // however long this machine takes to draw.
  const Clock::time_point start = Clock::now() + 100 * interval;
  source.water_clock = start;
  const std::uint64_t steps = source.pool->step();

  // Asked five intervals after the last advance: the water moves on by
  // exactly that, at once, and the frame drawn shows it.
  source.asked = (start + 5 * interval).time_since_epoch().count();
  { const Buffer moved = frame(); }
  EXPECT_EQ(source.water_clock, start + 5 * interval);
  EXPECT_GT(source.pool->step(), steps);

  // The same ask again, and one within half an interval: no new water.
  const std::uint64_t after_ask = source.pool->step();
  { const Buffer again = frame(); }
  source.asked = (start + 5 * interval + interval * 2 / 5).time_since_epoch().count();
  { const Buffer early = frame(); }
  EXPECT_EQ(source.water_clock, start + 5 * interval);
  EXPECT_EQ(source.pool->step(), after_ask);

  // No asks (the stream not playing): once an interval and a half has
  // passed, the water moves by whole intervals of its own clock.
  source.asked = 0;
  const Clock::time_point back = Clock::now() - 7 * interval / 2;
  source.water_clock = back;
  { const Buffer own = frame(); }
  const auto moved = source.water_clock - back;
  EXPECT_GE(moved, 3 * interval);
  EXPECT_EQ(moved % interval, Clock::duration::zero()) << "not whole intervals";
  EXPECT_GT(source.pool->step(), after_ask);
}

TEST_F(FrameSourceWater, AFullFrameOnItsWayOutIsShownBeforeAPreviewTakesItsPlace) {
  never_fits();
  const auto interval = std::chrono::duration_cast<Clock::duration>(source.frame_interval);
  Clock::time_point asked = Clock::now() + 100 * interval;
  source.water_clock = asked;
  auto frame = [&] {
    asked += 2 * interval;  // each frame a new step of water
    source.asked = asked.time_since_epoch().count();
    return Buffer{caustic::gst::produce_frame(source, params, meshes, 32, 32, false)};
  };
  auto level = [](const Buffer& b) { return caustic_buffer_get_frame_meta(b.buffer)->level; };
  { const Buffer first = frame(); ASSERT_EQ(level(first), caustic::gst::full_quality); }
  { const Buffer second = frame(); ASSERT_EQ(level(second), caustic::gst::preview); }

  // A full frame's copy queued and not yet handed over, as on a GPU (or a
  // busy llvmpipe) whose fence has not signalled by the time it is polled.
  source.context->make_current();
  const std::uint64_t tag = ++source.readbacks;
  source.in_flight.push_back({tag, source.rendered, source.pool->step(), caustic::gst::full_quality});
  source.engine->start_readback(tag, source.format);
  source.readback_pending = true;
  source.rendered_level = caustic::gst::full_quality;
  source.context->release_current();

  // The water moves on, so a preview is due; the full frame comes out first,
  // and the preview with the frame after it.
  const std::uint64_t passes = source.engine->ray_passes();
  { const Buffer shown = frame(); EXPECT_EQ(level(shown), caustic::gst::full_quality) << "the full frame was hidden"; }
  EXPECT_EQ(source.engine->ray_passes(), passes) << "a preview drawn over the full frame on its way out";
  { const Buffer next = frame(); EXPECT_EQ(level(next), caustic::gst::preview); }
  EXPECT_GT(source.engine->ray_passes(), passes);
}

// The stream takes the newest picture when it asks: a full frame of water
// followed by a preview before the next ask (a stream held up a moment on a
// loaded machine) was never sent, and the next try came a minute later.
TEST_F(FrameSourceWater, AFullFrameNotYetAskedForIsShownBeforeAPreviewTakesItsPlace) {
  never_fits();
  const auto interval = std::chrono::duration_cast<Clock::duration>(source.frame_interval);
  auto level = [](const Buffer& b) { return caustic_buffer_get_frame_meta(b.buffer)->level; };
  auto frame = [&] { return Buffer{caustic::gst::produce_frame(source, params, meshes, 32, 32, true)}; };
  source.asked = Clock::now().time_since_epoch().count();
  { const Buffer first = frame(); ASSERT_EQ(level(first), caustic::gst::full_quality); }
  source.picture_at = Clock::now();  // handed to the stream, as the worker does

  // The water moves on by its own clock, with no ask since the full frame.
  source.water_clock = Clock::now() - 4 * interval;
  const std::uint64_t passes = source.engine->ray_passes(), steps = source.pool->step();
  { const Buffer kept = frame(); EXPECT_EQ(level(kept), caustic::gst::full_quality) << "the full frame was hidden"; }
  EXPECT_GT(source.pool->step(), steps);
  EXPECT_EQ(source.engine->ray_passes(), passes) << "a preview drawn over a full frame never asked for";

  // Asked for: the preview follows.
  source.asked = Clock::now().time_since_epoch().count();
  { const Buffer next = frame(); EXPECT_EQ(level(next), caustic::gst::preview); }
  EXPECT_GT(source.engine->ray_passes(), passes);
}
