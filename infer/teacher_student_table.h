#pragma once
// The paper's Table 6 from a comparison: the PAGATNet teacher beside its students (size, cost,
// speed and accuracy), with the simulator that made the data as the speed yardstick.

#include <nlohmann/json.hpp>
#include <string>

namespace infer {

// Markdown for OUT/teacher_student.md, from the object written to comparison.json. Its rows are
// the models whose names contain "teacher" or "student" (ablations included, so a student without
// distillation sits beside the distilled one); the reference teacher is the model named
// "teacher", else the first whose name contains it. Returns "" when the comparison holds no
// teacher or no student: then there is no such table to write.
std::string teacher_student_table(const nlohmann::json& comparison);

}  // namespace infer
