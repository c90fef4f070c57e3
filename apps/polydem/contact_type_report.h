// The contact-type report (BENCHMARKS.md section C): every kernel on the seven cases, beside the
// analytical answer, with how the answer changes under rigid motions and changes of length unit.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "polydem/contact/contact_cases.h"

namespace polydem::app {

struct CaseRow {
  std::string kernel, case_id;
  contact::Contact result;
  contact::CaseEvaluation evaluation;
  // Largest deviation over random rigid motions of the pair (answers moved back to the case's
  // frame): how much the kernel's answer depends on the pose.
  double pose_normal_rad = 0.0, pose_point_rel = 0.0, pose_depth_rel = 0.0;
  bool correct_in_all_poses = false;
  bool correct_at_mm = false, correct_at_km = false;  // scales 1e-3 and 1e3
  double seconds_per_call = 0.0;
};

std::vector<CaseRow> contactTypeRows(const std::vector<std::string>& kernels, int poses,
                                     unsigned seed);
std::string contactTypeMarkdown(const std::vector<CaseRow>& rows,
                                const std::vector<std::string>& kernels);
nlohmann::json contactTypeJson(const std::vector<CaseRow>& rows);

}  // namespace polydem::app
