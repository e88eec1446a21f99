#include "infer/teacher_student_table.h"

#include <cstdio>
#include <sstream>
#include <vector>

namespace infer {
namespace {

bool contains(const std::string& text, const char* part) {
  return text.find(part) != std::string::npos;
}

std::string number(const nlohmann::json& v, const char* format = "%.3g") {
  if (!v.is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, v.get<double>());
  return text;
}

// "mean ± sd" of one figure of a row of comparison.json.
std::string figure(const nlohmann::json& row, const char* key) {
  const std::string m = number(row.value(key, nlohmann::json()));
  if (m == "-") return m;
  const nlohmann::json sd =
      row.value("spread", nlohmann::json::object()).value(key, nlohmann::json());
  return sd.is_number() && sd.get<double>() > 0 ? m + " ± " + number(sd) : m;
}

double value(const nlohmann::json& row, const char* key) {
  const nlohmann::json v = row.value(key, nlohmann::json());
  return v.is_number() ? v.get<double>() : -1.0;
}

}  // namespace

std::string teacher_student_table(const nlohmann::json& comparison) {
  std::vector<nlohmann::json> rows;
  int teacher = -1;
  bool any_student = false;
  for (const auto& row : comparison.at("models")) {
    const std::string name = row.at("name").get<std::string>();
    const bool is_teacher = contains(name, "teacher"), is_student = contains(name, "student");
    if (!is_teacher && !is_student) continue;
    any_student = any_student || is_student;
    if (is_teacher && (teacher < 0 || name == "teacher")) teacher = int(rows.size());
    rows.push_back(row);
  }
  if (teacher < 0 || !any_student) return "";

  const nlohmann::json& ref = rows[size_t(teacher)];
  const double ref_frame = value(ref, "seconds_per_frame");
  const double ref_flops = value(ref, "flops_per_particle");
  const double ref_params = value(ref, "params");
  std::ostringstream md;
  md << "# PAGATNet: teacher and students\n\n"
     << "The paper's Table 6 on our data: the models of `comparison.md` whose names contain "
        "`teacher` or `student`, rolled out on the same "
     << comparison.at("trajectories").size() << " trajectories of `"
     << comparison.at("data").get<std::string>() << "` ("
     << comparison.at("split").get<std::string>() << " split) from frame "
     << comparison.at("from_frame") << ", each on " << comparison.at("threads")
     << " threads, one model after the other. Ratios are against `"
     << ref.at("name").get<std::string>()
     << "` (speed-up: its seconds per frame over the row's). FLOPs per particle: the forward "
        "pass's matrix products (2 per multiply-add) on the first trajectory's starting graph, "
        "over its particles. Errors: mean ± standard deviation over the trajectories, as in "
        "`comparison.json`.\n\n";
  md << "| model | params | params / teacher | FLOPs per particle | FLOPs / teacher "
        "| s per frame | speed-up | s per simulated s | one-step MSE (m²) | MSE @20 | MSE @50 "
        "| oil IoU @20 | slick area error |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto ratio = [](double a, double b) {
    return a > 0 && b > 0 ? number(nlohmann::json(a / b), "%.2f") : std::string("-");
  };
  for (const auto& row : rows) {
    md << "| " << row.at("name").get<std::string>() << " | " << row.at("params") << " | "
       << ratio(value(row, "params"), ref_params) << " | "
       << number(row.value("flops_per_particle", nlohmann::json())) << " | "
       << ratio(value(row, "flops_per_particle"), ref_flops) << " | "
       << figure(row, "seconds_per_frame") << " | "
       << ratio(ref_frame, value(row, "seconds_per_frame")) << " | "
       << figure(row, "seconds_per_simulated_second") << " | " << figure(row, "one_step_mse")
       << " | " << figure(row, "rollout_mse_20") << " | " << figure(row, "rollout_mse_50") << " | "
       << figure(row, "oil_iou_20") << " | " << figure(row, "slick_area_error") << " |\n";
  }
  const nlohmann::json sph = comparison.value("sph", nlohmann::json::object());
  md << "| SPH (the data) | - | - | - | - | - | - | "
     << number(sph.value("seconds_per_simulated_second", nlohmann::json()))
     << " | - | - | - | - | - |\n\n"
     << "SPH's seconds per simulated second are the wall time recorded when the data were made "
        "(`metadata.json`), not a run beside the models.\n";
  return md.str();
}

}  // namespace infer
