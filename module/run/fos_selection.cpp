// What `polydem fos` reduces (run/fos.h): the material pairs and [[joint]]s of [fos], or, when it
// names neither, every pair and joint that some contact of a free block can use. A pair or joint
// that only fixed (or driven) bodies share is never reduced or listed: no contact of the run
// takes it.
#include <algorithm>

#include "polydem/run/fos.h"

namespace polydem::run {

namespace {

bool isFree(const setup::ParticleSpec& p) {
  return !p.fixed && p.driver < 0;
}

}  // namespace

bool pairUsable(const setup::Setup& scene, int a, int b) {
  bool free_a = false, free_b = false;
  int count_a = 0, count_b = 0;
  for (const auto& p : scene.particles) {
    if (p.material == a) {
      ++count_a;
      free_a = free_a || isFree(p);
    }
    if (p.material == b) {
      ++count_b;
      free_b = free_b || isFree(p);
    }
  }
  if (a == b) return count_a >= 2 && free_a;
  return count_a >= 1 && count_b >= 1 && (free_a || free_b);
}

bool jointUsable(const setup::Setup& scene, int joint) {
  for (const auto& p : scene.particles) {
    if (!isFree(p) || p.shape < 0) continue;
    for (const auto& face : scene.shapes[p.shape].face_planes) {
      if (face.plane >= 0 && face.plane < static_cast<int>(scene.joint_planes.size()) &&
          scene.joint_planes[face.plane].joint == joint) {
        return true;
      }
    }
  }
  return false;
}

std::vector<std::pair<int, int>> reducedPairs(const setup::Setup& scene) {
  const setup::FosSpec& f = scene.fos;
  if (!f.interactions.empty()) return f.interactions;
  if (f.joints_named) return {};  // only the joints named
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(scene.materials.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a; b < n; ++b) {
      if (pairUsable(scene, a, b)) pairs.emplace_back(a, b);
    }
  }
  return pairs;
}

std::vector<int> reducedJoints(const setup::Setup& scene) {
  const setup::FosSpec& f = scene.fos;
  if (f.joints_named) return f.joints;
  if (!f.interactions.empty()) return {};  // only the pairs named
  std::vector<int> joints;
  for (int j = 0; j < static_cast<int>(scene.joints.size()); ++j) {
    if (jointUsable(scene, j)) joints.push_back(j);
  }
  return joints;
}

}  // namespace polydem::run
