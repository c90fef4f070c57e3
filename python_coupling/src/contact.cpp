// Bindings of module/contact: the kernel registry, one-off collisions (as `polydem contact` does
// them) and the contact-type cases of BENCHMARKS.md section C.
#include <memory>
#include <string>

#include "bindings.h"
#include "polydem/contact/contact.h"
#include "polydem/contact/contact_cases.h"
#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::python {

namespace {

using geometry::ConvexPolyhedron;

const char* statusName(contact::Status s) {
  switch (s) {
    case contact::Status::kOk:
      return "ok";
    case contact::Status::kNotConverged:
      return "not_converged";
    case contact::Status::kDegenerate:
      return "degenerate";
    case contact::Status::kInnerDomainReached:
      return "inner_domain_reached";
  }
  return "ok";
}

// A polyhedron given as a ConvexPolyhedron or as its points.
ConvexPolyhedron polyhedronOf(const py::handle& object, const char* what) {
  if (py::isinstance<ConvexPolyhedron>(object)) return object.cast<ConvexPolyhedron>();
  return ConvexPolyhedron::fromPoints(toPoints(object, what));
}

std::unique_ptr<contact::Kernel> kernelByName(const std::string& name, double lp_rounding) {
  contact::KernelParams params;
  params.lp_rounding = lp_rounding;
  try {
    return contact::makeKernel(name, params);
  } catch (const Error& e) {
    throw py::value_error(e.what());  // an unknown name is a bad argument
  }
}

py::dict collide(const py::handle& a_object, const py::handle& b_object, const std::string& name,
                 double lp_rounding) {
  const auto kernel = kernelByName(name, lp_rounding);
  const ConvexPolyhedron a_shape = polyhedronOf(a_object, "a");
  const ConvexPolyhedron b_shape = polyhedronOf(b_object, "b");
  std::vector<Vec3> va, vb;
  const auto a = contact::placeBody(a_shape, Vec3::Zero(), Mat3::Identity(), va);
  const auto b = contact::placeBody(b_shape, Vec3::Zero(), Mat3::Identity(), vb);
  const contact::Contact c = kernel->collide(a, b, nullptr);
  py::dict out;
  out["contact"] = c.touching;
  if (!c.touching) return out;
  out["normal"] = vec3Array(c.normal);
  out["point"] = vec3Array(c.point);
  out["depth"] = c.depth;
  if (c.model == contact::ForceModel::kPotential) out["potential"] = c.potential;
  if (c.status != contact::Status::kOk) out["status"] = statusName(c.status);
  return out;
}

py::list contactCases() {
  py::list cases;
  for (const auto& c : contact::contactTypeCases()) {
    py::dict d;
    d["id"] = c.id;
    d["description"] = c.description;
    d["a"] = pointsArray(c.a);
    d["b"] = pointsArray(c.b);
    d["normal"] = vec3Array(c.normal);
    d["point"] = vec3Array(c.point);
    d["depth"] = c.depth;
    d["size"] = c.size;
    cases.append(d);
  }
  return cases;
}

}  // namespace

void bindContact(py::module_& m) {
  m.def("kernels", &contact::kernelNames,
        "Names of the contact kernels, in the order reports list them (polydem kernels).");
  m.def(
      "collide", &collide, py::arg("a"), py::arg("b"), py::arg("kernel") = "gjk-epa-ipm",
      py::arg("lp_rounding") = contact::KernelParams{}.lp_rounding,
      R"(Resolves the contact between two convex polyhedra with one kernel, as `polydem contact` does.

`a` and `b` are ConvexPolyhedron objects or (n, 3) arrays of world coordinates [m] (their convex
hulls are taken). Returns {"contact": False} when they do not touch, otherwise
    {"contact": True, "normal": n, "point": p, "depth": d}
with `normal` the unit vector from b into a (the direction a must move to separate), `point` the
contact point half way between the two surfaces and `depth` >= 0 the penetration [m]; potential
kernels add "potential" (integral of the potential over the overlap [m^2]), and a kernel that
could not give a trustworthy answer adds "status" ("not_converged", "degenerate",
"inner_domain_reached"). `lp_rounding` is the LP kernel's rounding radius / inradius.
Raises ValueError for an unknown kernel (the message lists the known ones) and
polydem.GeometryError for points that do not make a polyhedron.)");
  m.def("contact_cases", &contactCases,
        R"(The seven contact types of BENCHMARKS.md section C (Keissar tables 3.1-3.6) at unit size.

A list of dicts {id, description, a, b, normal, point, depth, size}: a (above) and b (below) are
world vertex arrays; normal, point and depth are the analytical answer (normal (0, 0, 1), point
(0, 0, -5e-6), depth 1e-5); `size` is the particle size point errors are relative to.)");
}

}  // namespace polydem::python
