#include "fos_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/core/types.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/output/output_file.h"
#include "polydem/output/summary_json.h"
#include "polydem/particles/material.h"

namespace polydem::app {

namespace {

using nlohmann::json;

json optional(const std::optional<double>& v) {
  return v ? json(*v) : json();
}

json criterionJson(const run::FosCriterion& c) {
  return {{"description", c.describe()},
          {"max_time", c.max_time},
          {"time_cap", c.time_cap},
          {"settle_time", c.window},
          {"force_ratio", c.force_ratio},
          {"speed_decay", c.speed_decay},
          {"moved_fraction", c.moved_fraction},
          {"growth_fraction", c.growth_fraction},
          {"rest_fraction", c.rest_fraction},
          {"local_damping", c.local_damping},
          {"local_damping_from",
           c.damping_from_scene ? "[fos] local_damping" : "default: 3DEC's static solution"},
          {"speed_limit", optional(c.speed_limit)},
          {"displacement_limit", optional(c.displacement_limit)},
          {"check_every", c.check_every},
          {"label_prefix", c.label_prefix}};
}

json trialJson(const run::FosTrial& t) {
  json history = json::array();
  for (const auto& s : t.history) {
    history.push_back(
        {s.time, s.mean_displacement, s.mean_speed, s.max_speed, s.force_ratio, s.max_move});
  }
  return {{"factor", t.factor},
          {"outcome", t.outcome},
          {"displacement", t.mean_displacement},
          {"max_displacement", t.max_displacement},
          {"max_reach_fraction", t.max_move},
          {"mean_speed", t.mean_speed},
          {"max_speed", t.max_speed},
          {"force_ratio", t.force_ratio},
          {"time", t.time},
          {"steps", t.steps},
          {"extended", t.extended},
          {"state_hash", BitHasher::hex(t.state_hash)},
          {"group", t.group},
          {"round", t.round},
          {"wall_seconds", t.wall_seconds},
          {"history", history}};
}

// Each reduced [[joint]] with its strength and, when F is known, the strength the reduction
// gives it at F (read back from the reduced scene, so that it is whatever the joint's law does).
json jointsJson(const setup::Setup& scene, const std::optional<double>& f) {
  const std::optional<setup::Setup> at_f =
      f ? std::optional<setup::Setup>(run::reduceStrength(scene, *f)) : std::nullopt;
  json joints = json::array();
  for (const int k : run::reducedJoints(scene)) {
    const setup::JointSpec& j = scene.joints[k];
    const dynamics::JointLawInfo& info = dynamics::jointLaw(j.law.law);
    json e = {{"name", j.name}, {"law", j.lawName()}};
    // Each parameter that strength reduction scales, with its value at F (json null until F is
    // known); a law whose mobilized strength is divided as a whole reports the divisor.
    json parameters = json::object(), critical = json::object();
    for (std::size_t i = 0; i < info.parameters.size(); ++i) {
      const dynamics::LawParameter& p = info.parameters[i];
      if (p.reduction == dynamics::Reduction::kNone) continue;
      parameters[p.name] = j.law.values[i];
      critical[p.name] = at_f ? json(at_f->joints[k].law.values[i]) : json();
    }
    e["parameters"] = parameters;
    e["critical"] = critical;
    if (info.reduces_mobilized_strength) {
      e["critical_strength_divisor"] = at_f ? json(at_f->joints[k].law.strength_divisor) : json();
    }
    const int phi = dynamics::parameterIndex(info, "friction_angle");
    e["critical_friction_angle_deg"] =
        at_f && phi >= 0 ? json(at_f->joints[k].law.values[phi]) : json();
    joints.push_back(e);
  }
  return joints;
}

json mechanismJson(const run::FosMechanism& m, const std::string& picture) {
  json blocks = json::array();
  for (const auto& b : m.blocks) {
    blocks.push_back(
        {{"uid", b.uid},
         {"label", b.label},
         {"mode", b.mode},
         {"displacement", {b.displacement.x(), b.displacement.y(), b.displacement.z()}},
         {"rotation_deg", b.rotation_deg},
         {"size", b.size},
         {"reach", b.reach},
         {"contacts", b.contacts},
         {"seat_slip", b.seat_slip}});
  }
  json slips = json::array();
  for (const auto& s : m.slips) {
    slips.push_back({{"name", s.name},
                     {"kind", s.joint >= 0 ? "joint" : "material pair"},
                     {"contacts", s.contacts},
                     {"slipping", s.slipping},
                     {"total_slip", s.total_slip},
                     {"max_slip", s.max_slip}});
  }
  return {{"summary", m.summary},
          {"factor", m.factor},
          {"folder", m.dir},
          {"same_bits_as_search", m.same_bits},
          {"decided_time", m.decided_time},
          {"time", m.time},
          {"max_reach", m.max_reach},
          {"steps", m.steps},
          {"stopped_by", m.stopped_by},
          {"snapshots", m.snapshots},
          {"picture", picture.empty() ? json() : json(picture)},
          {"free_blocks", m.free_blocks},
          {"moving_blocks", m.blocks.size()},
          {"modes", m.modes},
          {"governing", m.governing.empty() ? json() : json(m.governing)},
          {"slip", slips},
          {"blocks", blocks},
          {"thresholds",
           {{"move_share_of_largest", run::kMoveShare},
            {"rest_fraction_of_size", run::kRestFraction},
            {"run_on_fraction_of_size", run::kRunOnFraction},
            {"rotation_share", run::kRotationShare},
            {"pivot_slip_share", run::kPivotSlipShare}}}};
}

json fosJson(const setup::Setup& scene, const run::FosCriterion& c, const run::FosResult& r,
             const std::string& resume_command, const run::FosMechanism* mechanism,
             const std::string& picture) {
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
  table.finalize();
  const std::optional<double> f = r.factor();
  json pairs = json::array();
  for (const auto& [a, b] : run::reducedPairs(scene)) {
    const auto& p = table.pair(a, b);
    const json phi = f ? json(reducedFrictionAngle(p.friction_angle, *f)) : json();
    pairs.push_back({{"name", scene.materials[a].name + "/" + scene.materials[b].name},
                     {"materials", {scene.materials[a].name, scene.materials[b].name}},
                     {"friction_angle_deg", p.friction_angle},
                     {"cohesion", p.cohesion},
                     {"critical_friction_angle_deg", phi},
                     {"critical_cohesion", f ? json(p.cohesion / *f) : json()}});
  }
  const json joints = jointsJson(scene, f);
  // The governing interaction's critical friction angle where it is reduced, else the first
  // reduced joint's, else the first reduced pair's.
  json critical;
  for (const json* list : {&joints, static_cast<const json*>(&pairs)}) {
    for (const json& e : *list) {
      if (mechanism && mechanism->governing == e["name"].get<std::string>()) {
        critical = e["critical_friction_angle_deg"];
      }
    }
  }
  if (critical.is_null() && !joints.empty()) critical = joints[0]["critical_friction_angle_deg"];
  if (critical.is_null() && !pairs.empty()) critical = pairs[0]["critical_friction_angle_deg"];
  json trials = json::array();
  for (const auto& t : r.trials) trials.push_back(trialJson(t));
  json j = {{"scene", scene.id},
            {"scene_file", scene.file},
            {"scene_path", std::filesystem::absolute(scene.file).string()},
            {"scene_hash", sceneHash(scene.text)},
            {"kernel", scene.kernel},
            {"contact_model", scene.contact_model},
            {"complete", r.complete},
            {"stop_signal", r.complete ? json() : json(r.stop_signal)},
            {"resume_command", resume_command.empty() ? json() : json(resume_command)},
            {"factor_of_safety", optional(f)},
            {"bracket", {{"stable", optional(r.stable)}, {"failed", optional(r.failed)}}},
            {"resolved", r.resolved},
            {"resolution", r.resolution},
            {"f_min", scene.fos.f_min},
            {"f_max", scene.fos.f_max},
            {"critical_friction_angle_deg", critical},
            {"interactions", pairs},
            {"joints", joints},
            {"bolts",
             scene.bolts.empty() ? json() : json(scene.fos.reduce_bolts ? "reduced" : "unreduced")},
            {"governing",
             mechanism && !mechanism->governing.empty() ? json(mechanism->governing) : json()},
            {"mechanism", mechanism ? mechanismJson(*mechanism, picture) : json()},
            {"criterion", criterionJson(c)},
            {"ranks", r.ranks},
            {"groups", r.groups},
            {"rounds_complete", r.rounds_complete},
            {"settled_state",
             {{"used", r.settle_used},
              {"steps", r.settle_steps},
              {"reached", r.settle_reached},
              {"wall_seconds", r.settle_wall_seconds}}},
            {"note", r.note},
            {"trials", trials}};
  return j;
}

run::FosTrial trialFromJson(const json& j) {
  run::FosTrial t;
  t.factor = j.at("factor").get<double>();
  t.outcome = j.at("outcome").get<std::string>();
  t.mean_displacement = j.at("displacement").get<double>();
  t.max_displacement = j.at("max_displacement").get<double>();
  t.max_move = j.value("max_reach_fraction", 0.0);
  t.mean_speed = j.at("mean_speed").get<double>();
  t.max_speed = j.at("max_speed").get<double>();
  t.force_ratio = j.at("force_ratio").get<double>();
  t.time = j.at("time").get<double>();
  t.steps = j.at("steps").get<std::int64_t>();
  t.extended = j.at("extended").get<bool>();
  t.state_hash = std::stoull(j.at("state_hash").get<std::string>(), nullptr, 16);
  t.group = j.at("group").get<int>();
  t.round = j.at("round").get<int>();
  t.wall_seconds = j.at("wall_seconds").get<double>();
  for (const json& s : j.at("history")) {
    t.history.push_back({s.at(0).get<double>(), s.at(1).get<double>(), s.at(2).get<double>(),
                         s.at(3).get<double>(), s.at(4).get<double>(),
                         s.size() > 5 ? s.at(5).get<double>() : 0.0});
  }
  return t;
}

std::string trialsCsv(const run::FosResult& r) {
  std::ostringstream out;
  out << "trial,factor,outcome,time,mean_displacement,mean_speed,max_speed,force_ratio,"
         "max_reach_fraction\n";
  for (std::size_t i = 0; i < r.trials.size(); ++i) {
    const auto& t = r.trials[i];
    for (const auto& s : t.history) {
      out << i << ',' << num(t.factor) << ',' << t.outcome << ',' << num(s.time) << ','
          << num(s.mean_displacement) << ',' << num(s.mean_speed) << ',' << num(s.max_speed) << ','
          << num(s.force_ratio) << ',' << num(s.max_move) << '\n';
    }
  }
  return out.str();
}

// A line plot of each trial's mean displacement against time, as SVG.
std::string displacementSvg(const setup::Setup& scene, const run::FosCriterion& c,
                            const run::FosResult& r) {
  const double w = 720, h = 440, left = 70, right = 170, top = 40, bottom = 50;
  double t_max = 0.0, d_max = c.displacement_limit.value_or(0.0);
  for (const auto& t : r.trials) {
    for (const auto& s : t.history) {
      t_max = std::max(t_max, s.time);
      d_max = std::max(d_max, s.mean_displacement);
    }
  }
  t_max = t_max > 0 ? t_max : 1.0;
  d_max = d_max > 0 ? d_max : 1.0;
  const auto x = [&](double v) { return left + (w - left - right) * v / t_max; };
  const auto y = [&](double v) { return h - bottom - (h - top - bottom) * v / d_max; };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h
    << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' "
       "fill='white'/>\n";
  s << "<text x='" << left << "' y='22' font-size='14'>" << scene.id
    << ": mean displacement of the free blocks per trial (strength divided by F)</text>\n";
  s << "<line x1='" << left << "' y1='" << y(0) << "' x2='" << x(t_max) << "' y2='" << y(0)
    << "' stroke='black'/>\n<line x1='" << left << "' y1='" << y(0) << "' x2='" << left << "' y2='"
    << y(d_max) << "' stroke='black'/>\n";
  for (int k = 0; k <= 4; ++k) {
    const double tv = t_max * k / 4, dv = d_max * k / 4;
    s << "<text x='" << x(tv) << "' y='" << h - bottom + 18 << "' text-anchor='middle'>" << num(tv)
      << "</text>\n<text x='" << left - 6 << "' y='" << y(dv) + 4 << "' text-anchor='end'>"
      << num(dv) << "</text>\n";
  }
  s << "<text x='" << 0.5 * (left + w - right) << "' y='" << h - 12
    << "' text-anchor='middle'>time [s]</text>\n<text x='16' y='" << 0.5 * h
    << "' transform='rotate(-90 16 " << 0.5 * h
    << ")' text-anchor='middle'>mean displacement [m]</text>\n";
  if (c.displacement_limit) {
    const double limit = *c.displacement_limit;
    s << "<line x1='" << left << "' y1='" << y(limit) << "' x2='" << x(t_max) << "' y2='"
      << y(limit) << "' stroke='grey' stroke-dasharray='4 3'/>\n<text x='" << x(t_max) - 4
      << "' y='" << y(limit) - 4 << "' text-anchor='end' fill='grey'>displacement limit</text>\n";
  }
  for (std::size_t i = 0; i < r.trials.size(); ++i) {
    const auto& t = r.trials[i];
    // Stable trials in blue shades, failed and moving ones in red shades.
    const int shade = static_cast<int>(40 + (i * 37) % 150);
    const std::string colour =
        t.stable() ? cat("rgb(", shade / 3, ",", shade / 2, ",", 160 + shade / 3, ")")
                   : cat("rgb(", 160 + shade / 3, ",", shade / 3, ",", shade / 4, ")");
    s << "<polyline fill='none' stroke='" << colour << "' stroke-width='1.5' points='";
    for (const auto& p : t.history) {
      s << x(p.time) << ',' << y(std::min(p.mean_displacement, d_max)) << ' ';
    }
    s << "'/>\n<text x='" << w - right + 10 << "' y='" << top + 16 * (i + 1) << "' fill='" << colour
      << "'>F = " << num(t.factor) << ": " << t.outcome << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace

std::string sceneHash(const std::string& text) {
  BitHasher h;
  h.add(static_cast<std::uint64_t>(text.size()));
  for (std::size_t i = 0; i < text.size(); i += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, text.data() + i, std::min<std::size_t>(8, text.size() - i));
    h.add(word);
  }
  return BitHasher::hex(h.value());
}

FosRun readFosRun(const std::string& dir) {
  const std::string path = dir + "/fos.json";
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open it: nothing to resume in " + dir);
  try {
    const json j = json::parse(in);
    FosRun run;
    run.scene_path = j.at("scene_path").get<std::string>();
    run.scene_hash = j.at("scene_hash").get<std::string>();
    run.f_min = j.at("f_min").get<double>();
    run.f_max = j.at("f_max").get<double>();
    run.resolution = j.at("resolution").get<double>();
    run.max_time = j.at("criterion").at("max_time").get<double>();
    run.kernel = j.at("kernel").get<std::string>();
    run.contact_model = j.at("contact_model").get<std::string>();
    run.complete = j.at("complete").get<bool>();
    run::FosResult& r = run.result;
    r.rounds_complete = j.at("rounds_complete").get<int>();
    r.groups = j.at("groups").get<int>();
    for (const json& t : j.at("trials")) r.trials.push_back(trialFromJson(t));
    return run;
  } catch (const json::exception& e) {
    throw InputError(path, 0, cat("not a fos.json that polydem fos can resume: ", e.what()));
  }
}

double reducedFrictionAngle(double phi_deg, double factor) {
  return radToDeg(std::atan(std::tan(degToRad(phi_deg)) / factor));
}

std::vector<std::string> criticalStrengthLines(const setup::Setup& scene, double factor) {
  const setup::Setup at_f = run::reduceStrength(scene, factor);
  std::vector<std::string> lines;
  for (const int k : run::reducedJoints(scene)) {
    const setup::JointSpec &j = scene.joints[k], &c = at_f.joints[k];
    const dynamics::JointLawInfo& info = dynamics::jointLaw(j.law.law);
    std::string line = cat("joint '", j.name, "' (", j.lawName(), "):");
    const char* separator = " ";
    for (std::size_t i = 0; i < info.parameters.size(); ++i) {
      const dynamics::LawParameter& p = info.parameters[i];
      if (p.reduction == dynamics::Reduction::kNone) continue;
      if (p.reduction == dynamics::Reduction::kDivide && j.law.values[i] == 0.0) continue;
      const char* unit = p.unit == dynamics::ParameterUnit::kAngle ? " deg" : " Pa";
      const char* how = p.reduction == dynamics::Reduction::kTangent ? " divided by F" : " / F";
      line += cat(separator, p.name, " ", num(c.law.values[i]), unit, " (", num(j.law.values[i]),
                  unit, how, ")");
      separator = ", ";
    }
    if (info.reduces_mobilized_strength) {
      line += cat(separator, "shear strength divided by ", num(c.law.strength_divisor));
    }
    lines.push_back(line);
  }
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
  table.finalize();
  for (const auto& [a, b] : run::reducedPairs(scene)) {
    const double phi = table.pair(a, b).friction_angle;
    lines.push_back(cat("pair ", scene.materials[a].name, "/", scene.materials[b].name,
                        ": friction angle ", num(reducedFrictionAngle(phi, factor)), " deg (",
                        num(phi), " deg divided by F)"));
  }
  return lines;
}

void writeFosFiles(const std::string& dir, const setup::Setup& scene,
                   const run::FosCriterion& criterion, const run::FosResult& result,
                   const std::string& resume_command, const run::FosMechanism* mechanism,
                   const std::string& picture) {
  output::createDirectories(dir);
  output::writeJsonAtomic(dir + "/fos.json",
                          fosJson(scene, criterion, result, resume_command, mechanism, picture));
  output::writeFileAtomic(dir + "/fos_trials.csv", trialsCsv(result));
  output::writeFileAtomic(dir + "/fos.svg", displacementSvg(scene, criterion, result));
}

}  // namespace polydem::app
