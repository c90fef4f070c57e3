#include "polydem/output/vtk_writer.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdlib>
#include <filesystem>

#include "output/output_test_util.h"
#include "output/vtk_test_reader.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"

namespace polydem::output {
namespace {

namespace fs = std::filesystem;
using test::readPolyData;

ParticleFields fields(Uid uid, bool fixed = false) {
  ParticleFields f;
  f.uid = uid;
  f.velocity = Vec3(0.1 * uid, -2.0 / 3.0, 3.0);
  f.angular_velocity = Vec3(1e-300, -0.0, 7.0 * uid);
  f.displacement = Vec3(1.0 / 7.0, 2.5e7, -static_cast<double>(uid));
  f.fixed = fixed;
  return f;
}

void add(PolyhedraBatch& batch, const ParticleFields& f, const test::Mesh& mesh) {
  batch.addParticle(f, mesh.vertices, mesh.faces);
}

std::vector<test::XmlElement> elements(const std::string& path, const std::string& tag) {
  std::vector<test::XmlElement> out;
  for (auto& e : test::parseXml(test::readFile(path))) {
    if (e.tag == tag) out.push_back(std::move(e));
  }
  return out;
}

/// Expects `a` to hold `per_cell` repeated `count` times per group of cells.
void expectRepeated(const test::DataArray& a, const std::vector<std::vector<double>>& per_particle,
                    const std::vector<int>& faces_per_particle) {
  std::vector<double> expected;
  for (std::size_t p = 0; p < per_particle.size(); ++p) {
    for (int f = 0; f < faces_per_particle[p]; ++f) {
      expected.insert(expected.end(), per_particle[p].begin(), per_particle[p].end());
    }
  }
  ASSERT_EQ(a.values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.values[i], &expected[i], sizeof(double)), 0) << "value " << i;
  }
}

std::vector<double> flat(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

class VtkWriterEncodings : public ::testing::TestWithParam<VtkEncoding> {};

TEST_P(VtkWriterEncodings, CubeIsEightPointsSixQuadsWithItsDataOnEachFace) {
  const test::ScratchDir scratch("cube", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  SnapshotWriter writer(dir, MPI_COMM_SELF, {GetParam(), std::nullopt});
  const auto cube = test::box(Vec3(-0.5, 1.0 / 3.0, 2e-3), Vec3(1.0, 0.25, 1e-7));
  PolyhedraBatch batch;
  const auto f = fields(42, true);
  add(batch, f, cube);
  writer.write(0.125, 7, batch, nullptr);

  const auto piece = readPolyData(writer.particlePath(7, 0));
  EXPECT_EQ(piece.root.at("type"), "PolyData");
  EXPECT_EQ(piece.root.at("header_type"), "UInt64");
  EXPECT_EQ(piece.points, 8u);
  EXPECT_EQ(piece.polys, 6u);
  EXPECT_EQ(piece.verts, 0u);
  if (GetParam() == VtkEncoding::kBase64) {
    EXPECT_EQ(piece.appended_used, piece.appended_chars);  // blocks tile the appended data
  }

  const auto& points = piece.at("Points");
  EXPECT_EQ(points.section, "Points");
  ASSERT_EQ(points.values.size(), 24u);
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(points.values[3 * i + k], cube.vertices[i][k]);
  }
  const auto& offsets = piece.at("Polys/offsets");
  const auto& connectivity = piece.at("Polys/connectivity");
  ASSERT_EQ(offsets.ints.size(), 6u);
  ASSERT_EQ(connectivity.ints.size(), 24u);
  for (std::size_t face = 0; face < 6; ++face) {
    EXPECT_EQ(offsets.ints[face], 4 * (face + 1));
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(connectivity.ints[4 * face + k], static_cast<std::uint64_t>(cube.faces[face][k]));
    }
  }
  const std::vector<int> faces{6};
  EXPECT_EQ(piece.at("uid").type, "UInt64");
  EXPECT_EQ(piece.at("uid").ints, std::vector<std::uint64_t>(6, 42));
  EXPECT_EQ(piece.at("rank").ints, std::vector<std::uint64_t>(6, 0));
  EXPECT_EQ(piece.at("fixed").ints, std::vector<std::uint64_t>(6, 1));
  EXPECT_EQ(piece.at("velocity").components, 3);
  EXPECT_EQ(piece.at("velocity").section, "CellData");
  expectRepeated(piece.at("velocity"), {flat(f.velocity)}, faces);
  expectRepeated(piece.at("angular_velocity"), {flat(f.angular_velocity)}, faces);
  expectRepeated(piece.at("displacement"), {flat(f.displacement)}, faces);
  expectRepeated(piece.at("speed"), {{f.velocity.norm()}}, faces);
}

TEST_P(VtkWriterEncodings, EachFaceCarriesItsOwnJoint) {
  const test::ScratchDir scratch("joints", MPI_COMM_SELF);
  SnapshotWriter writer(scratch.path(), MPI_COMM_SELF, {GetParam(), std::nullopt});
  const auto cube = test::box(Vec3::Zero(), Vec3::Ones());
  PolyhedraBatch batch;
  batch.addParticle(fields(3), cube.vertices);
  const std::vector<std::int32_t> joints = {-1, 0, 2, -1, 7, 1};
  for (std::size_t f = 0; f < cube.faces.size(); ++f) batch.addFace(cube.faces[f], joints[f]);
  add(batch, fields(4), cube);  // faces added without a joint: on none
  writer.write(0.0, 1, batch, nullptr);

  const auto piece = readPolyData(writer.particlePath(1, 0));
  const auto& joint = piece.at("joint");
  EXPECT_EQ(joint.type, "Int32");
  EXPECT_EQ(joint.section, "CellData");
  std::vector<std::uint64_t> expected;
  for (const std::int32_t j : joints) expected.push_back(static_cast<std::uint64_t>(j));
  expected.resize(12, static_cast<std::uint64_t>(-1));
  EXPECT_EQ(joint.ints, expected);
}

INSTANTIATE_TEST_SUITE_P(Both, VtkWriterEncodings,
                         ::testing::Values(VtkEncoding::kBase64, VtkEncoding::kAscii));

TEST(VtkWriter, BinaryAndAsciiPiecesDecodeToTheSameBits) {
  const test::ScratchDir scratch("encodings", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  PolyhedraBatch batch;
  add(batch, fields(1), test::box(Vec3(0.1, 0.2, 0.3), Vec3(1, 2, 3)));
  add(batch, fields(2), test::hexagonalPrism(Vec3(5, 0, 0), 1.0 / 3.0, 2.0));
  SnapshotWriter binary(dir + "/b", MPI_COMM_SELF);
  SnapshotWriter ascii(dir + "/a", MPI_COMM_SELF, {VtkEncoding::kAscii, std::nullopt});
  binary.write(1.0, 1, batch, nullptr);
  ascii.write(1.0, 1, batch, nullptr);
  const auto b = readPolyData(binary.particlePath(1, 0));
  const auto a = readPolyData(ascii.particlePath(1, 0));
  ASSERT_EQ(a.arrays.size(), b.arrays.size());
  for (const auto& [name, array] : b.arrays) {
    const auto& other = a.at(name);
    EXPECT_EQ(array.type, other.type) << name;
    ASSERT_EQ(array.values.size(), other.values.size()) << name;
    EXPECT_EQ(
        std::memcmp(array.values.data(), other.values.data(), array.values.size() * sizeof(double)),
        0)
        << name;
  }
  // The binary file is the smaller one (the point of choosing it).
  EXPECT_LT(fs::file_size(binary.particlePath(1, 0)), fs::file_size(ascii.particlePath(1, 0)));
}

TEST(VtkWriter, LaterParticlesIndexTheirOwnPoints) {
  const test::ScratchDir scratch("two", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  const auto cube = test::box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const auto tet = test::tetrahedron(Vec3(3, 0, 0), 2.0);
  PolyhedraBatch batch;
  add(batch, fields(5), cube);
  add(batch, fields(9), tet);
  SnapshotWriter writer(dir, MPI_COMM_SELF);
  writer.write(0.0, 0, batch, nullptr);
  const auto piece = readPolyData(writer.particlePath(0, 0));
  EXPECT_EQ(piece.points, 12u);
  EXPECT_EQ(piece.polys, 10u);
  const auto& connectivity = piece.at("Polys/connectivity").ints;
  const auto& offsets = piece.at("Polys/offsets").ints;
  ASSERT_EQ(offsets.size(), 10u);
  EXPECT_EQ(offsets.back(), 24u + 12u);
  for (std::size_t f = 0; f < 4; ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(connectivity[24 + 3 * f + k], 8u + static_cast<std::uint64_t>(tet.faces[f][k]));
    }
  }
  std::vector<std::uint64_t> uids(6, 5);
  uids.insert(uids.end(), 4, 9);
  EXPECT_EQ(piece.at("uid").ints, uids);
  expectRepeated(piece.at("velocity"), {flat(fields(5).velocity), flat(fields(9).velocity)},
                 {6, 4});
}

TEST(VtkWriter, CollectionsListExistingFilesInTimeOrderAndAStepOnce) {
  const test::ScratchDir scratch("pvd", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  SnapshotWriter writer(dir, MPI_COMM_SELF);
  PolyhedraBatch batch;
  add(batch, fields(1), test::box(Vec3(0, 0, 0), Vec3(1, 1, 1)));
  const std::vector<std::pair<std::int64_t, double>> steps{{0, 0.0}, {10, 0.1}, {20, 0.2}};
  for (const auto& [step, time] : steps) writer.write(time, step, batch, nullptr);
  writer.write(0.2, 20, batch, nullptr);  // a step written twice is listed once

  const auto sets = elements(writer.particleCollectionPath(), "DataSet");
  ASSERT_EQ(sets.size(), steps.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(std::stod(sets[i].attributes.at("timestep")), steps[i].second);
    const std::string pvtp = dir + "/" + sets[i].attributes.at("file");
    EXPECT_EQ(pvtp, writer.particlePath(steps[i].first));
    ASSERT_TRUE(fs::exists(pvtp)) << pvtp;
    const auto pieces = elements(pvtp, "Piece");
    ASSERT_EQ(pieces.size(), 1u);
    const auto source = fs::path(pvtp).parent_path() / pieces[0].attributes.at("Source");
    EXPECT_TRUE(fs::exists(source)) << source;
    // The header declares exactly the arrays the piece holds, with the same types.
    const auto piece = readPolyData(source);
    for (const auto& declared : elements(pvtp, "PDataArray")) {
      const auto& a = piece.at(declared.attributes.at("Name"));
      EXPECT_EQ(declared.attributes.at("type"), a.type);
      EXPECT_EQ(std::stoi(declared.attributes.at("NumberOfComponents")), a.components);
    }
    EXPECT_EQ(elements(pvtp, "PDataArray").size(), piece.arrays.size() - 2);  // + Polys arrays
  }
  EXPECT_TRUE(elements(writer.contactCollectionPath(), "DataSet").empty());
  for (const auto& entry : fs::directory_iterator(dir + "/snapshots")) {
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }
}

TEST(VtkWriter, ResumingKeepsTheSnapshotsUpToTheCheckpoint) {
  const test::ScratchDir scratch("resume", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  PolyhedraBatch batch;
  add(batch, fields(1), test::tetrahedron(Vec3(0, 0, 0), 1.0));
  ContactBatch contacts;
  contacts.contacts.push_back({1, 2, Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, Vec3::Zero()});
  {
    SnapshotWriter first(dir, MPI_COMM_SELF);
    for (std::int64_t step : {0, 10, 20, 30}) first.write(step * 0.5, step, batch, &contacts);
  }
  SnapshotWriter resumed(dir, MPI_COMM_SELF, {VtkEncoding::kBase64, 10});
  for (const auto& path : {resumed.particleCollectionPath(), resumed.contactCollectionPath()}) {
    EXPECT_EQ(elements(path, "DataSet").size(), 2u) << path;
  }
  resumed.write(7.5, 15, batch, nullptr);
  const auto sets = elements(resumed.particleCollectionPath(), "DataSet");
  ASSERT_EQ(sets.size(), 3u);
  EXPECT_EQ(sets[2].attributes.at("timestep"), "7.5");
  EXPECT_EQ(elements(resumed.contactCollectionPath(), "DataSet").size(), 2u);

  // A fresh writer in the same directory starts empty collections.
  SnapshotWriter fresh(dir, MPI_COMM_SELF);
  EXPECT_TRUE(elements(fresh.particleCollectionPath(), "DataSet").empty());
}

TEST(VtkWriter, ContactsArePointsWithTheirForces) {
  const test::ScratchDir scratch("contacts", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  ContactBatch contacts;
  contacts.contacts.push_back(
      {3, 8, Vec3(0.5, 0.25, -5e-6), Vec3(0, 0, 1), 1.5e4, Vec3(-2.0, 1.0 / 3.0, 0)});
  contacts.contacts.push_back({4, 5, Vec3(1, 2, 3), Vec3(0.6, 0.8, 0), 0.0, Vec3::Zero()});
  SnapshotWriter writer(dir, MPI_COMM_SELF);
  writer.write(2.0, 4, PolyhedraBatch{}, &contacts);
  const auto sets = elements(writer.contactCollectionPath(), "DataSet");
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(dir + "/" + sets[0].attributes.at("file"), writer.contactPath(4));
  const auto piece = readPolyData(writer.contactPath(4, 0));
  EXPECT_EQ(piece.points, 2u);
  EXPECT_EQ(piece.verts, 2u);
  EXPECT_EQ(piece.polys, 0u);
  EXPECT_EQ(piece.at("Verts/connectivity").ints, (std::vector<std::uint64_t>{0, 1}));
  EXPECT_EQ(piece.at("Verts/offsets").ints, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(piece.at("uid_a").ints, (std::vector<std::uint64_t>{3, 4}));
  EXPECT_EQ(piece.at("uid_b").ints, (std::vector<std::uint64_t>{8, 5}));
  EXPECT_EQ(piece.at("normal_force").values, (std::vector<double>{1.5e4, 0.0}));
  EXPECT_EQ(piece.at("normal").section, "PointData");
  std::vector<double> points, normals, shear;
  for (const auto& c : contacts.contacts) {
    for (int k = 0; k < 3; ++k) {
      points.push_back(c.point[k]);
      normals.push_back(c.normal[k]);
      shear.push_back(c.shear_force[k]);
    }
  }
  EXPECT_EQ(piece.at("Points").values, points);
  EXPECT_EQ(piece.at("normal").values, normals);
  EXPECT_EQ(piece.at("shear_force").values, shear);
  // No particles on this rank: an empty but valid particle piece.
  const auto particles = readPolyData(writer.particlePath(4, 0));
  EXPECT_EQ(particles.points, 0u);
  EXPECT_EQ(particles.polys, 0u);
  EXPECT_TRUE(particles.at("uid").values.empty());
}

TEST(VtkWriter, RejectsFacesThatAreNotPolygonsOfTheParticle) {
  PolyhedraBatch batch;
  const std::vector<int> face{0, 1, 2};
  EXPECT_THROW(batch.addFace(face), Error);  // no particle yet
  const auto tet = test::tetrahedron(Vec3(0, 0, 0), 1.0);
  batch.addParticle(fields(1), tet.vertices);
  const std::vector<int> out_of_range{0, 1, 4}, too_short{0, 1};
  EXPECT_THROW(batch.addFace(out_of_range), Error);
  EXPECT_THROW(batch.addFace(too_short), Error);
  batch.addFace(face);
  EXPECT_EQ(batch.faceCount(), 1u);
}

TEST(VtkWriter, FailureNamesThePathAndLeavesTheCollectionAsItWas) {
  const test::ScratchDir scratch("fail", MPI_COMM_SELF);
  const std::string& dir = scratch.path();
  SnapshotWriter writer(dir, MPI_COMM_SELF);
  PolyhedraBatch batch;
  add(batch, fields(1), test::tetrahedron(Vec3(0, 0, 0), 1.0));
  writer.write(0.0, 0, batch, nullptr);
  // A directory where the temporary piece should go: it cannot be created.
  fs::create_directories(writer.particlePath(5, 0) + ".tmp");
  try {
    writer.write(1.0, 5, batch, nullptr);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(writer.particlePath(5, 0)), std::string::npos) << e.what();
  }
  EXPECT_EQ(elements(writer.particleCollectionPath(), "DataSet").size(), 1u);
  EXPECT_FALSE(fs::exists(writer.particlePath(5)));

  // A file where the snapshot directory should be.
  const std::string blocked = dir + "/blocked";
  fs::create_directories(blocked);
  std::ofstream(blocked + "/snapshots") << "not a directory";
  try {
    SnapshotWriter bad(blocked, MPI_COMM_SELF);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(blocked + "/snapshots"), std::string::npos) << e.what();
  }
}

TEST(VtkWriterParallel, EveryRankWritesItsPieceAndRankZeroListsThemAll) {
  const test::ScratchDir scratch("parallel", MPI_COMM_WORLD);
  const std::string& dir = scratch.path();
  const int rank = mpi::rank(), size = mpi::size();
  SnapshotWriter writer(dir, MPI_COMM_WORLD);
  PolyhedraBatch batch;
  // Rank r holds r + 1 cubes, uids r * 100 + k.
  for (int k = 0; k <= rank; ++k) {
    add(batch, fields(static_cast<Uid>(rank * 100 + k)),
        test::box(Vec3(2.0 * k, 2.0 * rank, 0), Vec3(1, 1, 1)));
  }
  ContactBatch contacts;
  contacts.contacts.push_back(
      {static_cast<Uid>(rank), 99, Vec3(rank, 0, 0), Vec3(0, 0, 1), 1.0, Vec3::Zero()});
  writer.write(0.5, 3, batch, rank == 0 ? &contacts : nullptr);
  MPI_Barrier(MPI_COMM_WORLD);

  for (const auto& [pvtp, pvd] :
       {std::pair{writer.particlePath(3), writer.particleCollectionPath()},
        std::pair{writer.contactPath(3), writer.contactCollectionPath()}}) {
    ASSERT_EQ(elements(pvd, "DataSet").size(), 1u);
    const auto pieces = elements(pvtp, "Piece");
    ASSERT_EQ(pieces.size(), static_cast<std::size_t>(size));
    for (int r = 0; r < size; ++r) {
      const auto source = fs::path(pvtp).parent_path() / pieces[r].attributes.at("Source");
      EXPECT_TRUE(fs::exists(source)) << source;
    }
  }
  // Each piece holds its rank's particles only.
  for (int r = 0; r < size; ++r) {
    const auto piece = readPolyData(writer.particlePath(3, r));
    EXPECT_EQ(piece.points, 8u * (r + 1));
    EXPECT_EQ(piece.at("rank").ints, std::vector<std::uint64_t>(6 * (r + 1), r));
    EXPECT_EQ(piece.at("uid").ints[0], static_cast<std::uint64_t>(r * 100));
    const auto contact_piece = readPolyData(writer.contactPath(3, r));
    EXPECT_EQ(contact_piece.points, r == 0 ? 1u : 0u);  // null contacts: an empty piece
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// Writes a small run for tests/output/check_vtk_files.py (an independent check with Python's XML
// and base64 modules) when POLYDEM_VTK_SAMPLE_DIR is set; skipped otherwise.
TEST(VtkSample, WritesASampleRunForTheExternalCheck) {
  const char* target = std::getenv("POLYDEM_VTK_SAMPLE_DIR");
  if (!target) GTEST_SKIP() << "POLYDEM_VTK_SAMPLE_DIR not set";
  const int rank = mpi::rank(), size = mpi::size();
  if (rank == 0) fs::remove_all(target);
  MPI_Barrier(MPI_COMM_WORLD);
  SnapshotWriter writer(target, MPI_COMM_WORLD);
  const std::vector<test::Mesh> meshes{test::box(Vec3(0, 0, 0), Vec3(1, 0.5, 0.25)),
                                       test::tetrahedron(Vec3(2, 0, 0), 1.0),
                                       test::hexagonalPrism(Vec3(4, 0, 0), 0.5, 2.0),
                                       test::box(Vec3(-10, -10, -1), Vec3(20, 20, 1))};
  for (std::int64_t step = 0; step <= 20; step += 10) {
    PolyhedraBatch batch;
    ContactBatch contacts;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      if (static_cast<int>(i) % size != rank) continue;
      test::Mesh moved = meshes[i];
      for (auto& v : moved.vertices) v += Vec3(0, 0, 0.01 * step);
      add(batch, fields(i + 1, i == 3), moved);
      contacts.contacts.push_back(
          {i + 1, 4, moved.vertices[0], Vec3(0, 0, 1), 10.0 * step, Vec3(0.5, 0, 0)});
    }
    // Contacts from rank 0 only: the other ranks' contact pieces are empty, as in a real run
    // where a rank holds no contact.
    writer.write(1e-3 * step, step, batch, rank == 0 ? &contacts : nullptr);
  }
}

}  // namespace
}  // namespace polydem::output
