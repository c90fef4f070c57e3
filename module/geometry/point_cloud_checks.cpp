#include "polydem/geometry/point_cloud_checks.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/core/tolerance.h"

namespace polydem::geometry {

namespace {

void checkCount(std::span<const Vec3> points) {
  if (points.size() < 4) {
    throw GeometryError("a convex polyhedron needs at least 4 points, got " +
                        std::to_string(points.size()));
  }
}

void checkFinite(std::span<const Vec3> points) {
  std::vector<int> bad;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) bad.push_back(static_cast<int>(i));
  }
  if (!bad.empty()) {
    throw GeometryError(
        "point(s) " + formatIndices(bad) +
        " have a NaN or infinite coordinate (first: " + formatPoint(points[bad.front()]) + ")");
  }
}

CloudFrame boundingFrame(std::span<const Vec3> points) {
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {0.5 * (lo + hi), (hi - lo).norm()};
}

/// Pairs closer than `tol`: sweep over the points sorted by x, so O(n log n) for sane clouds.
void checkDuplicates(std::span<const Vec3> points, double size) {
  const double tol = absTol(size, RelTol::kPoint);
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return points[a].x() < points[b].x() || (points[a].x() == points[b].x() && a < b);
  });
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      if (points[order[j]].x() - points[order[i]].x() > tol) break;
      if ((points[order[j]] - points[order[i]]).norm() <= tol) {
        pairs.emplace_back(std::min(order[i], order[j]), std::max(order[i], order[j]));
      }
    }
  }
  if (pairs.empty()) return;
  std::sort(pairs.begin(), pairs.end());
  std::ostringstream msg;
  msg << "duplicate points (closer than " << RelTol::kPoint << " of the cloud size " << size
      << "):";
  const std::size_t shown = std::min<std::size_t>(pairs.size(), 6);
  for (std::size_t k = 0; k < shown; ++k) {
    msg << (k ? "," : "") << " points " << pairs[k].first << " and " << pairs[k].second;
  }
  if (shown < pairs.size()) msg << ", ... (" << pairs.size() << " pairs in all)";
  msg << " at " << formatPoint(points[pairs[0].first]);
  throw GeometryError(msg.str());
}

/// All points within tol of their least-squares plane. The plane comes from the covariance about
/// the mean; its normal is accurate to round-off relative to the cloud size even for very thin
/// clouds, which is all a 1e-10 relative test needs. (Slightly thicker clouds whose least-squares
/// plane is not their thinnest direction are caught after the hull is built.)
void checkNotFlat(std::span<const Vec3> points, const CloudFrame& frame) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += (p - frame.centre) / frame.size;
  mean /= static_cast<double>(points.size());
  Mat3 cov = Mat3::Zero();
  for (const Vec3& p : points) {
    const Vec3 d = (p - frame.centre) / frame.size - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
  const Vec3 normal = eig.eigenvectors().col(0);
  double thickness = 0.0;
  for (const Vec3& p : points) {
    const Vec3 d = (p - frame.centre) / frame.size - mean;
    thickness = std::max(thickness, std::abs(normal.dot(d)));
  }
  if (thickness <= RelTol::kPlane) {
    std::vector<int> all(points.size());
    std::iota(all.begin(), all.end(), 0);
    std::ostringstream msg;
    msg << "flat point cloud: all " << points.size() << " points (" << formatIndices(all)
        << ") lie within " << thickness * frame.size << " of one plane with normal "
        << formatPoint(normal) << " (less than " << RelTol::kPlane << " of the cloud size "
        << frame.size << "), so they enclose no volume";
    throw GeometryError(msg.str());
  }
}

}  // namespace

CloudFrame checkPointCloud(std::span<const Vec3> points) {
  checkCount(points);
  checkFinite(points);
  const CloudFrame frame = boundingFrame(points);
  checkDuplicates(points, frame.size);  // also catches a cloud of identical points (size 0)
  checkNotFlat(points, frame);
  return frame;
}

std::string formatIndices(std::span<const int> indices, std::size_t max_shown) {
  std::string out;
  const std::size_t shown = std::min(indices.size(), max_shown);
  for (std::size_t k = 0; k < shown; ++k) {
    if (k) out += ", ";
    out += std::to_string(indices[k]);
  }
  if (shown < indices.size()) out += ", ... (" + std::to_string(indices.size()) + " in all)";
  return out;
}

std::string formatPoint(const Vec3& p) {
  return cat("(", p.x(), ", ", p.y(), ", ", p.z(), ")");
}

}  // namespace polydem::geometry
