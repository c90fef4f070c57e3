// The shape records of a saved state and their comparison with a built shape table.
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/sim/saved_state.h"

namespace polydem::sim {

namespace {

bool sameBits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 24) == 0;
}
bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace

const char* toString(CheckpointStage stage) {
  return stage == CheckpointStage::kEquilibrium ? "equilibrium" : "main";
}

std::vector<CheckpointShape> shapeRecords(const particles::ShapeTable& shapes) {
  std::vector<CheckpointShape> out;
  for (const auto& s : shapes) {
    CheckpointShape r;
    r.name = s.name;
    r.vertices = s.polyhedron->vertices();
    for (const auto& f : s.polyhedron->faces()) r.faces.push_back(f.vertices);
    r.volume = s.volume;
    r.principal_moments = s.principal_moments;
    r.circumradius = s.circumradius;
    r.inradius = s.inradius;
    r.face_plane.emplace(s.polyhedron->faces().size(), -1);
    for (std::size_t f = 0; f < r.face_plane->size(); ++f)
      (*r.face_plane)[f] = s.facePlane(static_cast<int>(f));
    out.push_back(std::move(r));
  }
  return out;
}

std::string shapeMismatch(const std::vector<CheckpointShape>& stored,
                          const particles::ShapeTable& built) {
  if (stored.size() != built.size()) {
    return cat("the checkpoint has ", stored.size(), " shapes, the scene builds ", built.size());
  }
  for (std::size_t i = 0; i < stored.size(); ++i) {
    const CheckpointShape& a = stored[i];
    const CheckpointShape b = shapeRecords({built[i]}).front();
    const std::string which = cat("shape ", i, " '", a.name, "'");
    if (a.name != b.name) return cat(which, ": the scene calls it '", b.name, "'");
    if (a.vertices.size() != b.vertices.size()) {
      return cat(which, ": ", a.vertices.size(), " vertices stored, ", b.vertices.size(), " built");
    }
    for (std::size_t v = 0; v < a.vertices.size(); ++v) {
      if (!sameBits(a.vertices[v], b.vertices[v])) return cat(which, ": vertex ", v, " differs");
    }
    if (a.faces != b.faces) return cat(which, ": the faces differ");
    if (!sameBits(a.volume, b.volume) || !sameBits(a.principal_moments, b.principal_moments) ||
        !sameBits(a.circumradius, b.circumradius) || !sameBits(a.inradius, b.inradius)) {
      return cat(which, ": the mass properties or radii differ");
    }
  }
  return {};
}

void restoreFacePlanes(const std::vector<CheckpointShape>& stored, particles::ShapeTable& built,
                       std::size_t planes, const std::string& file) {
  for (std::size_t s = 0; s < stored.size() && s < built.size(); ++s) {
    auto& face_plane = built[s].face_plane;
    face_plane.clear();
    if (!stored[s].face_plane) continue;
    const auto& ids = *stored[s].face_plane;
    if (ids.size() != built[s].polyhedron->faces().size()) {
      throw CheckpointError(cat(file, ": shape ", s, " '", stored[s].name, "': ", ids.size(),
                                " face joint planes stored for ",
                                built[s].polyhedron->faces().size(), " faces"));
    }
    bool any = false;
    for (const std::int32_t id : ids) {
      if (id < -1 || id >= static_cast<std::int64_t>(planes)) {
        throw CheckpointError(cat(file, ": shape ", s, " '", stored[s].name, "': joint plane ", id,
                                  " of a face, but the scene has ", planes));
      }
      any = any || id >= 0;
    }
    if (any) face_plane = ids;
  }
}

}  // namespace polydem::sim
