// SPDX-License-Identifier: MIT
// A per-step series stays within its capacity, keeps an even stride over the whole run, and,
// when asked, keeps each thinned block's peak.
#include "harness/run/decimated_series.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>

namespace softbench::harness {
namespace {

TEST(DecimatedSeries, KeepsEveryValueUpToItsCapacity) {
  DecimatedSeries<int> series(8);
  for (int i = 0; i < 8; ++i) {
    series.offer(i);
  }
  EXPECT_EQ(series.values(), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(series.stride(), 1u);
}

TEST(DecimatedSeries, ThinsToAnEvenStrideThatSpansTheRun) {
  DecimatedSeries<int> series(8);
  for (int i = 0; i < 100; ++i) {
    series.offer(i);
  }
  // 100 values at capacity 8: stride 16, the first step of each block of 16.
  EXPECT_EQ(series.stride(), 16u);
  EXPECT_EQ(series.values(), (std::vector<int>{0, 16, 32, 48, 64, 80, 96}));
  EXPECT_EQ(series.offered(), 100u);
}

TEST(DecimatedSeries, StaysWithinItsCapacityOverAMillionValues) {
  DecimatedSeries<double> series(1000);
  std::size_t largest = 0;
  for (int i = 0; i < 1000000; ++i) {
    series.offer(i);
    largest = std::max(largest, series.values().size());
  }
  EXPECT_EQ(largest, 1000u);
  EXPECT_GE(series.values().size(), 500u);
  EXPECT_EQ(series.values().front(), 0.0);
  EXPECT_GT(series.values().back(), 1000000.0 - 2.0 * static_cast<double>(series.stride()));
}

TEST(DecimatedSeries, KeepsEachBlocksPeakWhenAskedTo) {
  DecimatedSeries<int> series(4);
  const auto larger = [](int a, int b) { return a > b; };
  // One spike at step 13; every other value is 0.
  for (int i = 0; i < 64; ++i) {
    series.offer(i == 13 ? 7 : 0, larger);
  }
  EXPECT_EQ(series.stride(), 16u);
  EXPECT_EQ(series.values(), (std::vector<int>{7, 0, 0, 0}));
}

TEST(DecimatedSeries, AnOddCapacityStillCoversEveryStep) {
  DecimatedSeries<int> series(5);
  const auto larger = [](int a, int b) { return a > b; };
  for (int i = 0; i < 40; ++i) {
    series.offer(i, larger);
  }
  ASSERT_LE(series.values().size(), 5u);
  EXPECT_EQ(series.values().back(), 39);  // the last block's peak is the last value
}

}  // namespace
}  // namespace softbench::harness
