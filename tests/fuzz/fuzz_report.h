#pragma once
// Bookkeeping shared by the fuzzers: outcome counts, the failed cases (kept on disk for a
// look), the JSON summary they print, and the check that a failed command left nothing behind.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "tests/fuzz/child_process.h"

namespace fuzz {

// Entries of `folder` (recursively) that are not in `inputs`, relative names.
std::vector<std::string> leftovers(const std::filesystem::path& folder,
                                   const std::set<std::string>& inputs);

class FuzzReport {
 public:
  // Records a case: `problem` is empty when it behaved (exit 0, 1 or 2 with a message, nothing
  // left behind on failure). A case that behaved has its folder removed (unless `keep`); one
  // that did not keeps it and is named on stderr.
  void add(const ChildOutcome& outcome, const std::string& problem, const std::string& what,
           const std::filesystem::path& case_dir, const std::filesystem::path& log, bool keep);
  bool passed() const { return failures_.empty(); }
  nlohmann::json summary(const std::string& fuzzer, const nlohmann::json& settings) const;

 private:
  std::map<std::string, int> counts_;
  std::map<std::string, int> exit1_messages_;  // exit 1 is rarer and worth reading
  std::vector<nlohmann::json> failures_;
  double slowest_s_ = 0;
  int cases_ = 0;
};

// The problem with a finished command, or "": only exits 0, 1 and 2 are allowed; 1 and 2 must
// say "error:" and leave nothing in `case_dir` but `inputs`.
std::string judge(const ChildOutcome& outcome, const std::filesystem::path& log,
                  const std::filesystem::path& case_dir, const std::set<std::string>& inputs);

}  // namespace fuzz
