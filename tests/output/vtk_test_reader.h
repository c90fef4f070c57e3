// A deliberately small reader of the VTK XML files SnapshotWriter writes, for tests only: enough
// XML to find the elements and attributes, an independent base64 decoder, and the appended-data
// rules of the VTK file format (UInt64 byte-count header, offsets in base64 characters).
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace polydem::output::test {

struct XmlElement {
  std::string tag;
  std::map<std::string, std::string> attributes;
  std::string text;    // text up to the first child or the closing tag
  std::string parent;  // tag of the enclosing element
};

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// All start tags of a document in order (no comments, no CDATA: the writer uses none).
inline std::vector<XmlElement> parseXml(const std::string& doc) {
  std::vector<XmlElement> out;
  std::vector<std::string> stack;
  std::size_t pos = 0;
  while ((pos = doc.find('<', pos)) != std::string::npos) {
    const std::size_t end = doc.find('>', pos);
    if (end == std::string::npos) throw std::runtime_error("unterminated tag");
    std::string tag_text = doc.substr(pos + 1, end - pos - 1);
    pos = end + 1;
    if (tag_text.starts_with("?")) continue;
    if (tag_text.starts_with("/")) {
      if (stack.empty() || stack.back() != tag_text.substr(1)) {
        throw std::runtime_error("mismatched closing tag " + tag_text);
      }
      stack.pop_back();
      continue;
    }
    const bool self_closing = tag_text.ends_with("/");
    if (self_closing) tag_text.pop_back();
    XmlElement e;
    std::size_t i = tag_text.find_first_of(" \n");
    e.tag = tag_text.substr(0, i);
    while (i != std::string::npos && i < tag_text.size()) {
      const std::size_t eq = tag_text.find("=\"", i);
      if (eq == std::string::npos) break;
      std::size_t name_begin = tag_text.find_first_not_of(" \n", i);
      const std::size_t value_end = tag_text.find('"', eq + 2);
      e.attributes[tag_text.substr(name_begin, eq - name_begin)] =
          tag_text.substr(eq + 2, value_end - eq - 2);
      i = value_end + 1;
    }
    e.parent = stack.empty() ? "" : stack.back();
    e.text = doc.substr(pos, doc.find('<', pos) - pos);
    out.push_back(e);
    if (!self_closing) stack.push_back(e.tag);
  }
  if (!stack.empty()) throw std::runtime_error("unclosed element " + stack.back());
  return out;
}

inline std::vector<unsigned char> decodeBase64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  if (text.size() % 4 != 0) throw std::runtime_error("base64 block of odd length");
  std::vector<unsigned char> out;
  for (std::size_t i = 0; i < text.size(); i += 4) {
    int v[4];
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      if (text[i + k] == '=') {
        v[k] = 0;
        ++pad;
      } else {
        v[k] = value(text[i + k]);
        if (v[k] < 0 || pad) throw std::runtime_error("bad base64 character");
      }
    }
    const unsigned group = (v[0] << 18) | (v[1] << 12) | (v[2] << 6) | v[3];
    out.push_back(static_cast<unsigned char>(group >> 16));
    if (pad < 2) out.push_back(static_cast<unsigned char>(group >> 8));
    if (pad < 1) out.push_back(static_cast<unsigned char>(group));
  }
  return out;
}

struct DataArray {
  std::string section;  // Points, PointData, CellData, Verts, Polys
  std::string type;
  int components = 1;
  std::vector<double> values;       // every type widened to double
  std::vector<std::uint64_t> ints;  // integer types, exactly
};

struct PolyDataPiece {
  std::map<std::string, std::string> root;  // VTKFile attributes
  std::size_t points = 0, verts = 0, polys = 0;
  std::map<std::string, DataArray> arrays;  // by Name; "Polys/connectivity", "Verts/offsets"...
  std::size_t appended_chars = 0;           // length of the appended block after '_'
  std::size_t appended_used = 0;            // characters covered by the arrays, in order
  const DataArray& at(const std::string& name) const {
    const auto it = arrays.find(name);
    if (it == arrays.end()) throw std::runtime_error("no array " + name);
    return it->second;
  }
};

template <typename T>
void widen(const unsigned char* bytes, std::size_t count, DataArray& a) {
  for (std::size_t i = 0; i < count; ++i) {
    T v;
    std::memcpy(&v, bytes + i * sizeof(T), sizeof(T));
    a.values.push_back(static_cast<double>(v));
    if constexpr (!std::is_floating_point_v<T>) a.ints.push_back(static_cast<std::uint64_t>(v));
  }
}

inline std::size_t typeSize(const std::string& type) {
  if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
  if (type == "Int32") return 4;
  if (type == "UInt8") return 1;
  throw std::runtime_error("unexpected type " + type);
}

inline void decodeInto(const std::string& type, const unsigned char* bytes, std::size_t count,
                       DataArray& a) {
  if (type == "Float64") widen<double>(bytes, count, a);
  if (type == "Int64") widen<std::int64_t>(bytes, count, a);
  if (type == "UInt64") widen<std::uint64_t>(bytes, count, a);
  if (type == "Int32") widen<std::int32_t>(bytes, count, a);
  if (type == "UInt8") widen<std::uint8_t>(bytes, count, a);
}

/// Reads a .vtp written by SnapshotWriter (ascii or appended base64).
inline PolyDataPiece readPolyData(const std::string& path) {
  const std::string doc = readFile(path);
  PolyDataPiece piece;
  // The appended block is not XML: cut it out before parsing, keep its characters after '_'.
  std::string appended;
  std::string xml = doc;
  const auto open = doc.find("<AppendedData");
  if (open != std::string::npos) {
    const auto underscore = doc.find('_', open);
    const auto close = doc.find("</AppendedData>", underscore);
    appended = doc.substr(underscore + 1, close - underscore - 1);
    while (!appended.empty() && (appended.back() == '\n' || appended.back() == ' ')) {
      appended.pop_back();
    }
    xml = doc.substr(0, underscore) + doc.substr(close);
    piece.appended_chars = appended.size();
  }
  for (const auto& e : parseXml(xml)) {
    if (e.tag == "VTKFile") piece.root = e.attributes;
    if (e.tag == "Piece") {
      piece.points = std::stoul(e.attributes.at("NumberOfPoints"));
      piece.verts = std::stoul(e.attributes.at("NumberOfVerts"));
      piece.polys = std::stoul(e.attributes.at("NumberOfPolys"));
    }
    if (e.tag != "DataArray") continue;
    DataArray a;
    a.section = e.parent;
    a.type = e.attributes.at("type");
    a.components = std::stoi(e.attributes.at("NumberOfComponents"));
    if (e.attributes.at("format") == "ascii") {
      std::istringstream in(e.text);
      std::string token;
      while (in >> token) {
        a.values.push_back(std::stod(token));
        if (a.type != "Float64") a.ints.push_back(std::stoull(token));
      }
    } else {
      // Block length: header (8 bytes) first, then the values it counts.
      const std::size_t offset = std::stoul(e.attributes.at("offset"));
      if (offset != piece.appended_used) throw std::runtime_error("gap or overlap " + path);
      const auto head = decodeBase64(appended.substr(offset, 12));
      std::uint64_t bytes = 0;
      std::memcpy(&bytes, head.data(), 8);
      const std::size_t chars = 4 * ((8 + bytes + 2) / 3);
      const auto block = decodeBase64(appended.substr(offset, chars));
      if (block.size() != 8 + bytes) throw std::runtime_error("short block " + path);
      decodeInto(a.type, block.data() + 8, bytes / typeSize(a.type), a);
      piece.appended_used += chars;
    }
    const std::string name = e.attributes.at("Name");
    const std::string key =
        (name == "connectivity" || name == "offsets") ? a.section + "/" + name : name;
    piece.arrays[key] = std::move(a);
  }
  return piece;
}

}  // namespace polydem::output::test
