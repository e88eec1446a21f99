// The paper's Table 6 (infer/teacher_student_table.h) from a hand-made comparison: the right rows,
// ratios against the right teacher, and no table without a teacher and a student.
#include <gtest/gtest.h>

#include "infer/teacher_student_table.h"

namespace {

nlohmann::json row(const std::string& name, double params, double flops, double s_per_frame) {
  return {{"name", name},
          {"model", "pagat"},
          {"params", int64_t(params)},
          {"flops_per_particle", flops},
          {"seconds_per_frame", s_per_frame},
          {"seconds_per_simulated_second", s_per_frame / 0.05},
          {"rollout_mse_20", 0.01},
          {"spread", {{"rollout_mse_20", 0.002}}}};
}

nlohmann::json comparison(const nlohmann::json& models) {
  return {{"models", models},
          {"data", "data/x"},
          {"split", "test"},
          {"from_frame", 5},
          {"threads", 2},
          {"trajectories", nlohmann::json::array({{{"source", "a"}}, {{"source", "b"}}})},
          {"sph", {{"seconds_per_simulated_second", 0.47}}}};
}

TEST(TeacherStudentTable, RatiosAreAgainstTheTeacherNamedTeacher) {
  // The ablation listed first must not become the reference.
  const std::string md = infer::teacher_student_table(comparison(
      nlohmann::json::array({row("teacher_no_physics", 800, 300, 0.1), row("gns", 5, 5, 0.04),
                             row("teacher", 1000, 400, 0.2), row("student", 100, 40, 0.05)})));
  EXPECT_NE(md.find("| student | 100 | 0.10 | 40 | 0.10 | 0.05 | 4.00 | 1 | - | 0.01 ± 0.002 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| teacher_no_physics | 800 | 0.80 | 300 | 0.75 | 0.1 | 2.00 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| teacher | 1000 | 1.00 | 400 | 1.00 | 0.2 | 1.00 |"), std::string::npos);
  EXPECT_EQ(md.find("| gns |"), std::string::npos);  // not a teacher or a student
  EXPECT_NE(md.find("| SPH (the data) | - | - | - | - | - | - | 0.47 |"), std::string::npos);
  EXPECT_NE(md.find("2 trajectories of `data/x`"), std::string::npos);
}

TEST(TeacherStudentTable, NoTableWithoutBothATeacherAndAStudent) {
  EXPECT_EQ(infer::teacher_student_table(
                comparison(nlohmann::json::array({row("teacher", 1, 1, 1), row("gns", 1, 1, 1)}))),
            "");
  EXPECT_EQ(
      infer::teacher_student_table(comparison(nlohmann::json::array({row("student", 1, 1, 1)}))),
      "");
  EXPECT_NE(infer::teacher_student_table(comparison(nlohmann::json::array(
                {row("teacher_big", 1, 1, 1), row("student_alone", 1, 1, 1)}))),
            "");
}

}  // namespace
