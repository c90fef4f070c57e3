// Water pressure on the joint faces of the free blocks (water.h).
#include "polydem/sim/water.h"

#include <algorithm>
#include <optional>

#include "polydem/core/error.h"
#include "polydem/geometry/plan_triangulation.h"

namespace polydem::sim {

namespace {

// The triangles of a surface through four points or more: as given, else Delaunay's.
std::vector<geometry::PlanTriangle> trianglesOf(const setup::WaterSurfaceSpec& spec) {
  if (!spec.triangles.empty()) return spec.triangles;
  auto t = geometry::delaunayTriangulation(spec.points);
  if (!t.error.empty()) throw InputError("", 0, "[water] points: " + t.error);
  return std::move(t.triangles);
}

// One surface at one time, and its pressure about one point (a block's centroid).
class SurfaceNow {
 public:
  SurfaceNow(const setup::WaterSurfaceSpec& spec, double unit_weight, double time)
      : dry_(spec.dry), unit_weight_(unit_weight) {
    if (dry_) return;
    if (spec.points.size() <= 3) {
      plane_ = phreaticSurface(spec, time);
      return;
    }
    std::vector<double> z;
    surfaceHeights(spec, time, z);
    const auto triangles = trianglesOf(spec);
    partition_.emplace(spec.points, triangles);
    for (std::size_t c = 0; c < partition_->cellCount(); ++c) {
      cell_planes_.push_back(partition_->plane(c, z));
    }
    cell_pressure_.resize(cell_planes_.size());
  }

  bool dry() const { return dry_; }

  void about(const Vec3& c) {
    if (dry_) return;
    if (!partition_) {
      pressure_ = hydrostaticPressure(plane_, unit_weight_, c);
      return;
    }
    for (std::size_t k = 0; k < cell_planes_.size(); ++k) {
      cell_pressure_[k] = hydrostaticPressure(cell_planes_[k], unit_weight_, c);
    }
  }

  geometry::PressureResultant on(std::span<const Vec3> vertices, std::span<const int> face,
                                 const Vec3& normal) const {
    if (!partition_) return geometry::pressureResultant(vertices, face, normal, pressure_);
    return partition_->resultant(vertices, face, normal, cell_pressure_);
  }

 private:
  bool dry_;
  double unit_weight_;
  geometry::PlanPlane plane_;  // a level or three points
  geometry::LinearPressure pressure_;
  std::optional<geometry::PlanPartition> partition_;  // four points or more
  std::vector<geometry::PlanPlane> cell_planes_;
  std::vector<geometry::LinearPressure> cell_pressure_;
};

// The [water] surfaces at one time: the global one (0) and each [[water.joint]]'s (1, 2, ...),
// and which acts on the faces of each joint plane.
class WaterNow {
 public:
  WaterNow(const setup::WaterSpec& water, double time) {
    surfaces_.emplace_back(water, water.unit_weight, time);
    for (std::size_t j = 0; j < water.joints.size(); ++j) {
      surfaces_.emplace_back(water.joints[j].surface, water.unit_weight, time);
      for (const int plane : water.joints[j].planes) {
        const auto k = static_cast<std::size_t>(plane);
        if (surface_of_plane_.size() <= k) surface_of_plane_.resize(k + 1, 0);
        surface_of_plane_[k] = j + 1;
      }
    }
  }

  void about(const Vec3& c) {
    for (auto& s : surfaces_) s.about(c);
  }

  // The surface on the faces of joint plane `plane`, nullptr where they are dry.
  const SurfaceNow* on(int plane) const {
    const auto k = static_cast<std::size_t>(plane);
    const SurfaceNow& s = surfaces_[k < surface_of_plane_.size() ? surface_of_plane_[k] : 0];
    return s.dry() ? nullptr : &s;
  }

 private:
  std::vector<SurfaceNow> surfaces_;
  std::vector<std::size_t> surface_of_plane_;
};

}  // namespace

void surfaceHeights(const setup::WaterSurfaceSpec& water, double time, std::vector<double>& z) {
  // The rows to blend, linear between them; held at the first and last.
  const auto& t = water.times;
  std::size_t lo = 0, hi = 0;
  double s = 0.0;  // the weight of row `hi`
  if (time >= t.back()) {
    lo = hi = t.size() - 1;
  } else if (time > t.front()) {
    hi = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
    lo = hi - 1;  // t[lo] <= time < t[hi]
    s = (time - t[lo]) / (t[hi] - t[lo]);
  }
  z.resize(water.heights[lo].size());
  for (std::size_t i = 0; i < z.size(); ++i) {
    z[i] = water.heights[lo][i] + s * (water.heights[hi][i] - water.heights[lo][i]);
  }
}

geometry::PlanPlane phreaticSurface(const setup::WaterSurfaceSpec& water, double time) {
  std::vector<double> z;
  surfaceHeights(water, time, z);
  geometry::PlanPlane s;
  if (water.points.empty()) {
    s.height = z[0];
    return s;
  }
  // The plane through the three points (x_i, y_i, z_i): solve for the slopes from the two
  // differences to the first point (Cramer's rule; the reader refused collinear points).
  const auto& p = water.points;
  const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1], uz = z[1] - z[0];
  const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1], vz = z[2] - z[0];
  const double det = ux * vy - uy * vx;
  s.x0 = p[0][0];
  s.y0 = p[0][1];
  s.height = z[0];
  s.slope_x = (uz * vy - uy * vz) / det;
  s.slope_y = (ux * vz - uz * vx) / det;
  return s;
}

geometry::LinearPressure hydrostaticPressure(const geometry::PlanPlane& surface, double unit_weight,
                                             const Vec3& c) {
  geometry::LinearPressure pressure;
  pressure.origin = c;
  pressure.value = unit_weight * (surface.at(c.x(), c.y()) - c.z());
  pressure.gradient = unit_weight * Vec3(surface.slope_x, surface.slope_y, -1.0);
  return pressure;
}

geometry::PressureResultant waterOnFace(const setup::WaterSurfaceSpec& surface, double unit_weight,
                                        double time, std::span<const Vec3> vertices,
                                        std::span<const int> face, const Vec3& normal,
                                        const Vec3& c) {
  SurfaceNow now(surface, unit_weight, time);
  if (now.dry()) return {};
  now.about(c);
  return now.on(vertices, face, normal);
}

void faceWaterPressures(const setup::WaterSpec& water, double time,
                        const geometry::BodyShape& shape, std::span<const Vec3> vertices,
                        std::span<const Vec3> normals, const Vec3& centroid,
                        std::vector<double>& out) {
  const auto& faces = shape.polyhedron->faces();
  out.assign(faces.size(), 0.0);
  if (shape.face_plane.empty()) return;
  WaterNow now(water, time);
  now.about(centroid);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (shape.face_plane[f] < 0) continue;
    const SurfaceNow* surface = now.on(shape.face_plane[f]);
    if (!surface) continue;
    const auto r = surface->on(vertices, faces[f].vertices, normals[f]);
    out[f] = r.load / faces[f].area;
  }
}

void addWaterForces(const setup::WaterSpec& water, double time, const particles::ShapeTable& shapes,
                    const particles::ParticleStorage& particles,
                    std::span<dynamics::ForceAccumulator> forces) {
  WaterNow now(water, time);
  for (std::size_t i = 0; i < forces.size(); ++i) {
    const auto& p = particles[i];
    const geometry::BodyShape& shape = shapes[p.shape];
    if (!p.isFree() || shape.face_plane.empty()) continue;
    // p(x) = gamma_w (z_surface(x, y) - z), about the block's centroid.
    now.about(particles.placedPosition(i));
    const auto vertices = particles.worldVertices(i);
    const auto normals = particles.worldFaceNormals(i);
    const auto& faces = shape.polyhedron->faces();
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (shape.face_plane[f] < 0) continue;
      const SurfaceNow* surface = now.on(shape.face_plane[f]);
      if (!surface) continue;
      const auto r = surface->on(vertices, faces[f].vertices, normals[f]);
      if (r.load > 0.0) forces[i].addPair(r.force, r.moment);
    }
  }
}

}  // namespace polydem::sim
