// Setup: everything the engine (sim::Simulation) is built from: materials, shapes, particles,
// drivers, stages, contact model and kernel, domain, output and check settings. Plain data, filled
// alike by the scene file reader (scene/scene_reader.h), Python, or a C++ program
// (examples/force_operator); nothing here knows the file format. Units are SI throughout.
// The `file` and `line` members are diagnostics only: where a scene file defined the item, for
// error messages (empty / 0 when it was not read from a file).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/types.h"
#include "polydem/dynamics/contact_models.h"
#include "polydem/dynamics/driver_spec.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/geometry/rock_mass.h"
#include "polydem/particles/material.h"

namespace polydem::setup {

/// The contact models of Setup::contact_model: the scene reader, the command line and Python
/// accept these and no other (the registry dynamics/contact_model_list.inc).
inline const std::vector<std::string> kContactModels = dynamics::contactModelNames();

/// "unknown contact model 'NAME' (known: sub-contacts, point)" for a name that is none of
/// kContactModels, else "".
inline std::string unknownContactModel(const std::string& name) {
  std::string known;
  for (const auto& m : kContactModels) {
    if (m == name) return "";
    known += (known.empty() ? "" : ", ") + m;
  }
  return "unknown contact model '" + name + "' (known: " + known + ")";
}

/// A plane that one face of a shape lies on, in the shape's own frame: a face of the hull whose
/// outward normal is +-normal and whose vertices satisfy normal . x = offset (to round-off) gets
/// joint plane `plane` (an index into Setup::joint_planes).
struct FacePlane {
  Vec3 normal = Vec3::UnitZ();  // unit
  double offset = 0.0;          // m
  int plane = -1;
};

/// A shape, resolved by the reader to the vertex list of its convex hull (in the shape's own
/// frame; the simulation moves it to its body frame).
struct ShapeSpec {
  std::string name;
  std::vector<Vec3> vertices;
  int line = 0;  // where it was defined, for error messages
  // The joint planes its faces lie on (a block cut from a [[rock_mass]]); empty for [[shape]]s.
  // Last, so that {name, vertices, line} written before joints existed still means the same.
  std::vector<FacePlane> face_planes;
};

/// A [[joint]]: its law and the law's parameters (dynamics/joint_law.h, docs/scene-format.md).
/// Stresses act on each sub-contact's share of the face contact's area.
struct JointSpec {
  std::string name;
  dynamics::JointParameters law;  // the law, its parameters in its declared order (SI, degrees)
  int line = 0;

  const char* lawName() const { return dynamics::jointLaw(law.law).name; }
  /// The value of the law's parameter `key`; throws polydem::Error if the law has none.
  double value(std::string_view key) const {
    const int i = dynamics::parameterIndex(dynamics::jointLaw(law.law), key);
    if (i < 0) {
      throw Error(std::string("joint '") + name + "' (law " + lawName() + ") has no parameter '" +
                  std::string(key) + "'");
    }
    return law.values[static_cast<std::size_t>(i)];
  }
};

/// A plane that cut a [[rock_mass]] ("mass/J1#3", "mass/fault"): the faces it made carry its
/// index. `joint` is the [[joint]] whose properties contacts on it take (index into
/// Setup::joints), -1: the material pair's.
struct JointPlaneSpec {
  std::string name;
  int joint = -1;
};

struct ParticleSpec {
  Uid uid = 0;        // assigned by the reader in file order, starting at 1
  std::string label;  // optional name, used by checks and monitors
  int shape = -1;     // index into Setup::shapes
  int material = -1;  // index into Setup::materials
  // The particle occupies { position + orientation * v : v in the shape's vertices }. Built-in
  // shapes (box, prisms, regular polyhedra...) are centred on their centroid, so `position` is the
  // centroid; a vertex-list shape stays where its vertices are when position = 0.
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  bool fixed = false;
  int driver = -1;  // index into Setup::drivers
  int line = 0;
};

/// What a [[rock_mass]] became: its blocks are particles first_uid .. first_uid + blocks - 1,
/// each with a shape of its own, in the order the cutting produced them (docs/scene-format.md).
struct RockMassInfo {
  std::string name;
  std::string label_prefix;  // block i is labelled "<label_prefix>_<i>", i from 0
  Uid first_uid = 0;
  int blocks = 0;
  std::vector<std::string> plane_names;  // every plane applied, single planes first
  geometry::RockMassReport report;
  int line = 0;
};

struct DomainSpec {
  std::optional<Vec3> min, max;              // default: particles' bounding box, inflated
  std::optional<std::array<int, 3>> blocks;  // default: fitted to the free particles
  std::array<bool, 3> periodic{false, false, false};
  std::int64_t rebalance_every = 100;  // steps between balance checks; 0 = never after the start
  // Steps between reorders of each rank's particles into the broad phase's cell order (sim/
  // simulation.cpp; the same results), also at the first step; 0 = never (the default: it pays
  // where particles are created scattered, and cost time on a pack created in space order,
  // docs/performance.md).
  std::int64_t sort_every = 0;
  std::string balancer = "metis";  // "metis" | "sfc" | "cyclic" (round robin: borders everywhere,
                                   // to stress communication in tests)
  // Evaluate the pairs of two local particles while the exchange's messages travel (several
  // ranks; the same bits either way: sim/contact_phase.h). Off by default: on the 2-core machine
  // it made the 2-rank step 10-20 % slower (docs/domain.md), more work than the wait it hides.
  bool overlap_exchange = false;
  int line = 0;  // of `blocks` (else of [domain]), for errors found once the rank count is known
};

/// The initial-equilibrium stage of 3DEC and Keissar section 3.3: heavy local damping and a
/// friction angle of 89 degrees until the force ratio R (Keissar eq. 3.2) drops below a threshold.
struct EquilibriumSpec {
  bool enabled = false;
  double local_damping = 0.8;
  double friction_angle = 89.0;  // degrees
  double force_ratio = 1e-5;
  std::int64_t max_steps = 1000000;
  bool reset_velocities = true;  // zero velocities when the stage ends (3DEC practice)
};

struct OutputSpec {
  std::int64_t series_every = 10;    // steps between rows of series.csv
  std::int64_t snapshot_every = 0;   // steps between snapshots (0 = first and last only)
  std::int64_t progress_every = 0;   // steps between progress lines (0 = automatic)
  std::vector<std::string> monitor;  // particle labels whose state goes into series.csv
  // "xdmf": one HDF5 file per snapshot, written collectively, and snapshots.xmf (the default:
  // 1 file per snapshot on any rank count); "vtk": one .vtp per rank per snapshot (small runs).
  std::string snapshot_format = "xdmf";
  // Fields of the XDMF snapshots (setup/snapshot_fields.h); empty: the defaults declared there.
  std::vector<std::string> fields, contact_fields;
  bool picture = false;  // render frames.png after the run (python_coupling/plots/)
};

struct CheckpointSpec {
  std::int64_t every_steps = 0;  // 0 = never
  double every_seconds = 0.0;    // wall clock; 0 = never
  int keep = 2;                  // keep the last K checkpoints
};

/// How `polydem fos` finds the scene's factor of safety by strength reduction: tan(friction
/// angle) and cohesion of the chosen material pairs are divided by F, and each trial at F is run
/// as a static solution (local damping 0.8 unless set here) until it is decided: stable when the
/// unbalanced-force ratio and the blocks' speeds have decayed, failed when their speeds have not
/// decayed over a window while the displacement grows. F is bisected between f_min and f_max to
/// `resolution` (run/fos.h).
struct FosSpec {
  std::vector<std::pair<int, int>> interactions;  // material pairs reduced (run/fos.h)
  std::vector<int> interaction_lines;             // of each pair in the file
  // [[joint]]s reduced (indices into Setup::joints), when `joints_named`. Naming either list
  // reduces only what the lists name; naming neither reduces every joint and pair.
  std::vector<int> joints;
  std::vector<int> joint_lines;  // of each name in the file
  bool joints_named = false;     // [fos] joints was given (possibly empty)
  bool reduce_bolts = false;     // divide the [[bolt]]s' yield forces by F too (run/fos.h)
  double f_min = 0.5, f_max = 4.0;
  double resolution = 0.01;                  // width of the final bracket, in F
  std::optional<double> max_time;            // s, required (here or on the command line)
  std::optional<double> time_cap;            // s; undecided trials run on to it (4 x max_time)
  std::optional<double> settle_time;         // s: the window; default max_time / 4
  double force_ratio = 1e-5;                 // stable: Keissar eq. 3.2 below it
  double speed_decay = 1e-3;                 // stable: largest speed / its peak below it
  std::optional<double> local_damping;       // of every material in the trials; default 0.8
  std::optional<double> speed_limit;         // m/s; stable also needs the mean speed below it
  std::optional<double> displacement_limit;  // m; failed also beyond it
  std::int64_t check_every = 100;            // steps between evaluations of the criterion
  std::string label_prefix;                  // the free blocks watched (default: all)
  int line = 0, max_time_line = 0, check_every_line = 0;
};

/// One expected result of the scene, computed from the run by the check of that `kind`
/// (sim/checks). `params` holds the kind's parameters (numbers, vectors, labels) as written.
struct CheckSpec {
  std::string name;
  std::string kind;
  std::map<std::string, std::vector<double>> numbers;  // scalars are one-element vectors
  std::map<std::string, std::string> strings;          // e.g. particle labels
  double expected = 0.0;
  double tolerance = 0.0;
  std::string compare = "abs";  // "abs": |v-e| <= tol; "rel": |v-e| <= tol |e|; "max": v <= e;
                                // "min": v >= e; "report": recorded, never fails
  std::string reference;        // where the expected value comes from (paper, table, equation)
  int line = 0;
};

/// A phreatic surface of [water] (docs/scene-format.md "Water"): z = level, the plane through three
/// points, or a triangulated surface through more; any may change with time through a table whose
/// rows are interpolated linearly (held at the first and last row outside them).
struct WaterSurfaceSpec {
  /// x, y of the surface's points (m): none, a level surface; three, the plane through them;
  /// more, the surface linear on each triangle of `triangles` (sim/water.h).
  std::vector<std::array<double, 2>> points;
  /// With four points or more: their triangulation in plan (geometry/plan_triangulation.h),
  /// counter-clockwise; empty: the Delaunay triangulation, made when the water is applied.
  std::vector<std::array<int, 3>> triangles;
  /// Rows of the table, increasing in time (s); one row: a surface that does not move.
  std::vector<double> times;
  /// Per row: the level (one height), or the heights of the points (m).
  std::vector<std::vector<double>> heights;
  /// No water: the faces this surface covers carry no pressure.
  bool dry = false;
};

/// A [[water.joint]]: its own surface on the faces of some joint planes.
struct WaterJointSpec {
  std::string name;  // a [[joint]] or a [[rock_mass.plane]] / joint set name
  WaterSurfaceSpec surface;
  std::vector<int> planes;  // indices into Setup::joint_planes
  int line = 0;
};

/// [water]: the unit weight of water and the phreatic surface (docs/scene-format.md "Water"); the
/// surface of the base WaterSurfaceSpec acts on every joint face but those of `joints`' planes.
struct WaterSpec : WaterSurfaceSpec {
  bool enabled = false;
  double unit_weight = 9810.0;  // N/m^3
  std::vector<WaterJointSpec> joints;
  int line = 0;
};

/// [seismic]: the pseudo-static earthquake load (docs/scene-format.md "Earthquakes"): on every free
/// block a body force m g (kh h + kv z), g = |gravity|, h the horizontal unit vector at `azimuth`
/// (degrees clockwise from north = +y: h = (sin azimuth, cos azimuth, 0)), z = +z (up).
struct SeismicSpec {
  bool enabled = false;
  double kh = 0.0;       // horizontal coefficient, a fraction of g, in [0, 1]
  double azimuth = 0.0;  // degrees clockwise from +y: where the horizontal load pushes
  double kv = 0.0;       // vertical coefficient, a fraction of g, positive upward, in [-1, 1]
  /// record: the ground acceleration (m/s^2, world frame: x east, y north, z up) at increasing
  /// times (s of simulation time), linear between samples and zero outside them. Every fixed
  /// particle moves with the ground it integrates to (sim/ground_motion.h). Empty: no record.
  std::vector<double> record_time;
  std::vector<Vec3> record_acceleration;
  std::string record_file;  // as the scene names it, for messages
  int line = 0;
};

/// A [[bolt]] (docs/scene-format.md "Rock bolts"): a straight bolt or cable from `start` along
/// `direction` over `length`, anchored in every block it crosses (sim/bolt_geometry.h), with an
/// elastic-perfectly plastic law in tension/compression and in shear at each joint it crosses
/// (dynamics/bolt_law.h).
struct BoltSpec {
  std::string name;
  Vec3 start = Vec3::Zero();                  // m
  Vec3 direction = Vec3::UnitZ();             // unit, from start towards the far end
  double length = 0.0;                        // m
  double axial_stiffness = 0.0;               // N/m
  double axial_yield = 0.0;                   // N
  double shear_stiffness = 0.0;               // N/m
  double shear_yield = 0.0;                   // N
  double pretension = 0.0;                    // N, tension positive
  std::optional<double> ultimate_elongation;  // m of plastic elongation at a joint: it breaks
  int line = 0;
};

/// An [[operator]] (docs/scene-format.md "Operators"): a user force operator put into the step by
/// name, at the step's "force operators" place, in file order (sim/scene_operators.h).
struct OperatorSpec {
  std::string name;     // a C identifier: also the operator's timer name
  std::string library;  // shared library that defines it, relative paths resolved against the
                        // scene's folder; empty: the program running the scene supplies it
  int line = 0;
};

struct Setup {
  std::string file;  // path of the scene file, for messages (diagnostics only)
  // The TOML text the scene was parsed from, verbatim: what a checkpoint of its run stores (and a
  // restart parses again), so that a scene built without a file (Python) can be continued too.
  std::string text;
  std::string id, title, description, source;

  std::string kernel = "gjk-epa-ipm";
  contact::KernelParams kernel_params;
  std::string broadphase = "multilevel";
  // How a penalty kernel's contact becomes forces: "sub-contacts" (a spring at every corner of a
  // face overlap, contact/face/face_contact.h; the default) or "point" (the whole force at the
  // kernel's point, the model of the thesis's comparisons). Potential kernels integrate over the
  // overlap and ignore it.
  std::string contact_model = "sub-contacts";
  // Where a contact's force acts: "kernel" (the kernel's point) or "overlap-centroid" (the
  // centroid of the overlap volume, the centre of pressure of a linear bed;
  // contact/point/overlap_point.h)
  std::string contact_point = "kernel";
  double dt = 0.0;
  std::optional<double> end_time;
  std::optional<std::int64_t> steps;
  Vec3 gravity = Vec3(0, 0, -9.81);
  double contact_margin = 0.0;  // extra range for candidate pairs, relative to particle size

  std::vector<particles::Material> materials;
  struct Interaction {
    int a = -1, b = -1;
    particles::ContactProperties properties;
  };
  std::vector<Interaction> interactions;
  std::vector<ShapeSpec> shapes;
  std::vector<ParticleSpec> particles;
  std::vector<dynamics::DriverSpec> drivers;
  std::vector<RockMassInfo> rock_masses;
  std::vector<JointSpec> joints;             // [[joint]], in file order
  std::vector<JointPlaneSpec> joint_planes;  // every plane of every rock mass, in cutting order

  DomainSpec domain;
  EquilibriumSpec equilibrium;
  OutputSpec output;
  CheckpointSpec checkpoint;
  std::vector<CheckSpec> checks;
  FosSpec fos;          // [fos]; defaults when the scene has no such table
  WaterSpec water;      // [water]; off when the scene has no such table
  SeismicSpec seismic;  // [seismic]; off when the scene has no such table
  // [[bolt]], in file order
  std::vector<BoltSpec> bolts;
  // [[operator]], in file order
  std::vector<OperatorSpec> operators;
};

}  // namespace polydem::setup
