// test_scaling_model.cpp — the list-scheduling model of bench/scaling (mosaic-scaling).
//
// Takes: hand-made cost lists whose schedules are worked out by hand in the comments. Gives:
// checks of list_schedule, the two tile orders and model_frame, and the model's invariants
// (one core sums the costs, more cores never cost time, no schedule beats the lower bound) on
// random cost lists.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "../bench/scaling/list_schedule.hpp"

namespace {

using mosaic::scaling::busiest_first;
using mosaic::scaling::in_order;
using mosaic::scaling::list_schedule;
using mosaic::scaling::longest_first;
using mosaic::scaling::model_frame;

TEST(ScalingModel, ListScheduleByHand) {
  const std::vector<double> costs{3, 3, 2, 2, 2};
  // 1 core: everything in a row.
  EXPECT_DOUBLE_EQ(list_schedule(costs, 1).ms, 12);
  // 2 cores: 3 | 3, then 2 on core 0 (free at 3, lowest index) → 5, 2 on core 1 → 5,
  // 2 on core 0 → 7. The optimum is 6 (3+3 | 2+2+2): list scheduling is not optimal.
  const auto two = list_schedule(costs, 2);
  EXPECT_DOUBLE_EQ(two.ms, 7);
  EXPECT_DOUBLE_EQ(two.total, 12);
  EXPECT_DOUBLE_EQ(two.largest, 3);
  EXPECT_EQ(two.largest_job, 0u);
  EXPECT_DOUBLE_EQ(two.lower_bound(), 6);  // max(3, 12 / 2)
  EXPECT_FALSE(two.bound_by_largest());
  // 3 cores: 3 | 3 | 2, then 2 on core 2 (free at 2) → 4, 2 on core 0 (free at 3) → 5.
  EXPECT_DOUBLE_EQ(list_schedule(costs, 3).ms, 5);
  // 5 or more cores: every job starts at 0; the largest ends last.
  EXPECT_DOUBLE_EQ(list_schedule(costs, 5).ms, 3);
  EXPECT_DOUBLE_EQ(list_schedule(costs, 64).ms, 3);
  EXPECT_TRUE(list_schedule(costs, 5).bound_by_largest());   // 3 >= 12 / 5
  EXPECT_FALSE(list_schedule(costs, 3).bound_by_largest());  // 3 < 12 / 3
  EXPECT_TRUE(list_schedule(costs, 4).bound_by_largest());   // 3 >= 12 / 4
}

TEST(ScalingModel, EdgeCases) {
  EXPECT_DOUBLE_EQ(list_schedule(std::vector<double>{}, 4).ms, 0);
  // Fewer than one core counts as one; a negative cost (clock noise) as nothing.
  EXPECT_DOUBLE_EQ(list_schedule(std::vector<double>{1, 2}, 0).ms, 3);
  EXPECT_EQ(list_schedule(std::vector<double>{1, 2}, 0).cores, 1);
  EXPECT_DOUBLE_EQ(list_schedule(std::vector<double>{1, -5, 2}, 1).ms, 3);
  EXPECT_DOUBLE_EQ(list_schedule(std::vector<double>{1, -5, 2}, 1).total, 3);
}

TEST(ScalingModel, HotTileOrder) {
  // One tile of 10 and ten of 1, total 20.
  std::vector<double> hot_last(10, 1.0);
  hot_last.push_back(10.0);
  // Taken as given on 4 cores: the ten 1s load the cores 3, 3, 2, 2; the 10 lands on a core
  // free at 2 → 12.
  EXPECT_DOUBLE_EQ(list_schedule(hot_last, 4).ms, 12);
  // Longest first: the 10 starts at 0 on core 0; the ten 1s fill cores 1-3 up to 4, 3, 3 → 10.
  const auto lpt = longest_first(hot_last);
  ASSERT_EQ(lpt.front(), 10u);
  const auto hot_first = list_schedule(in_order(hot_last, lpt), 4);
  EXPECT_DOUBLE_EQ(hot_first.ms, 10);
  EXPECT_TRUE(hot_first.bound_by_largest());  // 10 >= 20 / 4
  EXPECT_EQ(hot_first.largest_job, 0u);       // index in the order given
  // From 2 cores on the hot tile bounds the stage (10 >= 20 / 2), not on 1.
  EXPECT_TRUE(list_schedule(in_order(hot_last, lpt), 2).bound_by_largest());
  EXPECT_FALSE(list_schedule(in_order(hot_last, lpt), 1).bound_by_largest());
  EXPECT_DOUBLE_EQ(list_schedule(in_order(hot_last, lpt), 2).ms, 10);
}

TEST(ScalingModel, Orders) {
  // frame.cpp: most triangles first, the lower tile index first on ties.
  const std::vector<std::uint32_t> triangles{5, 9, 5, 0, 9};
  EXPECT_EQ(busiest_first(triangles), (std::vector<std::size_t>{1, 4, 0, 2, 3}));
  const std::vector<double> costs{2.0, 5.0, 2.0, 7.0};
  EXPECT_EQ(longest_first(costs), (std::vector<std::size_t>{3, 1, 0, 2}));
  EXPECT_EQ(in_order(costs, longest_first(costs)), (std::vector<double>{7, 5, 2, 2}));
}

TEST(ScalingModel, FrameByHand) {
  // Setup chunks 1 and 2, binning 0.5 and 0.5, tiles 4, 1, 1, 1, 1 with 10, 1, 1, 1, 1
  // triangles (so the renderer starts the 4 first).
  const std::vector<double> setup{1, 2}, binning{0.5, 0.5}, tiles{1, 1, 4, 1, 1};
  const std::vector<std::uint32_t> triangles{1, 1, 10, 1, 1};
  const auto order = busiest_first(triangles);
  ASSERT_EQ(order.front(), 2u);
  // 2 cores: setup 1 | 2 → 2; binning 0.5 | 0.5 → 0.5; tiles 4 | 1+1+1+1 → 4. Sum 6.5.
  const auto two = model_frame(setup, binning, in_order(tiles, order), 2);
  EXPECT_DOUBLE_EQ(two.setup.ms, 2);
  EXPECT_DOUBLE_EQ(two.binning.ms, 0.5);
  EXPECT_DOUBLE_EQ(two.tiles.ms, 4);
  EXPECT_DOUBLE_EQ(two.ms(), 6.5);
  EXPECT_DOUBLE_EQ(two.total(), 12);
  // Bounds: max(2, 3/2) + max(0.5, 1/2) + max(4, 8/2) = 6.5: this schedule is optimal.
  EXPECT_DOUBLE_EQ(two.lower_bound(), 6.5);
  // 1 core: the sum of every cost.
  EXPECT_DOUBLE_EQ(model_frame(setup, binning, in_order(tiles, order), 1).ms(), 12);
  // Tiles in stored order (the 4 third): core 0 takes 1 then 4 → 5; core 1 takes 1, 1, 1 → 3.
  EXPECT_DOUBLE_EQ(model_frame(setup, binning, tiles, 2).tiles.ms, 5);
}

TEST(ScalingModel, InvariantsOnRandomCosts) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> cost(0.0, 3.0);
  std::uniform_int_distribution<int> count(1, 300);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> costs(static_cast<std::size_t>(count(rng)));
    for (double& c : costs) c = cost(rng);
    double sum = 0, largest = 0;
    for (double c : costs) {
      sum += c;
      largest = std::max(largest, c);
    }
    for (const auto& order : {costs, in_order(costs, longest_first(costs))}) {
      double previous = list_schedule(order, 1).ms;
      EXPECT_NEAR(previous, sum, 1e-9 * sum);
      for (int p = 2; p <= 70; ++p) {
        const double ms = list_schedule(order, p).ms;
        EXPECT_LE(ms, previous + 1e-12) << "trial " << trial << ", " << p << " cores";
        EXPECT_GE(ms, std::max(largest, sum / p) - 1e-9) << "trial " << trial;
        // Graham's bound for any list: total / P + largest * (1 - 1/P).
        EXPECT_LE(ms, sum / p + largest * (1.0 - 1.0 / p) + 1e-9) << "trial " << trial;
        previous = ms;
      }
    }
  }
}

}  // namespace
