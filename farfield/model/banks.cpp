#include "farfield/model/banks.h"

#include <algorithm>
#include <cmath>

namespace farfield {

Banks::Banks(const Centreline& centreline, double bin_length, std::vector<BankClass> classes,
             int default_class, const std::vector<BankStretch>& stretches)
    : bin_length_(bin_length), classes_(std::move(classes)) {
  bins_ = int(std::ceil(centreline.length() / bin_length_)) + 1;
  class_.assign(size_t(2 * bins_), default_class);
  for (const BankStretch& s : stretches)
    for (int b = 0; b < bins_; ++b) {
      const double mid = (b + 0.5) * bin_length_;
      if (mid >= s.from_m && mid < s.to_m) class_[size_t(int(s.side) * bins_ + b)] = s.bank_class;
    }
}

int Banks::bin_at(const RiverPosition& p) const {
  const int b = std::clamp(int(std::floor(p.along_m / bin_length_)), 0, bins_ - 1);
  return (p.offset_m > 0 ? bins_ : 0) + b;
}

}  // namespace farfield
