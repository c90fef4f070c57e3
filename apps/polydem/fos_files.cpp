#include "fos_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/core/types.h"
#include "polydem/output/output_file.h"
#include "polydem/output/summary_json.h"
#include "polydem/particles/material.h"

namespace polydem::app {

namespace {

using nlohmann::json;

json optional(const std::optional<double>& v) {
  return v ? json(*v) : json();
}

json fosJson(const io::Scene& scene, const sim::FosCriterion& c, const sim::FosResult& r) {
  particles::MaterialTable table;
  for (const auto& m : scene.materials) table.add(m);
  for (const auto& i : scene.interactions) table.setInteraction(i.a, i.b, i.properties);
  table.finalize();
  const std::optional<double> f = r.factor();
  json pairs = json::array();
  std::optional<double> critical;
  for (const auto& [a, b] : sim::reducedPairs(scene)) {
    const auto& p = table.pair(a, b);
    const std::optional<double> phi =
        f ? std::optional<double>(reducedFrictionAngle(p.friction_angle, *f)) : std::nullopt;
    if (!critical) critical = phi;
    pairs.push_back({{"materials", {scene.materials[a].name, scene.materials[b].name}},
                     {"friction_angle_deg", p.friction_angle},
                     {"cohesion", p.cohesion},
                     {"critical_friction_angle_deg", optional(phi)},
                     {"critical_cohesion", f ? json(p.cohesion / *f) : json()}});
  }
  json trials = json::array();
  for (const auto& t : r.trials) {
    trials.push_back({{"factor", t.factor},
                      {"outcome", t.outcome},
                      {"displacement", t.mean_displacement},
                      {"max_displacement", t.max_displacement},
                      {"mean_speed", t.mean_speed},
                      {"time", t.time},
                      {"steps", t.steps},
                      {"state_hash", BitHasher::hex(t.state_hash)},
                      {"group", t.group},
                      {"wall_seconds", t.wall_seconds}});
  }
  return {{"scene", scene.id},
          {"scene_file", scene.file},
          {"kernel", scene.kernel},
          {"contact_model", scene.contact_model},
          {"factor_of_safety", optional(f)},
          {"bracket", {{"stable", optional(r.stable)}, {"failed", optional(r.failed)}}},
          {"resolution", r.resolution},
          {"critical_friction_angle_deg", optional(critical)},
          {"interactions", pairs},
          {"criterion",
           {{"max_time", c.max_time},
            {"settle_time", c.settle_time},
            {"speed_limit", c.speed_limit},
            {"displacement_limit", c.displacement_limit},
            {"check_every", c.check_every},
            {"label_prefix", c.label_prefix}}},
          {"ranks", r.ranks},
          {"groups", r.groups},
          {"note", r.note},
          {"trials", trials}};
}

std::string trialsCsv(const sim::FosResult& r) {
  std::ostringstream out;
  out << "trial,factor,outcome,time,mean_displacement,mean_speed\n";
  for (std::size_t i = 0; i < r.trials.size(); ++i) {
    const auto& t = r.trials[i];
    for (const auto& s : t.history) {
      out << i << ',' << num(t.factor) << ',' << t.outcome << ',' << num(s.time) << ','
          << num(s.mean_displacement) << ',' << num(s.mean_speed) << '\n';
    }
  }
  return out.str();
}

// A line plot of each trial's mean displacement against time, as SVG.
std::string displacementSvg(const io::Scene& scene, const sim::FosCriterion& c,
                            const sim::FosResult& r) {
  const double w = 720, h = 440, left = 70, right = 170, top = 40, bottom = 50;
  double t_max = 0.0, d_max = c.displacement_limit;
  for (const auto& t : r.trials) {
    for (const auto& s : t.history) {
      t_max = std::max(t_max, s.time);
      d_max = std::max(d_max, s.mean_displacement);
    }
  }
  t_max = t_max > 0 ? t_max : 1.0;
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
  s << "<line x1='" << left << "' y1='" << y(c.displacement_limit) << "' x2='" << x(t_max)
    << "' y2='" << y(c.displacement_limit) << "' stroke='grey' stroke-dasharray='4 3'/>\n<text x='"
    << x(t_max) - 4 << "' y='" << y(c.displacement_limit) - 4
    << "' text-anchor='end' fill='grey'>displacement limit</text>\n";
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

double reducedFrictionAngle(double phi_deg, double factor) {
  return radToDeg(std::atan(std::tan(degToRad(phi_deg)) / factor));
}

void writeFosFiles(const std::string& dir, const io::Scene& scene,
                   const sim::FosCriterion& criterion, const sim::FosResult& result) {
  io::createDirectories(dir);
  io::writeJsonAtomic(dir + "/fos.json", fosJson(scene, criterion, result));
  io::writeFileAtomic(dir + "/fos_trials.csv", trialsCsv(result));
  io::writeFileAtomic(dir + "/fos.svg", displacementSvg(scene, criterion, result));
}

}  // namespace polydem::app
