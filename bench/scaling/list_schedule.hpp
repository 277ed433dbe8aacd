// bench/scaling/list_schedule.hpp — a list-scheduling model of one mosaic frame on P cores.
//
// Takes: measured costs (ms) of the frame's independent jobs — front-end chunks (setup), binning
// chunks, screen tiles — and a core count. Gives: the modelled makespan of each stage and of the
// frame, with the lower bound max(largest job, total / P) every schedule obeys.
//
// The model follows engine/src/frame.cpp: stage 1 (setup) in parallel over chunks, a barrier,
// stage 2 (binning) in parallel over the same chunks, a barrier, stage 3 one task per tile, in
// the renderer's order (busiest first by binned triangle count). One simplification: the renderer
// bins each chunk in the task that set it up (stages 1 and 2 are one stage there), while the
// model keeps a barrier between them so that each shows its own scaling; with many chunks of
// similar cost the two differ by about one chunk's cost. Each stage is Graham's list
// scheduling: jobs taken in a fixed order, each started on the core that falls free first.
// For a fixed order of independent jobs the makespan never rises with the core count (the k
// smallest core loads on P + 1 cores never exceed those on P cores, job after job), and it is
// at most total / P + largest * (1 - 1/P) (Graham 1966). Header-only, standard library only, so
// that tests/test_scaling_model.cpp checks it on hand-made cost lists.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <numeric>
#include <queue>
#include <span>
#include <utility>
#include <vector>

namespace mosaic::scaling {

/// One stage of the model on one core count.
struct StageModel {
  double ms = 0;                ///< modelled makespan: the last job's finish time
  double total = 0;             ///< sum of the job costs: the makespan on one core
  double largest = 0;           ///< the largest job: no schedule finishes before it
  std::size_t largest_job = 0;  ///< index (in the caller's order) of the largest job
  int cores = 1;                ///< the core count modelled
  /// max(largest, total / cores): no schedule of these jobs on `cores` cores beats it.
  double lower_bound() const { return std::max(largest, total / static_cast<double>(cores)); }
  /// Whether one job alone bounds the stage: largest >= total / cores.
  bool bound_by_largest() const { return largest >= total / static_cast<double>(cores); }
};

/// Graham's list scheduling of `costs` (taken in the order given) on `cores` cores: each job
/// starts on the core that is free first, the lowest-numbered core on ties. Negative costs
/// count as 0; fewer than one core counts as one.
inline StageModel list_schedule(std::span<const double> costs, int cores) {
  StageModel m;
  m.cores = std::max(1, cores);
  // (time the core falls free, core index), smallest first.
  using Slot = std::pair<double, int>;
  std::priority_queue<Slot, std::vector<Slot>, std::greater<>> free_at;
  for (int c = 0; c < m.cores; ++c) free_at.push({0.0, c});
  for (std::size_t j = 0; j < costs.size(); ++j) {
    const double cost = std::max(0.0, costs[j]);
    m.total += cost;
    if (cost > m.largest) {
      m.largest = cost;
      m.largest_job = j;
    }
    Slot s = free_at.top();
    free_at.pop();
    s.first += cost;
    m.ms = std::max(m.ms, s.first);
    free_at.push(s);
  }
  return m;
}

/// frame.cpp's tile order: most binned triangles first, lower tile index first on ties.
inline std::vector<std::size_t> busiest_first(std::span<const std::uint32_t> triangles) {
  std::vector<std::size_t> order(triangles.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return triangles[a] > triangles[b]; });
  return order;
}

/// Longest processing time first (LPT): the largest measured cost first, lower index on ties.
/// A scheduler that knew each tile's cost in advance would do this; it is within 4/3 - 1/(3P)
/// of the optimum (Graham 1969), so it stands for the bound of a better tile order.
inline std::vector<std::size_t> longest_first(std::span<const double> costs) {
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  return order;
}

/// `values` taken in `order`.
inline std::vector<double> in_order(std::span<const double> values,
                                    std::span<const std::size_t> order) {
  std::vector<double> out;
  out.reserve(order.size());
  for (std::size_t i : order) out.push_back(values[i]);
  return out;
}

/// The three stages of a frame on one core count; stages are separated by barriers, so the
/// frame's time is their sum.
struct FrameModel {
  StageModel setup, binning, tiles;
  /// Modelled frame time on `tiles.cores` cores.
  double ms() const { return setup.ms + binning.ms + tiles.ms; }
  /// Sum of every cost: the modelled one-core frame.
  double total() const { return setup.total + binning.total + tiles.total; }
  /// The sum of the stages' lower bounds (the barriers make them add up).
  double lower_bound() const {
    return setup.lower_bound() + binning.lower_bound() + tiles.lower_bound();
  }
};

/// Models a frame: chunk setup costs and chunk binning costs in chunk order, tile costs in the
/// order the tiles are started (see busiest_first and longest_first).
inline FrameModel model_frame(std::span<const double> setup_costs,
                              std::span<const double> binning_costs,
                              std::span<const double> tile_costs_in_start_order, int cores) {
  return {list_schedule(setup_costs, cores), list_schedule(binning_costs, cores),
          list_schedule(tile_costs_in_start_order, cores)};
}

}  // namespace mosaic::scaling
