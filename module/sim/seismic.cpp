#include "polydem/sim/seismic.h"

#include <cmath>
#include <numbers>

namespace polydem::sim {

Vec3 seismicAcceleration(const setup::SeismicSpec& seismic, const Vec3& gravity) {
  const double g = gravity.norm();
  const double a = seismic.azimuth * std::numbers::pi / 180.0;
  return g * Vec3(seismic.kh * std::sin(a), seismic.kh * std::cos(a), seismic.kv);
}

Vec3 bodyAcceleration(const setup::Setup& scene) {
  if (!scene.seismic.enabled) return scene.gravity;
  return scene.gravity + seismicAcceleration(scene.seismic, scene.gravity);
}

}  // namespace polydem::sim
