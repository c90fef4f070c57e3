// Pressure on a polygon, clipped at p = 0 and integrated over a triangle fan (face_pressure.h).
#include "polydem/geometry/face_pressure.h"

namespace polydem::geometry {

namespace {

// Sums over the triangles (x0, x_k, x_{k+1}) of the clipped polygon, its vertices fed one by one
// relative to the origin. For a linear p on a triangle of area A with corners r_i, p_i:
//   integral of p dA     = A (p_0 + p_1 + p_2) / 3,
//   integral of p r dA   = A / 12 (sum p_i r_i + (sum p_i) (sum r_i))
// (the integral of the product of two linear functions over a triangle).
class Fan {
 public:
  explicit Fan(const Vec3& normal) : normal_(normal) {}

  void add(const Vec3& r, double p) {
    if (count_ >= 2) triangle(r, p);
    if (count_ == 0) {
      r0_ = r;
      p0_ = p;
    }
    r_prev_ = r;
    p_prev_ = p;
    ++count_;
  }

  double area = 0.0;
  double load = 0.0;                 // integral of p dA
  Vec3 first_moment = Vec3::Zero();  // integral of p r dA

 private:
  void triangle(const Vec3& r2, double p2) {
    const double a = 0.5 * normal_.dot((r_prev_ - r0_).cross(r2 - r0_));
    const double p_sum = p0_ + p_prev_ + p2;
    area += a;
    load += a * p_sum / 3.0;
    first_moment +=
        (a / 12.0) * (p0_ * r0_ + p_prev_ * r_prev_ + p2 * r2 + p_sum * (r0_ + r_prev_ + r2));
  }

  Vec3 normal_;
  int count_ = 0;
  Vec3 r0_ = Vec3::Zero(), r_prev_ = Vec3::Zero();
  double p0_ = 0.0, p_prev_ = 0.0;
};

}  // namespace

PressureResultant pressureResultant(std::span<const Vec3> points, std::span<const int> polygon,
                                    const Vec3& normal, const LinearPressure& pressure) {
  PressureResultant out;
  const std::size_t n = polygon.size();
  if (n < 3) return out;
  Fan fan(normal);
  // Sutherland-Hodgman against p >= 0, one edge a -> b at a time: keep a where p(a) >= 0, and
  // the point where p = 0 where the edge crosses it. Positions relative to the origin.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = points[static_cast<std::size_t>(polygon[i])] - pressure.origin;
    const Vec3 b = points[static_cast<std::size_t>(polygon[(i + 1) % n])] - pressure.origin;
    const double pa = pressure.value + pressure.gradient.dot(a);
    const double pb = pressure.value + pressure.gradient.dot(b);
    if (pa >= 0.0) fan.add(a, pa);
    if ((pa >= 0.0) != (pb >= 0.0)) fan.add(a + (pa / (pa - pb)) * (b - a), 0.0);
  }
  if (!(fan.load > 0.0)) return out;
  out.wetted_area = fan.area;
  out.load = fan.load;
  out.force = -fan.load * normal;
  out.moment = normal.cross(fan.first_moment);  // (integral of p r dA) x (-normal)
  return out;
}

}  // namespace polydem::geometry
