// SPDX-License-Identifier: LGPL-2.1-or-later
// When moving water gets a full frame (water_pacing.hpp), against its stated
// policy with made-up render times, so nothing depends on this machine.
#include "water_pacing.hpp"

#include <gtest/gtest.h>

namespace {

using caustic::gst::WaterPacing;
using Clock = WaterPacing::Clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

const Clock::time_point t0 = Clock::time_point{} + seconds(1000);

TEST(WaterPacing, TheFirstFrameIsFullAndFullFramesGoOnWhileTheyFit) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  EXPECT_TRUE(pacing.want_full(t0));
  pacing.full_drawn(15, t0);
  EXPECT_TRUE(pacing.want_full(t0 + milliseconds(33)));
  pacing.full_drawn(25, t0 + milliseconds(33));
  EXPECT_FALSE(pacing.want_full(t0 + milliseconds(66)));
}

TEST(WaterPacing, AFitEndsASpellOfMissesSoTheNextOverloadIsTriedAgainSoon) {
  // Misses were never forgotten: after one fit, the next overload's first
  // retry waited the blind minute instead of the second.
  WaterPacing pacing(20, seconds(1), seconds(60));
  pacing.full_drawn(30, t0);  // a miss: tried again after a second
  EXPECT_TRUE(pacing.want_full(t0 + seconds(1)));
  pacing.full_drawn(30, t0 + seconds(1));  // a second miss: then once a minute
  EXPECT_FALSE(pacing.want_full(t0 + seconds(3)));
  pacing.full_drawn(10, t0 + seconds(61));  // fits again
  pacing.full_drawn(30, t0 + seconds(62));  // a new overload's first miss
  EXPECT_TRUE(pacing.want_full(t0 + seconds(63)));
}

TEST(WaterPacing, CheaperPreviewsPredictThatAFullFrameFitsAgain) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  pacing.full_drawn(30, t0);
  pacing.preview_drawn(15);  // full frames cost twice a preview
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 30);
  EXPECT_FALSE(pacing.want_full(t0 + milliseconds(33)));
  // The load drops: previews at 9 ms predict 18 ms, once the average has
  // come down (one fast preview is not enough).
  pacing.preview_drawn(9);
  EXPECT_FALSE(pacing.want_full(t0 + milliseconds(66)));
  for (int i = 0; i < 12; ++i) pacing.preview_drawn(9);
  EXPECT_NEAR(pacing.predicted_full_ms(), 18, 0.5);
  EXPECT_TRUE(pacing.want_full(t0 + milliseconds(500)));
}

TEST(WaterPacing, BlindTriesComeASecondAfterTheFirstMissThenOnceAMinute) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  pacing.full_drawn(30, t0);
  pacing.preview_drawn(15);
  EXPECT_FALSE(pacing.want_full(t0 + milliseconds(990)));
  EXPECT_TRUE(pacing.want_full(t0 + seconds(1)));
  const auto t1 = t0 + seconds(1);
  pacing.full_drawn(30, t1);
  pacing.preview_drawn(15);
  EXPECT_FALSE(pacing.want_full(t1 + seconds(1)));
  EXPECT_FALSE(pacing.want_full(t1 + seconds(59)));
  EXPECT_TRUE(pacing.want_full(t1 + seconds(60)));
}

TEST(WaterPacing, ARatioIsMeasuredAgainstPreviewsOfTheSameLoad) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  pacing.full_drawn(30, t0);
  for (int i = 0; i < 20; ++i) pacing.preview_drawn(8);  // a quiet machine: 30/8 would look expensive
  pacing.full_drawn(19, t0 + seconds(1));                // the try fits: full = 2.375 previews
  pacing.full_drawn(38, t0 + seconds(2));                // then the load doubles
  pacing.preview_drawn(16);
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 38);
  for (int i = 0; i < 20; ++i) pacing.preview_drawn(8);
  EXPECT_NEAR(pacing.predicted_full_ms(), 19, 0.2);  // 38 over the old 8 ms previews would say 45
  EXPECT_TRUE(pacing.want_full(t0 + seconds(3)));
}

TEST(WaterPacing, OneSlowFullFrameDoesNotHoldBackTheOthers) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  // Two misses at a steady load teach that a full frame costs two previews.
  pacing.full_drawn(22, t0);
  pacing.preview_drawn(11);
  pacing.full_drawn(22, t0 + seconds(1));
  pacing.preview_drawn(11);
  for (int i = 0; i < 20; ++i) pacing.preview_drawn(8);
  pacing.full_drawn(16, t0 + seconds(2));
  // A hiccup: one full frame takes 40 ms, the preview after it 10.
  pacing.full_drawn(40, t0 + seconds(3));
  pacing.preview_drawn(10);
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 20);  // 2 x 10, not 4 x 10
  EXPECT_TRUE(pacing.want_full(t0 + seconds(3) + milliseconds(66)));
  // Slow full frames that persist do count: three of the last five ratios.
  for (int i = 0; i < 2; ++i) {
    pacing.full_drawn(40, t0 + seconds(4 + i));
    pacing.preview_drawn(10);
  }
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 40);
  EXPECT_FALSE(pacing.want_full(t0 + seconds(5) + milliseconds(66)));
}

TEST(WaterPacing, NoPreviewsYetMeansTheLastFullFrameIsThePrediction) {
  WaterPacing pacing(20, seconds(1), seconds(60));
  pacing.full_drawn(30, t0);
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 30);
  EXPECT_FALSE(pacing.want_full(t0 + milliseconds(33)));
  pacing.preview_drawn(0);  // an empty measurement teaches nothing
  EXPECT_DOUBLE_EQ(pacing.predicted_full_ms(), 30);
}

}  // namespace
