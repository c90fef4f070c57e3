// A convex set given by half-spaces a_i . x <= d_i with unit normals a_i (for instance the faces
// of one or two placed polyhedra), stored as structure of arrays so that loops over the planes
// vectorise. The arrays keep their capacity across clear(): a set reused for every pair
// allocates nothing once it has held the largest pair.
#pragma once

#include <vector>

#include "polydem/core/types.h"

namespace polydem::geometry {

class Halfspaces {
 public:
  void clear() {
    ax_.clear();
    ay_.clear();
    az_.clear();
    d_.clear();
  }
  void reserve(std::size_t n) {
    ax_.reserve(n);
    ay_.reserve(n);
    az_.reserve(n);
    d_.reserve(n);
  }
  /// n planes, to be filled with set().
  void resize(std::size_t n) {
    ax_.resize(n);
    ay_.resize(n);
    az_.resize(n);
    d_.resize(n);
  }
  void set(int i, const Vec3& a, double d) {
    ax_[i] = a.x();
    ay_[i] = a.y();
    az_[i] = a.z();
    d_[i] = d;
  }
  /// Adds a . x <= d; `a` has unit length.
  void add(const Vec3& a, double d) {
    ax_.push_back(a.x());
    ay_.push_back(a.y());
    az_.push_back(a.z());
    d_.push_back(d);
  }

  int size() const { return static_cast<int>(d_.size()); }
  Vec3 normal(int i) const { return Vec3(ax_[i], ay_[i], az_[i]); }
  double offset(int i) const { return d_[i]; }
  /// d_i - a_i . x: the distance of x from plane i, positive inside.
  double slack(int i, const Vec3& x) const {
    return d_[i] - (ax_[i] * x.x() + ay_[i] * x.y() + az_[i] * x.z());
  }
  /// The smallest slack over planes [begin, end) (end < 0: to the last plane).
  double minSlack(const Vec3& x, int begin = 0, int end = -1) const;

  /// The part of the line x + t u inside the set is t_min <= t <= t_max; empty (t_min > t_max)
  /// when the line misses the set, infinite ends when the set is unbounded along u.
  struct Chord {
    double t_min = 0.0, t_max = 0.0;
    double length() const { return t_max > t_min ? t_max - t_min : 0.0; }
  };
  Chord chord(const Vec3& x, const Vec3& u) const;

  const double* ax() const { return ax_.data(); }
  const double* ay() const { return ay_.data(); }
  const double* az() const { return az_.data(); }
  const double* d() const { return d_.data(); }

 private:
  std::vector<double> ax_, ay_, az_, d_;
};

}  // namespace polydem::geometry
