#pragma once
// What an ensemble's members have in common to count: per member, the cells of the reach's grid
// its oil (floating or stranded) has been in at any time up to each output time, the bank bins
// it stranded on, when it reached each watch point and its budget at each output time; and from
// those, the probability of oiling per cell and per bank bin, and the quantiles of arrival and
// of the budget over the members.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "farfield/model/far_field_model.h"
#include "farfield/outputs/forecast_metrics.h"
#include "reach/grid.h"

namespace farfield {

class EnsembleTally {
 public:
  // `bank_group` gives each bank bin's group (a bank's kilometre), counted as oiled when any of
  // its bins is.
  EnsembleTally(const reach::Grid& grid, std::vector<int> bank_group, size_t outputs,
                size_t watch_points);

  // One member: begin, after_step after each of its steps (and before the first), then
  // at_output at each of its output times (the forecast's, in order, time 0 among them), end
  // with its watch points' arrivals.
  void begin_member();
  void after_step(const FarFieldModel& model);
  void at_output(const FarFieldModel& model);
  void end_member(const std::vector<WatchPoint>& points);

  int members() const { return members_; }

  // What the tally holds, as JSON (counts as [index, count] pairs of the cells and bins some
  // member oiled), for a shard of an ensemble run elsewhere; merge() adds such a tally of other
  // members to this one, throwing std::invalid_argument when its grid, bins, outputs or watch
  // points are not this one's.
  nlohmann::json to_json() const;
  void merge(const nlohmann::json& other);
  // The share of members whose oil was in each cell at some time up to output k.
  reach::Field cell_probability(size_t k) const;
  // The share of members that stranded oil on each bank bin, by the end.
  std::vector<double> bank_probability() const;
  // The share of members that stranded oil anywhere in each bank group, by the end.
  std::vector<double> group_probability() const;
  // Each bank bin's group, as given.
  const std::vector<int>& bank_group() const { return bank_group_; }
  // The mean offset from the centreline (m) of the oil stranded on each bin at the members'
  // output times (0 where none was).
  std::vector<double> bank_offset() const;
  // Per watch point, each member's arrival (s; < 0: it never arrived).
  const std::vector<std::vector<double>>& arrivals() const { return arrivals_; }
  // Per output time, each member's budget as fractions of what it released.
  const std::vector<std::vector<Budget>>& budgets() const { return budgets_; }

 private:
  reach::Grid grid_;
  size_t outputs_;
  int members_ = 0;
  size_t output_ = 0;                                   // the current member's next output
  std::vector<std::uint8_t> cell_seen_;                 // the current member's cells so far
  std::vector<std::uint8_t> bin_seen_;                  // and bank bins
  std::vector<std::vector<std::uint32_t>> cell_count_;  // [output][cell] members
  std::vector<std::uint32_t> bin_count_;
  std::vector<int> bank_group_;
  std::vector<std::uint32_t> group_count_;
  std::vector<double> bin_offset_sum_, bin_offset_count_;
  std::vector<std::vector<double>> arrivals_;
  std::vector<std::vector<Budget>> budgets_;
};

// The q-quantile (0-1) of `values` by linear interpolation between order statistics.
double quantile(std::vector<double> values, double q);

}  // namespace farfield
