#include "tests/fuzz/fuzz_report.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iostream>
#include <iterator>

namespace fuzz {

namespace fs = std::filesystem;

std::vector<std::string> leftovers(const fs::path& folder, const std::set<std::string>& inputs) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = fs::relative(it->path(), folder).string();
    bool input = false;
    for (const auto& i : inputs) input = input || name == i || name.rfind(i + "/", 0) == 0;
    if (!input) out.push_back(name);
  }
  return out;
}

std::string judge(const ChildOutcome& outcome, const fs::path& log, const fs::path& case_dir,
                  const std::set<std::string>& inputs) {
  if (outcome.kind != ChildOutcome::Kind::kExited) return describe(outcome);
  if (outcome.code == 0) return "";
  if (outcome.code != 1 && outcome.code != 2) return describe(outcome) + " (expected 0, 1 or 2)";
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.find("error:") == std::string::npos) return describe(outcome) + " without a message";
  std::set<std::string> allowed = inputs;
  allowed.insert(log.filename().string());
  const auto left = leftovers(case_dir, allowed);
  if (!left.empty()) return describe(outcome) + " left " + left.front();
  return "";
}

namespace {

// The error message of a log with file names and numbers blanked, so alike errors count as one.
std::string error_kind(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find("error:") != std::string::npos) last = line;
  last = last.substr(std::min(last.size(), last.find("error:") + 7));
  std::string out;
  for (char c : last) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (out.empty() || out.back() != '#') out += '#';
    } else {
      out += c;
    }
  }
  return out.substr(0, 90);
}

}  // namespace

void FuzzReport::add(const ChildOutcome& outcome, const std::string& problem,
                     const std::string& what, const fs::path& case_dir, const fs::path& log,
                     bool keep) {
  ++cases_;
  if (problem.empty() && outcome.code == 1) ++exit1_messages_[error_kind(log)];
  ++counts_[problem.empty() ? describe(outcome) : "failed"];
  slowest_s_ = std::max(slowest_s_, outcome.seconds);
  if (!problem.empty()) {
    failures_.push_back({{"problem", problem}, {"case", what}, {"folder", case_dir.string()}});
    std::cerr << case_dir.filename().string() << ": " << problem << ": " << what << "\n";
  } else if (!keep) {
    fs::remove_all(case_dir);
  }
}

nlohmann::json FuzzReport::summary(const std::string& fuzzer,
                                   const nlohmann::json& settings) const {
  return {{"fuzzer", fuzzer},
          {"settings", settings},
          {"cases", cases_},
          {"outcomes", counts_},
          {"slowest_s", slowest_s_},
          {"failures", failures_},
          {"exit_1_messages", exit1_messages_}};
}

}  // namespace fuzz
