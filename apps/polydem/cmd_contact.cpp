// polydem contact: resolve the contact between two vertex lists per input line.
//
//   input  (stdin or --in FILE), one JSON object per line:
//     {"a": [[x,y,z], ...], "b": [[x,y,z], ...]}            (optional "id": anything, echoed back)
//   output (stdout), one JSON object per input line:
//     {"contact": true, "normal": [...], "point": [...], "depth": d}   or   {"contact": false}
// The whole input is read and checked before anything is written, so a malformed line stops the
// command with its line number and no partial output.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "polydem/contact/contact.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"

namespace polydem::app {

namespace {

using nlohmann::json;

struct Query {
  int line = 0;
  json id;
  geometry::ConvexPolyhedron a, b;
};

std::vector<Vec3> readVertices(const json& j, const std::string& key, int line) {
  const auto it = j.find(key);
  if (it == j.end()) throw Error(cat("line ", line, ": missing \"", key, "\""));
  if (!it->is_array()) throw Error(cat("line ", line, ": \"", key, "\" must be an array"));
  std::vector<Vec3> v;
  for (std::size_t i = 0; i < it->size(); ++i) {
    const json& p = (*it)[i];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
        !p[2].is_number()) {
      throw Error(cat("line ", line, ": \"", key, "\" vertex ", i, " is not [x, y, z]"));
    }
    v.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  return v;
}

geometry::ConvexPolyhedron buildBody(const std::vector<Vec3>& vertices, const std::string& key,
                                     int line) {
  geometry::BuildReport report;
  geometry::ConvexPolyhedron poly;
  try {
    poly = geometry::ConvexPolyhedron::fromPoints(vertices, &report);
  } catch (const GeometryError& e) {
    throw Error(cat("line ", line, ": body \"", key, "\": ", e.what()));
  }
  const auto dropped = report.interior_points.size() + report.boundary_points.size();
  if (dropped > 0) {
    log::warning(cat("line ", line, ": body \"", key, "\": ", dropped,
                     " point(s) are not corners of the hull and were ignored"));
  }
  return poly;
}

Query parseLine(const std::string& text, int line) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw Error(cat("line ", line, ": not valid JSON (", e.what(), ")"));
  }
  if (!j.is_object()) throw Error(cat("line ", line, ": expected a JSON object"));
  for (const auto& [key, value] : j.items()) {
    if (key != "a" && key != "b" && key != "id") {
      throw Error(cat("line ", line, ": unknown key \"", key, "\" (expected a, b, id)"));
    }
  }
  Query q;
  q.line = line;
  if (j.contains("id")) q.id = j["id"];
  q.a = buildBody(readVertices(j, "a", line), "a", line);
  q.b = buildBody(readVertices(j, "b", line), "b", line);
  return q;
}

json vec(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json resolve(const contact::Kernel& kernel, const Query& q) {
  std::vector<Vec3> va, vb;
  const auto a = contact::placeBody(q.a, Vec3::Zero(), Mat3::Identity(), va);
  const auto b = contact::placeBody(q.b, Vec3::Zero(), Mat3::Identity(), vb);
  const contact::Contact c = kernel.collide(a, b, nullptr);
  json out;
  if (!q.id.is_null()) out["id"] = q.id;
  out["contact"] = c.touching;
  if (c.touching) {
    out["normal"] = vec(c.normal);
    out["point"] = vec(c.point);
    out["depth"] = c.depth;
    if (c.model == contact::ForceModel::kPotential) out["potential"] = c.potential;
    if (c.status != contact::Status::kOk) out["status"] = static_cast<int>(c.status);
  }
  return out;
}

}  // namespace

int contactCommand(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  if (args.flag("help")) {
    std::printf(
        "usage: polydem contact [--kernel NAME] [--in FILE]\n"
        "  reads {\"a\": [[x,y,z],...], \"b\": [[x,y,z],...]} per line (stdin by default) and\n"
        "  writes {\"contact\": true, \"normal\": [..], \"point\": [..], \"depth\": d} per line.\n"
        "  normal points from b into a; kernels: %s\n",
        join(contact::kernelNames(), ", ").c_str());
    return 0;
  }
  const std::string kernel_name = args.value("kernel", "gjk-epa-ipm");
  const auto input = args.value("in");
  args.rejectUnknown();
  if (!args.positional().empty()) throw UsageError("unexpected argument " + args.positional()[0]);
  const auto kernel = contact::makeKernel(kernel_name);

  std::ifstream file;
  if (input) {
    file.open(*input);
    if (!file) throw Error("cannot open " + *input);
  }
  std::istream& in = input ? static_cast<std::istream&>(file) : std::cin;
  const std::string source = input ? *input : "<stdin>";
  std::vector<Query> queries;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      queries.push_back(parseLine(text, line));
    } catch (const Error& e) {
      throw Error(source + ": " + e.what());
    }
  }
  for (const auto& q : queries) std::cout << resolve(*kernel, q).dump() << '\n';
  std::cout.flush();
  return 0;
}

int kernelsCommand(int argc, char** argv) {
  Args args(argc, argv);
  args.rejectUnknown();
  for (const auto& name : contact::kernelNames()) std::printf("%s\n", name.c_str());
  return 0;
}

}  // namespace polydem::app
