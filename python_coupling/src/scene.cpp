// Bindings of module/io's Scene (read a scene file, look at it, override kernel and stop time) and
// of run::runScene, the complete run `polydem run` makes.
#include <optional>
#include <string>

#include "bindings.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/run.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/setup/setup.h"

namespace polydem::python {

namespace {

py::list materials(const setup::Setup& s) {
  py::list out;
  for (const auto& m : s.materials) {
    py::dict d;
    d["name"] = m.name;
    d["density"] = m.density;
    d["kn"] = m.kn;
    d["ks"] = m.ks;
    d["friction_angle"] = m.friction_angle;
    d["cohesion"] = m.cohesion;
    d["normal_damping"] = m.normal_damping;
    d["local_damping"] = m.local_damping;
    d["penalty"] = m.penalty;
    d["jkn"] = m.jkn;
    d["jks"] = m.jks;
    out.append(d);
  }
  return out;
}

py::list shapes(const setup::Setup& s) {
  py::list out;
  for (const auto& shape : s.shapes) {
    py::dict d;
    d["name"] = shape.name;
    d["vertices"] = pointsArray(shape.vertices);
    out.append(d);
  }
  return out;
}

py::dict particles(const setup::Setup& s) {
  const auto n = static_cast<py::ssize_t>(s.particles.size());
  auto uid = emptyArray<std::uint64_t>({n});
  auto shape = emptyArray<std::int32_t>({n});
  auto material = emptyArray<std::int32_t>({n});
  auto driver = emptyArray<std::int32_t>({n});
  auto fixed = emptyArray<bool>({n});
  auto position = emptyArray<double>({n, 3});
  auto orientation = emptyArray<double>({n, 4});
  auto velocity = emptyArray<double>({n, 3});
  auto angular_velocity = emptyArray<double>({n, 3});
  py::list labels;
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& p = s.particles[i];
    uid.mutable_data()[i] = p.uid;
    shape.mutable_data()[i] = p.shape;
    material.mutable_data()[i] = p.material;
    driver.mutable_data()[i] = p.driver;
    fixed.mutable_data()[i] = p.fixed;
    for (int k = 0; k < 3; ++k) {
      position.mutable_data()[3 * i + k] = p.position[k];
      velocity.mutable_data()[3 * i + k] = p.velocity[k];
      angular_velocity.mutable_data()[3 * i + k] = p.angular_velocity[k];
    }
    const double q[4] = {p.orientation.w(), p.orientation.x(), p.orientation.y(),
                         p.orientation.z()};
    for (int k = 0; k < 4; ++k) orientation.mutable_data()[4 * i + k] = q[k];
    labels.append(p.label);
  }
  py::dict d;
  d["uid"] = uid;
  d["label"] = labels;
  d["shape"] = shape;
  d["material"] = material;
  d["position"] = position;
  d["orientation"] = orientation;
  d["velocity"] = velocity;
  d["angular_velocity"] = angular_velocity;
  d["fixed"] = fixed;
  d["driver"] = driver;
  return d;
}

py::list drivers(const setup::Setup& s) {
  py::list out;
  for (const auto& d : s.drivers) {
    py::dict x;
    x["name"] = d.name;
    x["velocity"] = vec3Array(d.velocity);
    x["angular_velocity"] = vec3Array(d.angular_velocity);
    x["pivot"] = vec3Array(d.pivot);
    x["oscillation"] = vec3Array(d.oscillation);
    x["frequency"] = d.frequency;
    x["phase"] = d.phase;
    x["start_time"] = d.start_time;
    x["end_time"] = d.end_time;
    out.append(x);
  }
  return out;
}

py::list checks(const setup::Setup& s) {
  py::list out;
  for (const auto& c : s.checks) {
    py::dict d;
    d["name"] = c.name;
    d["kind"] = c.kind;
    d["expected"] = c.expected;
    d["tolerance"] = c.tolerance;
    d["compare"] = c.compare;
    d["reference"] = c.reference;
    d["line"] = c.line;
    out.append(d);
  }
  return out;
}

// One phreatic surface of [water] as a dict: points, triangles, times, heights, dry.
void putSurface(const setup::WaterSurfaceSpec& w, py::dict& d) {
  py::list points;
  for (const auto& p : w.points) points.append(py::make_tuple(p[0], p[1]));
  d["points"] = points;
  py::list triangles;
  for (const auto& t : w.triangles) triangles.append(py::make_tuple(t[0], t[1], t[2]));
  d["triangles"] = triangles;
  d["times"] = w.times;
  d["heights"] = w.heights;
  d["dry"] = w.dry;
}

py::object water(const setup::Setup& s) {
  if (!s.water.enabled) return py::none();
  py::dict d;
  d["unit_weight"] = s.water.unit_weight;
  putSurface(s.water, d);
  py::list joints;
  for (const auto& j : s.water.joints) {
    py::dict e;
    e["joint"] = j.name;
    putSurface(j.surface, e);
    e["planes"] = j.planes;
    e["line"] = j.line;
    joints.append(e);
  }
  d["joints"] = joints;
  d["line"] = s.water.line;
  return d;
}

py::list bolts(const setup::Setup& s) {
  py::list out;
  for (const auto& b : s.bolts) {
    py::dict d;
    d["name"] = b.name;
    d["start"] = std::vector<double>{b.start.x(), b.start.y(), b.start.z()};
    d["direction"] = std::vector<double>{b.direction.x(), b.direction.y(), b.direction.z()};
    d["length"] = b.length;
    d["axial_stiffness"] = b.axial_stiffness;
    d["axial_yield"] = b.axial_yield;
    d["shear_stiffness"] = b.shear_stiffness;
    d["shear_yield"] = b.shear_yield;
    d["pretension"] = b.pretension;
    d["ultimate_elongation"] =
        b.ultimate_elongation ? py::object(py::float_(*b.ultimate_elongation)) : py::none();
    d["line"] = b.line;
    out.append(d);
  }
  return out;
}

py::object seismic(const setup::Setup& s) {
  if (!s.seismic.enabled) return py::none();
  py::dict d;
  d["kh"] = s.seismic.kh;
  d["azimuth"] = s.seismic.azimuth;
  d["kv"] = s.seismic.kv;
  // The acceleration record in m/s^2 (units and scale applied), empty without one.
  d["record_file"] = s.seismic.record_file;
  d["record_time"] = py::array_t<double>(static_cast<py::ssize_t>(s.seismic.record_time.size()),
                                         s.seismic.record_time.data());
  d["record_acceleration"] = pointsArray(s.seismic.record_acceleration);
  d["line"] = s.seismic.line;
  return d;
}

py::list rockMasses(const setup::Setup& s) {
  py::list out;
  for (const auto& r : s.rock_masses) {
    py::dict d;
    d["name"] = r.name;
    d["label_prefix"] = r.label_prefix;
    d["first_uid"] = r.first_uid;
    d["blocks"] = r.blocks;
    d["plane_names"] = r.plane_names;
    d["report"] = rockMassReport(r.report);
    d["line"] = r.line;
    out.append(d);
  }
  return out;
}

std::string repr(const setup::Setup& s) {
  return cat("Scene('", s.id, "', ", s.particles.size(), " particles, kernel ", s.kernel, ", dt ",
             num(s.dt), ")");
}

// Raises ValueError (listing the known kernels) for an unknown name.
void checkKernel(const std::string& name) {
  try {
    contact::makeKernel(name);
  } catch (const Error& e) {
    throw py::value_error(e.what());
  }
}

run::RunOptions runOptions(const std::string& out, std::optional<std::int64_t> steps,
                           std::optional<double> end_time, std::optional<std::string> kernel,
                           bool snapshots, std::int64_t progress_every) {
  if (steps && *steps <= 0) throw py::value_error(cat("steps must be positive, got ", *steps));
  if (end_time && !(*end_time > 0)) {
    throw py::value_error(cat("end_time must be > 0, got ", *end_time));
  }
  if (progress_every < 0) throw py::value_error("progress_every must be >= 0");
  if (kernel) checkKernel(*kernel);
  run::RunOptions o;
  o.out_dir = out;
  o.steps = steps;
  o.end_time = end_time;
  o.kernel = kernel;
  o.snapshots = snapshots;
  o.progress_every = progress_every;
  return o;
}

py::dict checkDict(const output::CheckResult& c) {
  py::dict d;
  d["name"] = c.name;
  d["kind"] = c.kind;
  d["value"] = c.value;
  d["expected"] = c.expected;
  d["tolerance"] = c.tolerance;
  d["compare"] = c.compare;
  d["pass"] = c.pass;
  d["reference"] = c.reference;
  d["note"] = c.note;
  return d;
}

py::dict runScene(const setup::Setup& scene, const std::string& out,
                  std::optional<std::int64_t> steps, std::optional<double> end_time,
                  std::optional<std::string> kernel, bool snapshots, std::int64_t progress_every,
                  const py::object& comm) {
  auto options = runOptions(out, steps, end_time, kernel, snapshots, progress_every);
  options.scene_text = scene.text;  // what its checkpoints store
  const run::RunResult r = run::runScene(scene, options, toComm(comm));
  py::list check_list;
  for (const auto& c : r.checks) check_list.append(checkDict(c));
  py::dict d;
  d["checks"] = check_list;
  d["all_checks_pass"] = r.all_checks_pass();
  d["state_hash"] = r.hash.hex();
  d["steps"] = r.steps;
  d["time"] = r.time;
  d["equilibrium_steps"] = r.equilibrium_steps;
  d["wall_seconds"] = r.wall_seconds;
  return d;
}

}  // namespace

void bindScene(py::module_& m) {
  py::class_<setup::Setup>(
      m, "SceneData",
      R"(A checked scene as read from a scene file (docs/scene-format.md), in SI units.

read_scene and parse_scene return one, and so does polydem.Scene.build() for a scene built in
Python; `text` is the TOML it was read from, which checkpoints of its run store.

A read-only view of its main fields, except the kernel, the contact model and the stop condition,
which may be overridden (as `polydem run --kernel/--contact-model/--steps/--end-time` do). Setting `steps` or `end_time`
replaces the scene's whole stop condition: the other one is cleared.)")
      .def_readonly("file", &setup::Setup::file, "Path of the scene file.")
      .def_readonly("text", &setup::Setup::text, "The TOML text the scene was read from, verbatim.")
      .def(
          "to_toml", [](const setup::Setup& s) { return s.text; },
          "The TOML text the scene was read from (kernel, contact model and stop overrides are\n"
          "not written into it).")
      .def_readonly("id", &setup::Setup::id)
      .def_readonly("title", &setup::Setup::title)
      .def_readonly("description", &setup::Setup::description)
      .def_readonly("source", &setup::Setup::source)
      .def_property(
          "kernel", [](const setup::Setup& s) { return s.kernel; },
          [](setup::Setup& s, const std::string& name) {
            checkKernel(name);
            s.kernel = name;
          },
          "Contact kernel name (one of polydem.kernels()).")
      .def_property(
          "contact_model", [](const setup::Setup& s) { return s.contact_model; },
          [](setup::Setup& s, const std::string& model) {
            if (const auto e = setup::unknownContactModel(model); !e.empty()) {
              throw py::value_error(e);
            }
            if (model != "point" && s.contact_point != "kernel") {
              throw py::value_error("contact_point = \"" + s.contact_point +
                                    "\" needs the point model");
            }
            s.contact_model = model;
          },
          "How penalty contacts become forces: \"sub-contacts\" (a spring at every corner of a "
          "face overlap; the default) or \"point\" (docs/dynamics.md).")
      .def_readonly("broadphase", &setup::Setup::broadphase)
      .def_readonly("dt", &setup::Setup::dt, "Time step [s].")
      .def_property(
          "steps", [](const setup::Setup& s) { return s.steps; },
          [](setup::Setup& s, std::optional<std::int64_t> steps) {
            if (!steps) return s.steps.reset();
            run::applyOverrides(s, runOptions("", steps, std::nullopt, std::nullopt, true, 0));
          },
          "Step count the run stops at, or None. Setting a count clears end_time.")
      .def_property(
          "end_time", [](const setup::Setup& s) { return s.end_time; },
          [](setup::Setup& s, std::optional<double> end_time) {
            if (!end_time) return s.end_time.reset();
            run::applyOverrides(s, runOptions("", std::nullopt, end_time, std::nullopt, true, 0));
          },
          "Simulated time the run stops at [s], or None. Setting a time clears steps.")
      .def_property_readonly(
          "gravity", [](const setup::Setup& s) { return vec3Array(s.gravity); }, "[m/s^2]")
      .def_readonly("contact_margin", &setup::Setup::contact_margin,
                    "Extra range of candidate pairs, relative to particle size.")
      .def_property_readonly(
          "num_particles", [](const setup::Setup& s) { return s.particles.size(); },
          "Number of particles (free, fixed and driven).")
      .def_property_readonly("particles", &particles,
                             "Initial particles as a dict of arrays: uid, label (list), shape and "
                             "material (indices), position (n, 3), orientation (n, 4: w, x, y, "
                             "z), velocity, angular_velocity (n, 3), fixed (bool), driver (index "
                             "or -1).")
      .def_property_readonly("materials", &materials,
                             "Materials as dicts (name, density [kg/m^3], kn, ks [N/m], "
                             "friction_angle [deg], cohesion [N], normal_damping, local_damping, "
                             "penalty [Pa], jkn, jks [Pa/m]).")
      .def_property_readonly("shapes", &shapes,
                             "Shapes as dicts {name, vertices}: the corners of each hull in the "
                             "shape's own frame.")
      .def_property_readonly("drivers", &drivers,
                             "Prescribed motions as dicts (name, velocity [m/s], angular_velocity "
                             "[rad/s], pivot [m], oscillation [m/s], frequency [Hz], phase [rad], "
                             "start_time, end_time [s]); particles()['driver'] indexes them.")
      .def_property_readonly("rock_masses", &rockMasses,
                             "The [[rock_mass]] entries as dicts (name, label_prefix, first_uid, "
                             "blocks: the particles first_uid .. first_uid + blocks - 1, "
                             "plane_names, report, line).")
      .def_property_readonly("checks", &checks,
                             "The expected results ([[check]]) as dicts (name, kind, expected, "
                             "tolerance, compare, reference, line).")
      .def_property_readonly(
          "monitor", [](const setup::Setup& s) { return s.output.monitor; },
          "Labels of the particles whose state a run writes to series.csv.")
      .def_property_readonly(
          "equilibrium", [](const setup::Setup& s) { return s.equilibrium.enabled; },
          "Whether the run starts with the initial-equilibrium stage.")
      .def_property_readonly("water", &water,
                             "[water] as read, in SI units: a dict (unit_weight [N/m^3], points "
                             "(x, y of the surface's points; empty: a level surface), triangles "
                             "(their triangulation in plan, with four points or more), times "
                             "[s], heights [m] per time, dry (no global surface), joints (one "
                             "dict per [[water.joint]]: joint, its surface's keys, planes: "
                             "indices of the joint planes)), or None without water.")
      .def_property_readonly("bolts", &bolts,
                             "The [[bolt]]s as read, in SI units: a list of dicts (name, start, "
                             "direction (unit), length [m], axial_stiffness [N/m], axial_yield "
                             "[N], shear_stiffness [N/m], shear_yield [N], pretension [N], "
                             "ultimate_elongation [m] or None, line).")
      .def_property_readonly("seismic", &seismic,
                             "[seismic] as read: a dict (kh, azimuth [deg clockwise from +y], kv "
                             "[positive upward], record_file, record_time [s], "
                             "record_acceleration [m/s^2, (n, 3)], line), or None without an "
                             "earthquake load.")
      .def(
          "copy", [](const setup::Setup& s) { return setup::Setup(s); },
          "An independent copy (to override kernel or stop time without changing this one).")
      .def("__copy__", [](const setup::Setup& s) { return setup::Setup(s); })
      .def(
          "__deepcopy__", [](const setup::Setup& s, const py::dict&) { return setup::Setup(s); },
          py::arg("memo"))
      .def("__repr__", &repr);

  m.def(
      "read_scene", &scene::readScene, py::arg("path"),
      "Reads and checks a scene file. Raises polydem.InputError ('file:line: message', with\n"
      "attributes file and line; line 0 for a file that cannot be opened) for the first problem.");
  m.def("parse_scene", &scene::parseScene, py::arg("text"), py::arg("name") = "<string>",
        "Reads a scene from TOML text; `name` is the file name messages carry.");
  m.def("run_scene", &runScene, py::arg("scene"), py::arg("out") = "",
        py::arg("steps") = py::none(), py::arg("end_time") = py::none(),
        py::arg("kernel") = py::none(), py::arg("snapshots") = true, py::arg("progress_every") = 0,
        py::arg("comm") = py::none(),
        "run::runScene: the run `polydem run` makes (use polydem.run, which takes paths too).");
}

}  // namespace polydem::python
