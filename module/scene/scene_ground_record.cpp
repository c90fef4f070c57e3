// [seismic] record: the ground acceleration record of an earthquake (docs/scene-format.md
// "Earthquakes"), read from text files next to the scene: one file of rows `time, ax, ay, az`
// (`record`), or one file of samples per axis at a constant time step (`record_x`, `record_y`,
// `record_z` with `time_step`). Values are separated by commas or blanks; `#` starts a comment;
// the first line may be a header of names. `units` ("m/s^2" or "g", multiples of the scene's
// |gravity|) and `scale` apply to every sample. A problem names the scene's line and the record's.
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "polydem/core/file_kind.h"
#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

/// One line of a record: its number in the file and its values.
struct RecordRow {
  int line = 0;
  std::vector<double> values;
};

/// The path of a record file the scene names, relative to the scene file's folder (a scene
/// parsed from a string, "<...>", resolves against the working directory).
std::string recordPath(const Section& s, const std::string& name) {
  const std::filesystem::path given(name);
  const std::string& scene_file = s.context().file();
  if (given.is_absolute() || scene_file.empty() || scene_file.front() == '<') return name;
  return (std::filesystem::path(scene_file).parent_path() / given).string();
}

/// Splits `text` at commas and blanks; false if a field is not a number.
bool parseNumbers(std::string_view text, std::vector<double>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ',' || std::isspace(static_cast<unsigned char>(text[i]))))
      ++i;
    if (i == text.size()) break;
    std::size_t end = i;
    while (end < text.size() && text[end] != ',' &&
           !std::isspace(static_cast<unsigned char>(text[end])))
      ++end;
    std::string_view field = text.substr(i, end - i);
    if (field.size() > 1 && field.front() == '+') field.remove_prefix(1);
    double x = 0.0;
    const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), x);
    if (ec != std::errc() || ptr != field.data() + field.size()) return false;
    out.push_back(x);
    i = end;
  }
  return true;
}

/// The rows of numbers of the record file `key` names, comments and blank lines left out, and a
/// first line of names (a header) too.
std::vector<RecordRow> readRows(const Section& s, std::string_view key, std::string& shown) {
  shown = s.requiredString(key);
  const std::string path = recordPath(s, shown);
  const std::string problem = notARegularFile(path);
  std::ifstream in(path);
  if (!problem.empty() || !in) {
    s.fail(key, cat("cannot open the record '", path, "'", problem.empty() ? "" : ": ", problem));
  }
  std::vector<RecordRow> rows;
  std::string text;
  bool first = true;
  for (int line = 1; std::getline(in, text); ++line) {
    if (const auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    if (text.find_first_not_of(" \t\r,") == std::string::npos) continue;
    RecordRow row{line, {}};
    if (!parseNumbers(text, row.values)) {
      if (first) {  // a header of column names
        first = false;
        continue;
      }
      s.fail(key, cat(shown, ":", line, ": '", text, "' is not a row of numbers"));
    }
    first = false;
    for (const double x : row.values) {
      if (!std::isfinite(x)) s.fail(key, cat(shown, ":", line, ": a value is not finite"));
    }
    rows.push_back(std::move(row));
  }
  if (in.bad()) s.fail(key, cat("cannot read the record '", path, "'"));
  return rows;
}

/// `record`: rows of time, ax, ay, az.
void readTable(const Section& s, setup::SeismicSpec& e) {
  std::string shown;
  const auto rows = readRows(s, "record", shown);
  e.record_file = shown;
  for (const auto& row : rows) {
    if (row.values.size() != 4) {
      s.fail("record", cat(shown, ":", row.line, ": expected 4 numbers (time in s, ax, ay, az), ",
                           "got ", row.values.size()));
    }
    const double t = row.values[0];
    if (t < 0.0) s.fail("record", cat(shown, ":", row.line, ": time ", t, " s is before 0"));
    if (!e.record_time.empty() && !(t > e.record_time.back())) {
      s.fail("record", cat(shown, ":", row.line, ": time ", t, " s does not follow ",
                           e.record_time.back(), " s (times must increase)"));
    }
    e.record_time.push_back(t);
    e.record_acceleration.emplace_back(row.values[1], row.values[2], row.values[3]);
  }
}

/// `record_x`, `record_y`, `record_z`: samples at time_step, from t = 0.
void readComponents(const Section& s, setup::SeismicSpec& e) {
  if (!s.has("time_step")) {
    s.fail(s.has("record_x") ? "record_x" : (s.has("record_y") ? "record_y" : "record_z"),
           "give the samples' time_step too (e.g. time_step = \"0.01 s\")");
  }
  const double dt = s.requiredNumber("time_step", Quantity::kTime, Range::kPositive);
  std::size_t count = 0;
  std::string first_key;
  std::array<std::vector<double>, 3> samples;
  const std::array<const char*, 3> keys{"record_x", "record_y", "record_z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!s.has(keys[axis])) continue;
    std::string shown;
    for (const auto& row : readRows(s, keys[axis], shown)) {
      samples[axis].insert(samples[axis].end(), row.values.begin(), row.values.end());
    }
    e.record_file += (e.record_file.empty() ? "" : ", ") + shown;
    if (!first_key.empty() && samples[axis].size() != count) {
      s.fail(keys[axis], cat(shown, " has ", samples[axis].size(), " samples, ", first_key, " has ",
                             count, ": the components must have the same length"));
    }
    if (first_key.empty()) first_key = keys[axis];
    count = samples[axis].size();
  }
  for (std::size_t i = 0; i < count; ++i) {
    e.record_time.push_back(static_cast<double>(i) * dt);
    Vec3 a = Vec3::Zero();
    for (int axis = 0; axis < 3; ++axis) {
      if (!samples[axis].empty()) a[axis] = samples[axis][i];
    }
    e.record_acceleration.push_back(a);
  }
}

}  // namespace

bool readGroundRecord(const Section& s, const setup::Setup& scene, setup::SeismicSpec& e) {
  const bool table = s.has("record");
  const bool components = s.has("record_x") || s.has("record_y") || s.has("record_z");
  if (!table && !components) {
    for (const char* key : {"time_step", "units", "scale"}) {
      if (s.has(key)) s.fail(key, "belongs to a record: give record (or record_x/y/z) too");
    }
    return false;
  }
  if (table && components) s.fail("record_x", "give either record or record_x/y/z, not both");
  if (table && s.has("time_step")) {
    s.fail("time_step", "the record's first column gives its times: leave out time_step");
  }
  for (const char* key : {"kh", "kv", "azimuth"}) {
    if (s.has(key)) {
      s.fail(key, "a record replaces the pseudo-static load: give either kh/kv or a record");
    }
  }
  const std::string units = s.choice("units", {"m/s^2", "g"}, "m/s^2");
  const double scale = s.number("scale", Quantity::kDimensionless, 1.0);
  if (!std::isfinite(scale)) s.fail("scale", "must be a finite number");
  double factor = scale;
  if (units == "g") {
    if (!(scene.gravity.norm() > 0.0)) {
      s.fail("units", "the record is in g, but [simulation] gravity is zero");
    }
    factor *= scene.gravity.norm();
  }
  if (table) {
    readTable(s, e);
  } else {
    readComponents(s, e);
  }
  const char* key = table ? "record" : "record_x";
  if (e.record_time.size() < 2) {
    s.fail(key, cat(e.record_file, " has ", e.record_time.size(),
                    " sample(s): a record needs at least two"));
  }
  for (Vec3& a : e.record_acceleration) a *= factor;
  return true;
}

}  // namespace polydem::scene::detail
