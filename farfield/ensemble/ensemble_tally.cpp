#include "farfield/ensemble/ensemble_tally.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace farfield {

EnsembleTally::EnsembleTally(const reach::Grid& grid, std::vector<int> bank_group, size_t outputs,
                             size_t watch_points)
    : grid_(grid),
      outputs_(outputs),
      cell_seen_(grid.cells(), 0),
      bin_seen_(bank_group.size(), 0),
      cell_count_(outputs, std::vector<std::uint32_t>(grid.cells(), 0)),
      bin_count_(bank_group.size(), 0),
      bank_group_(std::move(bank_group)),
      group_count_(bank_group_.empty()
                       ? 0
                       : size_t(*std::max_element(bank_group_.begin(), bank_group_.end())) + 1,
                   0),
      bin_offset_sum_(bank_group_.size(), 0.0),
      bin_offset_count_(bank_group_.size(), 0.0),
      arrivals_(watch_points),
      budgets_(outputs) {}

void EnsembleTally::begin_member() {
  std::fill(cell_seen_.begin(), cell_seen_.end(), 0);
  std::fill(bin_seen_.begin(), bin_seen_.end(), 0);
  output_ = 0;
}

void EnsembleTally::after_step(const FarFieldModel& model) {
  const Elements& el = model.elements();
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] == ElementState::left_reach) continue;
    if (el.state[e] == ElementState::stranded) bin_seen_[size_t(el.bank_segment[e])] = 1;
    size_t cell = 0;
    if (cell_holding(grid_, el.x[e], el.y[e], cell)) cell_seen_[cell] = 1;
  }
}

void EnsembleTally::at_output(const FarFieldModel& model) {
  if (output_ >= outputs_) return;
  std::vector<std::uint32_t>& count = cell_count_[output_];
  for (size_t c = 0; c < count.size(); ++c) count[c] += cell_seen_[c];
  budgets_[output_].push_back(model.budget());
  const Elements& el = model.elements();
  for (size_t e = 0; e < el.size(); ++e) {
    if (el.state[e] != ElementState::stranded) continue;
    const size_t bin = size_t(el.bank_segment[e]);
    bin_offset_sum_[bin] += model.setup().centreline.locate(el.x[e], el.y[e]).offset_m;
    bin_offset_count_[bin] += 1;
  }
  ++output_;
}

void EnsembleTally::end_member(const std::vector<WatchPoint>& points) {
  std::vector<std::uint8_t> group_seen(group_count_.size(), 0);
  for (size_t b = 0; b < bin_count_.size(); ++b) {
    bin_count_[b] += bin_seen_[b];
    if (bin_seen_[b]) group_seen[size_t(bank_group_[b])] = 1;
  }
  for (size_t g = 0; g < group_count_.size(); ++g) group_count_[g] += group_seen[g];
  for (size_t p = 0; p < points.size() && p < arrivals_.size(); ++p)
    arrivals_[p].push_back(points[p].arrival_s);
  ++members_;
}

reach::Field EnsembleTally::cell_probability(size_t k) const {
  reach::Field p(grid_.cells(), 0.0);
  if (members_ == 0) return p;
  for (size_t c = 0; c < p.size(); ++c) p[c] = double(cell_count_[k][c]) / members_;
  return p;
}

std::vector<double> EnsembleTally::bank_probability() const {
  std::vector<double> p(bin_count_.size(), 0.0);
  if (members_ == 0) return p;
  for (size_t b = 0; b < p.size(); ++b) p[b] = double(bin_count_[b]) / members_;
  return p;
}

std::vector<double> EnsembleTally::group_probability() const {
  std::vector<double> p(group_count_.size(), 0.0);
  if (members_ == 0) return p;
  for (size_t g = 0; g < p.size(); ++g) p[g] = double(group_count_[g]) / members_;
  return p;
}

std::vector<double> EnsembleTally::bank_offset() const {
  std::vector<double> offset(bin_offset_sum_.size(), 0.0);
  for (size_t b = 0; b < offset.size(); ++b)
    if (bin_offset_count_[b] > 0) offset[b] = bin_offset_sum_[b] / bin_offset_count_[b];
  return offset;
}

namespace {
// Budget <-> [released, floating, stranded, evaporated, dispersed, left_reach, sunk].
nlohmann::json budget_json(const Budget& b) {
  return {b.released, b.floating, b.stranded, b.evaporated, b.dispersed, b.left_reach, b.sunk};
}
Budget budget_from(const nlohmann::json& j) {
  Budget b;
  b.released = j.at(0);
  b.floating = j.at(1);
  b.stranded = j.at(2);
  b.evaporated = j.at(3);
  b.dispersed = j.at(4);
  b.left_reach = j.at(5);
  b.sunk = j.at(6);
  return b;
}
}  // namespace

nlohmann::json EnsembleTally::to_json() const {
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& count : cell_count_) {
    nlohmann::json pairs = nlohmann::json::array();
    for (size_t c = 0; c < count.size(); ++c)
      if (count[c] > 0) pairs.push_back({c, count[c]});
    cells.push_back(pairs);
  }
  nlohmann::json bins = nlohmann::json::array();
  for (size_t b = 0; b < bin_count_.size(); ++b)
    if (bin_count_[b] > 0 || bin_offset_count_[b] > 0)
      bins.push_back({b, bin_count_[b], bin_offset_sum_[b], bin_offset_count_[b]});
  nlohmann::json budgets = nlohmann::json::array();
  for (const auto& at_output : budgets_) {
    nlohmann::json members = nlohmann::json::array();
    for (const Budget& b : at_output) members.push_back(budget_json(b));
    budgets.push_back(members);
  }
  nlohmann::json groups = nlohmann::json::array();
  for (size_t g = 0; g < group_count_.size(); ++g)
    if (group_count_[g] > 0) groups.push_back({g, group_count_[g]});
  return {{"members", members_},       {"group_counts", groups}, {"grid", {grid_.nx, grid_.ny}},
          {"bins", bin_count_.size()}, {"outputs", outputs_},    {"cell_counts", cells},
          {"bin_counts", bins},        {"arrivals", arrivals_},  {"budgets", budgets}};
}

void EnsembleTally::merge(const nlohmann::json& j) {
  if (j.at("grid") != nlohmann::json{grid_.nx, grid_.ny} || j.at("bins") != bin_count_.size() ||
      j.at("outputs") != outputs_ || j.at("arrivals").size() != arrivals_.size())
    throw std::invalid_argument(
        "its grid, bank bins, output times or watch points are not this forecast's");
  for (size_t k = 0; k < outputs_; ++k)
    for (const auto& pair : j.at("cell_counts").at(k)) {
      const size_t c = pair.at(0);
      if (c >= cell_count_[k].size()) throw std::invalid_argument("a cell outside the grid");
      cell_count_[k][c] += pair.at(1).get<std::uint32_t>();
    }
  for (const auto& bin : j.at("bin_counts")) {
    const size_t b = bin.at(0);
    if (b >= bin_count_.size()) throw std::invalid_argument("a bank bin outside the banks");
    bin_count_[b] += bin.at(1).get<std::uint32_t>();
    bin_offset_sum_[b] += bin.at(2).get<double>();
    bin_offset_count_[b] += bin.at(3).get<double>();
  }
  for (const auto& group : j.at("group_counts")) {
    const size_t g = group.at(0);
    if (g >= group_count_.size()) throw std::invalid_argument("a bank group outside the banks");
    group_count_[g] += group.at(1).get<std::uint32_t>();
  }
  for (size_t p = 0; p < arrivals_.size(); ++p)
    for (const auto& a : j.at("arrivals").at(p)) arrivals_[p].push_back(a.get<double>());
  for (size_t k = 0; k < outputs_; ++k)
    for (const auto& b : j.at("budgets").at(k)) budgets_[k].push_back(budget_from(b));
  members_ += j.at("members").get<int>();
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double at = q * double(values.size() - 1);
  const size_t lo = size_t(std::floor(at)), hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (at - double(lo)) * (values[hi] - values[lo]);
}

}  // namespace farfield
