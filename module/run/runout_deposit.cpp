// The deposit of a runout (run/runout.h): the failed mass, its runout and travel, and the
// thickness map from the blocks' convex geometry.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/run/runout.h"
#include "polydem/sim/simulation.h"

namespace polydem::run {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One particle's pose, to gather over the ranks.
struct DepositRow {
  Uid uid;
  int shape, free;
  double x, y, z, qw, qx, qy, qz;
};

// A body placed in the world: its face planes n . p <= d and its horizontal bounding box.
struct Placed {
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  std::vector<Vec3> vertices;
  double xlo = kInf, xhi = -kInf, ylo = kInf, yhi = -kInf;
};

Placed place(const geometry::BodyShape& shape, const Vec3& c, const Quat& q) {
  Placed b;
  const Mat3 r = q.toRotationMatrix();
  for (const Vec3& v : shape.polyhedron->vertices()) {
    const Vec3 w = c + r * v;
    b.vertices.push_back(w);
    b.xlo = std::min(b.xlo, w.x());
    b.xhi = std::max(b.xhi, w.x());
    b.ylo = std::min(b.ylo, w.y());
    b.yhi = std::max(b.yhi, w.y());
  }
  for (const auto& f : shape.polyhedron->faces()) {
    const Vec3 n = r * f.normal;
    b.normals.push_back(n);
    b.offsets.push_back(f.offset + n.dot(c));
  }
  return b;
}

// Where the vertical line through (x, y) crosses a convex body: [lo, hi], or false if it misses.
bool verticalExtent(const Placed& b, double x, double y, double& lo, double& hi) {
  if (x < b.xlo || x > b.xhi || y < b.ylo || y > b.yhi) return false;
  constexpr double kFlat = 1e-12;  // a face this close to vertical bounds x and y only
  lo = -kInf;
  hi = kInf;
  for (std::size_t f = 0; f < b.normals.size(); ++f) {
    const Vec3& n = b.normals[f];
    const double rest = b.offsets[f] - n.x() * x - n.y() * y;  // n_z z <= rest
    if (n.z() > kFlat) {
      hi = std::min(hi, rest / n.z());
    } else if (n.z() < -kFlat) {
      lo = std::max(lo, rest / n.z());
    } else if (rest < 0.0) {
      return false;
    }
  }
  return lo <= hi;
}

std::vector<DepositRow> gatherDepositRows(const sim::Simulation& sim) {
  std::vector<DepositRow> mine;
  const auto& storage = sim.particles();
  const bool root = mpi::rank(sim.comm()) == 0;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (p.isGlobal() && !root) continue;  // replicated: once
    const Vec3 c = p.position + storage.shift(i);
    const Quat& q = p.orientation;
    mine.push_back(
        {p.uid, p.shape, p.isFree() ? 1 : 0, c.x(), c.y(), c.z(), q.w(), q.x(), q.y(), q.z()});
  }
  auto all = mpi::allgatherv(mine, sim.comm());
  std::sort(all.begin(), all.end(),
            [](const DepositRow& a, const DepositRow& b) { return a.uid < b.uid; });
  return all;
}

// The top of the failed mass and of the ground under it on the vertical line through (x, y);
// false if no failed block is over it. Without ground under it, the failed mass's own bottom.
bool column(const std::vector<Placed>& failed, const std::vector<Placed>& ground, double x,
            double y, double& top, double& base, bool& has_ground) {
  double lo = 0.0, hi = 0.0, bottom = kInf;
  top = -kInf;
  for (const Placed& b : failed) {
    if (!verticalExtent(b, x, y, lo, hi)) continue;
    top = std::max(top, hi);
    bottom = std::min(bottom, lo);
  }
  if (top == -kInf) return false;
  double ground_top = -kInf;
  for (const Placed& b : ground) {
    // The ground under the failed mass: a body whose top is below the mass's top.
    if (verticalExtent(b, x, y, lo, hi) && hi <= top) ground_top = std::max(ground_top, hi);
  }
  has_ground = ground_top > -kInf;
  base = has_ground ? ground_top : bottom;
  return true;
}

// The grid of the thickness map over the failed blocks, and each cell's measures. The grid's
// lines lie on multiples of the cell size (a scene's round coordinates fall on them); a cell's
// thickness is the mean over kSubSamples x kSubSamples points of it (the cell's share of the
// failed mass, so that the map integrates to its volume), its top and ground those at its centre.
void thicknessMap(const std::vector<Placed>& failed, const std::vector<Placed>& ground,
                  RunoutDeposit& d) {
  constexpr int kSubSamples = 4;
  double xlo = kInf, xhi = -kInf, ylo = kInf, yhi = -kInf;
  for (const Placed& b : failed) {
    xlo = std::min(xlo, b.xlo);
    xhi = std::max(xhi, b.xhi);
    ylo = std::min(ylo, b.ylo);
    yhi = std::max(yhi, b.yhi);
  }
  const double h = d.cell;
  d.x0 = std::floor(xlo / h) * h;
  d.y0 = std::floor(ylo / h) * h;
  d.nx = std::max(1, static_cast<int>(std::ceil((xhi - d.x0) / h)));
  d.ny = std::max(1, static_cast<int>(std::ceil((yhi - d.y0) / h)));
  const Vec3 across(-d.direction.y(), d.direction.x(), 0.0);
  double along_lo = kInf, along_hi = -kInf, across_lo = kInf, across_hi = -kInf;
  for (int j = 0; j < d.ny; ++j) {
    for (int i = 0; i < d.nx; ++i) {
      ThicknessCell c{i, j, d.x0 + (i + 0.5) * h, d.y0 + (j + 0.5) * h};
      double sum = 0.0, top = 0.0, base = 0.0;
      bool has_ground = false, any = false;
      for (int a = 0; a < kSubSamples; ++a) {
        for (int b = 0; b < kSubSamples; ++b) {
          const double x = c.x + ((a + 0.5) / kSubSamples - 0.5) * h;
          const double y = c.y + ((b + 0.5) / kSubSamples - 0.5) * h;
          if (!column(failed, ground, x, y, top, base, has_ground)) continue;
          any = true;
          sum += std::max(0.0, top - base);
        }
      }
      if (!any) continue;  // no failed block over this cell
      c.thickness = sum / (kSubSamples * kSubSamples);
      if (column(failed, ground, c.x, c.y, top, base, has_ground)) {
        c.top = top;
        c.ground = base;
        c.has_ground = has_ground;
      } else {  // the mass covers part of the cell only: its top over the ground's
        c.top = c.ground = std::nan("");
      }
      d.cells.push_back(c);
      if (!(c.thickness > kThinFraction * h)) continue;
      d.area += h * h;
      d.volume += c.thickness * h * h;
      d.max_thickness = std::max(d.max_thickness, c.thickness);
      for (const double sx : {-0.5, 0.5}) {
        for (const double sy : {-0.5, 0.5}) {
          const Vec3 corner(c.x + sx * h, c.y + sy * h, 0.0);
          along_lo = std::min(along_lo, corner.dot(d.direction));
          along_hi = std::max(along_hi, corner.dot(d.direction));
          across_lo = std::min(across_lo, corner.dot(across));
          across_hi = std::max(across_hi, corner.dot(across));
        }
      }
    }
  }
  if (d.area > 0.0) {
    d.length = along_hi - along_lo;
    d.width = across_hi - across_lo;
  }
}

}  // namespace

RunoutDeposit measureDeposit(const sim::Simulation& sim, double cell) {
  RunoutDeposit d;
  const auto& shapes = sim.shapes();
  std::vector<const setup::ParticleSpec*> spec_of;
  for (const auto& p : sim.scene().particles) {
    if (p.uid >= spec_of.size()) spec_of.resize(p.uid + 1, nullptr);
    spec_of[p.uid] = &p;
  }
  std::vector<Placed> failed, ground;
  std::vector<double> sizes;
  Vec3 sum = Vec3::Zero();
  double toe = -kInf;
  std::vector<Placed> failed_start;
  for (const DepositRow& r : gatherDepositRows(sim)) {
    const auto& shape = shapes[r.shape];
    const Vec3 c(r.x, r.y, r.z);
    const Quat q(r.qw, r.qx, r.qy, r.qz);
    Placed now = place(shape, c, q);
    if (!r.free) {
      ground.push_back(std::move(now));
      continue;
    }
    ++d.free_blocks;
    const setup::ParticleSpec* spec = r.uid < spec_of.size() ? spec_of[r.uid] : nullptr;
    const Vec3 c0 = spec ? sim.initialCentroid(*spec) : c;
    const double travel = (c - c0).norm(), size = std::cbrt(shape.volume);
    if (travel > d.max_travel) {
      d.max_travel = travel;
      d.max_travel_uid = r.uid;
    }
    if (!spec || travel < kMovedFraction * size) {
      ground.push_back(std::move(now));  // standing rock: part of the ground
      continue;
    }
    ++d.failed_blocks;
    d.failed_volume += shape.volume;
    sizes.push_back(size);
    sum += Vec3(c.x() - c0.x(), c.y() - c0.y(), 0.0);
    failed_start.push_back(place(shape, c0, sim.initialOrientation(*spec)));
    failed.push_back(std::move(now));
  }
  if (failed.empty()) return d;
  if (sum.norm() > 0.0) d.direction = sum.normalized();
  for (const Placed& b : failed_start) {
    for (const Vec3& v : b.vertices) toe = std::max(toe, v.dot(d.direction));
  }
  double front = -kInf;
  for (const Placed& b : failed) {
    for (const Vec3& v : b.vertices) front = std::max(front, v.dot(d.direction));
  }
  d.toe_start = toe;
  d.front_end = front;
  d.runout = front - toe;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  d.cell = cell > 0.0 ? cell : kCellFraction * sizes[sizes.size() / 2];
  thicknessMap(failed, ground, d);
  return d;
}

std::string thicknessCsv(const RunoutDeposit& d) {
  std::ostringstream out;
  out << "i,j,x,y,ground,top,thickness\n";
  for (const ThicknessCell& c : d.cells) {
    out << c.i << ',' << c.j << ',' << num(c.x) << ',' << num(c.y) << ',' << num(c.ground) << ','
        << num(c.top) << ',' << num(c.thickness) << '\n';
  }
  return out.str();
}

}  // namespace polydem::run
