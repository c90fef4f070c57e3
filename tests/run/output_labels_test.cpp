// Output is labelled with the step it holds: a cube in free fall, written to
// series.csv after every step, is at z0 - g t^2 / 2 at each row's time t = step x dt (the leapfrog
// is exact for a constant force), its leapfrog velocity is -g (t - dt/2), the last row is written
// once, and the snapshots are numbered by the steps they hold. A row holding the state one step
// later than its label would be off by g t dt in z.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "polydem/core/exact_sum.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/run.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::sim {
namespace {

namespace fs = std::filesystem;

const char* const kFreeFall = R"([scene]
id = "T-FREE-FALL"
[simulation]
dt = "1 ms"
steps = 50
gravity = [0, 0, -9.81]
[[material]]
name = "rock"
density = 2500
kn = 1e9
[[shape]]
name = "cube"
type = "cube"
edge = 1
[[particle]]
label = "box"
shape = "cube"
material = "rock"
position = [0, 0, 10]
[domain]
min = [-5, -5, 5]
max = [5, 5, 15]
[output]
series_every = 1
snapshot_every = 10
monitor = ["box"]
)";

struct Series {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name) const {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) -
                                    columns.begin());
  }
};

Series readSeries(const fs::path& path) {
  Series s;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) s.columns.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<double> values;
    for (std::string v; std::getline(row, v, ',');) values.push_back(std::stod(v));
    s.rows.push_back(values);
  }
  return s;
}

TEST(OutputLabels, FreeFallAtExactStepTimes) {
  log::setLevel(log::Level::kWarning);
  // One directory for all ranks: the snapshot files are written by all of them together.
  long pid = static_cast<long>(getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::temp_directory_path() / cat("polydem_free_fall_", pid, "_", mpi::size());
  run::RunOptions options;
  options.out_dir = dir.string();
  const run::RunResult result =
      run::runScene(scene::parseScene(kFreeFall, "free_fall.toml"), options, MPI_COMM_WORLD);
  ASSERT_EQ(result.steps, 50);
  if (mpi::rank() == 0) {
    const Series s = readSeries(dir / "series.csv");
    const double dt = 1e-3, g = 9.81, z0 = 10.0;
    ASSERT_EQ(s.rows.size(), 51u);  // step 0 and every step once, the last one not repeated
    ExactSum t;
    for (std::size_t k = 0; k < s.rows.size(); ++k) {
      const auto& row = s.rows[k];
      EXPECT_EQ(row[s.column("step")], static_cast<double>(k));
      EXPECT_EQ(row[s.column("time")], t.value()) << "row " << k;
      const double time = t.value();
      // Exact for a constant force up to rounding (the cube is 1 m: 1e-9 of its size).
      EXPECT_NEAR(row[s.column("box_z")], z0 - 0.5 * g * time * time, 1e-9) << "step " << k;
      if (k > 0) {
        EXPECT_NEAR(row[s.column("box_vz")], -g * (time - 0.5 * dt), 1e-9) << "step " << k;
      }
      EXPECT_EQ(row[s.column("box_x")], 0.0);
      t.add(dt);
    }
    // Snapshots 0, 10, ..., 50 (XDMF, the default format): named by the step they hold, each
    // file in place and listed in the collection.
    std::ifstream xmf(dir / "snapshots.xmf");
    const std::string text((std::istreambuf_iterator<char>(xmf)), std::istreambuf_iterator<char>());
    for (int step = 0; step <= 50; step += 10) {
      const std::string name = cat("snapshot_", std::string(10 - cat(step).size(), '0'), step);
      EXPECT_NE(text.find(name + ".h5:/mesh/points"), std::string::npos) << step << "\n" << text;
      EXPECT_TRUE(fs::is_regular_file(dir / "snapshots" / (name + ".h5"))) << name;
    }
    EXPECT_EQ(text.find("snapshot_0000000049"), std::string::npos) << text;
    EXPECT_EQ(text.find("snapshot_0000000009"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(dir / "snapshots.pvd"));  // the VTK files only on request
    fs::remove_all(dir);
  }
}

}  // namespace
}  // namespace polydem::sim
