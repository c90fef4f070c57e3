#include "polydem/output/series_writer.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "output/output_test_util.h"
#include "output/vtk_test_reader.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::output {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines(const std::string& path) {
  std::istringstream in(test::readFile(path));
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  return out;
}

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(SeriesWriter, RowsReadBackToTheSameDoublesBitForBit) {
  const test::ScratchDir scratch("series", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::vector<std::string> columns{"time",     "step",    "kinetic_energy",  "force_ratio",
                                         "contacts", "block_x", "block_x_analytic"};
  const double third = 1.0 / 3.0;
  const std::vector<std::vector<double>> rows{
      {0.0, 0.0, 0.1 + 0.2, third, 0.0, -0.0, 1e-300},
      {1e-4, 1.0, DBL_MAX, DBL_MIN, 9007199254740993.0, 4.9406564584124654e-324, -third},
      {2e-4, 2.0, std::nextafter(1.0, 2.0), 1e22, 3.0, std::numeric_limits<double>::infinity(),
       std::nan("")}};
  {
    SeriesWriter writer(dir + "/series.csv", columns, MPI_COMM_SELF);
    for (const auto& row : rows) writer.write(row);
    EXPECT_EQ(writer.rows(), 3);
    EXPECT_EQ(writer.column("kinetic_energy"), 2u);
    EXPECT_THROW(writer.column("nope"), Error);
    writer.close();
  }
  const auto text = lines(dir + "/series.csv");
  ASSERT_EQ(text.size(), rows.size() + 1);
  EXPECT_EQ(text[0], "time,step,kinetic_energy,force_ratio,contacts,block_x,block_x_analytic");
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto values = cells(text[r + 1]);
    ASSERT_EQ(values.size(), columns.size());
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const double back = std::strtod(values[c].c_str(), nullptr);
      if (std::isnan(rows[r][c])) {
        EXPECT_TRUE(std::isnan(back));
      } else {
        EXPECT_TRUE(sameBits(back, rows[r][c])) << values[c] << " row " << r << " col " << c;
      }
    }
  }
}

TEST(SeriesWriter, RejectsBadColumnsAndRowsOfTheWrongLength) {
  const test::ScratchDir scratch("series_bad", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/series.csv";
  for (const auto& columns : std::vector<std::vector<std::string>>{
           {}, {"time", "a,b"}, {"time", "time"}, {"time", ""}, {"block 1_x"}, {"a\"b"}}) {
    EXPECT_THROW(SeriesWriter(path, columns, MPI_COMM_SELF), Error) << columns.size();
  }
  SeriesWriter writer(path, {"time", "step"}, MPI_COMM_SELF);
  EXPECT_THROW(writer.write({1.0}), Error);
  EXPECT_THROW(writer.write({1.0, 2.0, 3.0}), Error);
  writer.close();
  EXPECT_THROW(writer.write({1.0, 2.0}), Error);
  EXPECT_EQ(lines(path).size(), 1u);
}

TEST(SeriesWriter, FlushesWholeRowsRegularly) {
  const test::ScratchDir scratch("series_flush", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/series.csv";
  SeriesWriter::Options options;
  options.flush_rows = 3;
  options.flush_seconds = 1e9;
  SeriesWriter writer(path, {"time", "step"}, MPI_COMM_SELF, options);
  EXPECT_EQ(lines(path).size(), 1u);  // the header is there from the start
  writer.write({0.0, 0.0});
  writer.write({0.1, 1.0});
  EXPECT_EQ(lines(path).size(), 1u);  // buffered
  writer.write({0.2, 2.0});
  EXPECT_EQ(lines(path).size(), 4u);  // third row: flushed
  writer.write({0.3, 3.0});
  writer.flush();
  EXPECT_EQ(lines(path).back(), "0.29999999999999999,3");
}

TEST(SeriesWriter, ResumingKeepsRowsUpToTheCheckpointStep) {
  const test::ScratchDir scratch("series_resume", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/series.csv";
  const std::vector<std::string> columns{"time", "step", "x"};
  {
    SeriesWriter writer(path, columns, MPI_COMM_SELF);
    for (int step = 0; step <= 50; step += 10) writer.write({step * 1e-3, double(step), 0.5});
  }
  std::ofstream(path, std::ios::app) << "0.06,6";  // killed in the middle of a row
  SeriesWriter::Options options;
  options.resume_after_step = 20;
  {
    SeriesWriter writer(path, columns, MPI_COMM_SELF, options);
    writer.write({0.03, 30, 0.25});
  }
  const auto text = lines(path);
  ASSERT_EQ(text.size(), 5u);
  EXPECT_EQ(cells(text[3])[1], "20");
  EXPECT_EQ(text[4], "0.029999999999999999,30,0.25");
  // Other columns: not the same series.
  EXPECT_THROW(SeriesWriter(path, {"time", "step", "y"}, MPI_COMM_SELF, options), Error);
  // Fresh (no resume): truncated to the header.
  SeriesWriter fresh(path, columns, MPI_COMM_SELF);
  EXPECT_EQ(lines(path).size(), 1u);
}

TEST(SeriesWriterParallel, OnlyRankZeroWritesAndFailuresReachEveryRank) {
  const test::ScratchDir scratch("series_parallel", MPI_COMM_WORLD);
  const std::string& dir = scratch.path();
  const std::string path = dir + "/series.csv";
  {
    SeriesWriter writer(path, {"time", "step", "rank"}, MPI_COMM_WORLD);
    for (int step = 0; step < 4; ++step)
      writer.write({0.5 * step, double(step), double(mpi::rank())});
    EXPECT_EQ(writer.rows(), mpi::rank() == 0 ? 4 : 0);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const auto text = lines(path);
  ASSERT_EQ(text.size(), 5u);
  for (std::size_t i = 1; i < text.size(); ++i) EXPECT_EQ(cells(text[i])[2], "0");

  const std::string bad = dir + "/missing/series.csv";
  try {
    SeriesWriter writer(bad, {"time"}, MPI_COMM_WORLD);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace
}  // namespace polydem::output
