#include "polydem/output/vtk_xml.h"

#include <bit>
#include <cstdio>

#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"

namespace polydem::output::vtk {

namespace {

constexpr char kBase64Alphabet[] =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Base64 characters of one appended block: the 8-byte header plus the values.
std::size_t base64Length(std::size_t raw_bytes) {
  return 4 * ((raw_bytes + 2) / 3);
}

/// Streams bytes into the file as one base64 block (RFC 4648, padded at the end).
class Base64Stream {
 public:
  explicit Base64Stream(AtomicFile& file) : file_(file) {}

  void put(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    const unsigned char* end = p + bytes;
    while (carried_ > 0 && carried_ < 3 && p < end) carry_[carried_++] = *p++;
    if (carried_ == 3) {
      encode(carry_, 3);
      carried_ = 0;
    }
    for (; end - p >= 3; p += 3) encode(p, 3);  // whole groups straight from the input
    while (p < end) carry_[carried_++] = *p++;
  }

  /// Pads the last group and writes out the block.
  void finish() {
    if (carried_ > 0) encode(carry_, carried_);
    carried_ = 0;
    file_.write(out_, used_);
    used_ = 0;
  }

 private:
  static constexpr std::size_t kChunk = std::size_t{1} << 16;  // characters per file write

  void encode(const unsigned char* in, int bytes) {
    const unsigned b1 = bytes > 1 ? in[1] : 0, b2 = bytes > 2 ? in[2] : 0;
    const unsigned group = (unsigned{in[0]} << 16) | (b1 << 8) | b2;
    char* out = out_ + used_;
    out[0] = kBase64Alphabet[(group >> 18) & 63];
    out[1] = kBase64Alphabet[(group >> 12) & 63];
    out[2] = bytes > 1 ? kBase64Alphabet[(group >> 6) & 63] : '=';
    out[3] = bytes > 2 ? kBase64Alphabet[group & 63] : '=';
    used_ += 4;
    if (used_ == kChunk) {
      file_.write(out_, used_);
      used_ = 0;
    }
  }

  AtomicFile& file_;
  char out_[kChunk];
  std::size_t used_ = 0;
  unsigned char carry_[3] = {0, 0, 0};
  int carried_ = 0;
};

const char* byteOrder() {
  return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
}

std::string arrayAttributes(const Array& a) {
  return cat("type=\"", a.type, "\" Name=\"", a.name, "\" NumberOfComponents=\"", a.components,
             "\"");
}

void appendAscii(std::string& out, double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  out += buffer;
}
template <typename T>
void appendAscii(std::string& out, T v) {
  out += std::to_string(
      static_cast<std::conditional_t<std::is_signed_v<T>, long long, unsigned long long>>(v));
}

void writeAsciiValues(AtomicFile& file, const Array& a) {
  std::visit(
      [&](const auto& values) {
        std::string out;
        const std::size_t per_line = static_cast<std::size_t>(a.components) * 2;
        for (std::size_t i = 0; i < values.size(); ++i) {
          out += (i % per_line == 0) ? "\n          " : " ";
          appendAscii(out, values[i]);
          if (out.size() > (std::size_t{1} << 16)) {
            file.write(out);
            out.clear();
          }
        }
        out += "\n        ";
        file.write(out);
      },
      a.make());
}

}  // namespace

std::string fileHeader(const char* type) {
  return cat("<?xml version=\"1.0\"?>\n<VTKFile type=\"", type, "\" version=\"1.0\" byte_order=\"",
             byteOrder(), "\" header_type=\"UInt64\">\n");
}

void writePiece(const std::string& path, const Piece& piece, bool binary) {
  AtomicFile file(path);
  file.write(fileHeader("PolyData"));
  file.write(cat("  <PolyData>\n    <Piece NumberOfPoints=\"", piece.points, "\" NumberOfVerts=\"",
                 piece.verts,
                 "\" NumberOfLines=\"0\" NumberOfStrips=\"0\""
                 " NumberOfPolys=\"",
                 piece.polys, "\">\n"));
  std::size_t offset = 0;
  for (const auto& section : piece.sections) {
    file.write(cat("      <", section.tag, section.attributes, ">\n"));
    for (const auto& a : section.arrays) {
      if (binary) {
        file.write(cat("        <DataArray ", arrayAttributes(a), " format=\"appended\" offset=\"",
                       offset, "\"/>\n"));
        offset += base64Length(sizeof(std::uint64_t) + a.values * a.value_bytes);
      } else {
        file.write(cat("        <DataArray ", arrayAttributes(a), " format=\"ascii\">"));
        writeAsciiValues(file, a);
        file.write("</DataArray>\n");
      }
    }
    file.write(cat("      </", section.tag, ">\n"));
  }
  file.write("    </Piece>\n  </PolyData>\n");
  if (binary) {
    file.write("  <AppendedData encoding=\"base64\">\n   _");
    Base64Stream stream(file);
    for (const auto& section : piece.sections) {
      for (const auto& a : section.arrays) {
        const std::uint64_t bytes = a.values * a.value_bytes;
        stream.put(&bytes, sizeof bytes);
        std::visit([&](const auto& v) { stream.put(v.data(), v.size() * sizeof(v[0])); }, a.make());
        stream.finish();  // each array is its own padded block
      }
    }
    file.write("\n  </AppendedData>\n");
  }
  file.write("</VTKFile>\n");
  file.commit();
}

void writeParallelHeader(const std::string& path, const Piece& piece,
                         const std::vector<std::string>& sources) {
  std::string text = fileHeader("PPolyData");
  text += "  <PPolyData GhostLevel=\"0\">\n";
  for (const auto& section : piece.sections) {
    if (section.tag == "Verts" || section.tag == "Polys") continue;  // topology: not declared
    text += cat("    <P", section.tag, section.attributes, ">\n");
    for (const auto& a : section.arrays)
      text += cat("      <PDataArray ", arrayAttributes(a), "/>\n");
    text += cat("    </P", section.tag, ">\n");
  }
  for (const auto& source : sources) text += cat("    <Piece Source=\"", source, "\"/>\n");
  text += "  </PPolyData>\n</VTKFile>\n";
  writeFileAtomic(path, text);
}

}  // namespace polydem::output::vtk
