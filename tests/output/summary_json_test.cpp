#include "polydem/output/summary_json.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>

#include "output/output_test_util.h"
#include "output/vtk_test_reader.h"
#include "polydem/core/error.h"

namespace polydem::output {
namespace {

TEST(SummaryJson, CheckComparisonsFollowTheirDefinitions) {
  EXPECT_TRUE(checkPasses("abs", 1.5, 1.0, 0.5));  // on the boundary
  EXPECT_FALSE(checkPasses("abs", 1.5, 1.0, 0.25));
  EXPECT_TRUE(checkPasses("rel", -101.0, -100.0, 0.01));
  EXPECT_FALSE(checkPasses("rel", -101.5, -100.0, 0.01));
  EXPECT_FALSE(checkPasses("rel", 1e-300, 0.0, 0.5));  // relative to zero: only zero passes
  EXPECT_TRUE(checkPasses("max", 1e-7, 1e-6, 0.0));
  EXPECT_FALSE(checkPasses("max", 2e-6, 1e-6, 0.0));
  EXPECT_TRUE(checkPasses("min", 3.0, 2.0, 0.0));
  EXPECT_FALSE(checkPasses("min", 1.0, 2.0, 0.0));
  for (const char* compare : {"abs", "rel", "max", "min"}) {
    EXPECT_FALSE(checkPasses(compare, std::nan(""), 1.0, 1e9)) << compare;
  }
  EXPECT_TRUE(checkPasses("report", std::nan(""), 1.0, 0.0));
  EXPECT_THROW(checkPasses("approx", 1.0, 1.0, 1.0), Error);
}

TEST(SummaryJson, ChecksCarryEveryFieldAndNonFiniteNumbersBecomeNull) {
  CheckResult a{"drift", "centroid_drift", 3e-7, 1e-6, 0.0, "max", true, "BENCHMARKS.md S", "", ""};
  CheckResult b{"energy", "kinetic_energy_ratio", std::nan(""), 1.0, 0.01, "rel", false, "", "NaN",
                "1"};
  const auto j = checksJson({a, b});
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["name"], "drift");
  EXPECT_EQ(j[0]["kind"], "centroid_drift");
  EXPECT_EQ(j[0]["value"].get<double>(), 3e-7);
  EXPECT_EQ(j[0]["expected"].get<double>(), 1e-6);
  EXPECT_EQ(j[0]["tolerance"].get<double>(), 0.0);
  EXPECT_EQ(j[0]["compare"], "max");
  EXPECT_EQ(j[0]["pass"], true);
  EXPECT_EQ(j[0]["reference"], "BENCHMARKS.md S");
  EXPECT_EQ(j[0]["note"], "");
  EXPECT_EQ(j[0]["unit"], "");
  EXPECT_TRUE(j[1]["value"].is_null());
  EXPECT_EQ(j[1]["pass"], false);
  EXPECT_EQ(j[1]["note"], "NaN");
  EXPECT_EQ(j[1]["unit"], "1");
}

TEST(SummaryJson, TimingRowsKeepTheReducedFiguresAndAddPerStepAndImbalance) {
  std::vector<TimingPool::Reduced> rows{{"contact", 1.0, 2.0, 4.0, 10, 0.8},
                                        {"output", 0.5, 0.5, 0.5, 2, 0.2}};
  const auto j = timingJson(rows, 100);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["name"], "contact");
  EXPECT_EQ(j[0]["min_s"].get<double>(), 1.0);
  EXPECT_EQ(j[0]["mean_s"].get<double>(), 2.0);
  EXPECT_EQ(j[0]["max_s"].get<double>(), 4.0);
  EXPECT_EQ(j[0]["count"].get<std::int64_t>(), 10);
  EXPECT_EQ(j[0]["share"].get<double>(), 0.8);
  EXPECT_EQ(j[0]["imbalance"].get<double>(), 2.0);
  EXPECT_EQ(j[0]["per_step_s"].get<double>(), 0.02);
  EXPECT_EQ(j[1]["imbalance"].get<double>(), 1.0);
  EXPECT_FALSE(timingJson(rows, 0)[0].contains("per_step_s"));
}

TEST(SummaryJson, WrittenAtomicallyAndReadsBackEqual) {
  const test::ScratchDir scratch("summary", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/summary.json";
  nlohmann::json summary = {{"id", "S-BLOCK-ON-PLANE"},
                            {"steps", 100000},
                            {"dt", 1.0 / 3.0 * 1e-4},
                            {"checks", checksJson({})}};
  writeJsonAtomic(path, summary);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const std::string text = test::readFile(path);
  EXPECT_EQ(text.back(), '\n');
  const auto back = nlohmann::json::parse(text);
  EXPECT_EQ(back, summary);
  EXPECT_EQ(back["dt"].get<double>(), 1.0 / 3.0 * 1e-4);  // round-trips exactly
  // Invalid UTF-8 in a label does not lose the summary.
  summary["title"] = std::string("bad \xff byte");
  writeJsonAtomic(path, summary);
  EXPECT_NO_THROW(nlohmann::json::parse(test::readFile(path)));
}

}  // namespace
}  // namespace polydem::output
