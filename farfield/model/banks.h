#pragma once
// The river's banks as bins along the centreline, one row per side: where stranded oil is
// counted (per bank and per km) and how much each bin can hold. A bin's class (rock, gravel,
// sand, vegetated, ...) sets how much oil a metre of its bank holds and how fast stranded oil
// floats off again; past its capacity a bank takes no more and the slick moves along it.
//
// The numbers are a user's: TELEMAC-2D's oil module and GNOME's shoreline types tabulate
// retention by bank type and oil viscosity and are the documented place to start; the shipped
// configs state what they assumed.

#include <string>
#include <vector>

#include "farfield/model/centreline.h"

namespace farfield {

struct BankClass {
  std::string name;
  double capacity_m3_per_m = 0.01;     // oil (emulsion) a metre of bank holds
  double refloat_half_life_s = 86400;  // half of the stranded oil floats off in this time
};

enum class BankSide { right = 0, left = 1 };

struct BankStretch {
  BankSide side = BankSide::right;
  double from_m = 0, to_m = 0;  // along the centreline
  int bank_class = 0;           // index into the classes
};

class Banks {
 public:
  Banks() = default;
  // Bins of `bin_length` (m) along the whole centreline (and one more each end for what lies
  // beyond it); every bin of `default_class` unless a stretch says otherwise.
  Banks(const Centreline& centreline, double bin_length, std::vector<BankClass> classes,
        int default_class, const std::vector<BankStretch>& stretches);

  int bins_per_side() const { return bins_; }
  int bins() const { return 2 * bins_; }
  double bin_length() const { return bin_length_; }
  // The bin at a point beside the river (along, offset as Centreline::locate gives them).
  int bin_at(const RiverPosition& p) const;
  BankSide side_of(int bin) const { return bin < bins_ ? BankSide::right : BankSide::left; }
  // Distance along the centreline of the bin's start (m).
  double bin_start(int bin) const { return (bin % bins_) * bin_length_; }
  const BankClass& class_of(int bin) const { return classes_[size_t(class_[size_t(bin)])]; }
  double capacity_m3(int bin) const { return class_of(bin).capacity_m3_per_m * bin_length_; }
  const std::vector<BankClass>& classes() const { return classes_; }

 private:
  double bin_length_ = 100;
  int bins_ = 0;
  std::vector<BankClass> classes_;
  std::vector<int> class_;  // per bin
};

}  // namespace farfield
