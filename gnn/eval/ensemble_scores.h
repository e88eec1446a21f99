#pragma once
// Scores of an ensemble forecast against what happened, for a flow too chaotic to forecast as one
// answer: the continuous ranked probability score of a quantity (front distance, slick area,
// arrival time) and the Brier score of an event (oil at an intake by a time). Both in their fair
// form (Ferro 2014, "Fair scores for ensemble forecasts"): their expectation over ensembles
// drawn from a distribution is that distribution's score whatever the number of members, so an
// ensemble of 5 and one of 8 are scored alike. Lower is better; 0 is a sure, right forecast.

#include <vector>

namespace gnn {

// Fair CRPS, in the quantity's units: mean_i |x_i - y| - sum_{i,j} |x_i - x_j| / (2 K (K - 1)).
// With one member, |x - y|. Throws std::invalid_argument for no members or a value not finite.
double fair_crps(const std::vector<double>& members, double observed);

// Fair Brier score of an event that `members_with_event` of `members` ensemble members forecast,
// against whether it happened: (p - o)^2 - p (1 - p) / (K - 1), p the members' share; with one
// member, (p - o)^2. Throws std::invalid_argument for no members or more with the event than
// members.
double fair_brier(int members_with_event, int members, bool happened);

}  // namespace gnn
