// The VTK XML PolyData format as SnapshotWriter writes it: a piece (.vtp) described as sections of
// named arrays, written as ASCII or as base64 "appended" data, and the parallel header (.pvtp) that
// declares the same arrays and lists the pieces. Internal to output (vtk_writer.cpp uses it).
//
// Appended base64 (VTK file format, "appended" data with encoding="base64", header_type UInt64):
// after the '_' that opens <AppendedData>, each array is one base64 block encoding an 8-byte
// unsigned byte count followed by that many bytes of values (host byte order, declared in the
// file); a block is padded on its own, and a DataArray's `offset` counts base64 characters from
// the '_' to the start of its block.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace polydem::output::vtk {

using Values =
    std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::uint64_t>,
                 std::vector<std::int32_t>, std::vector<std::uint8_t>>;

template <typename T>
constexpr const char* vtkType() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::uint64_t>) return "UInt64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

/// A named data array of a piece. Its values are made by `make` only while the piece is being
/// written, so that one array at a time is in memory.
struct Array {
  std::string name;
  const char* type = "";
  int components = 1;
  std::size_t values = 0;  // tuples * components
  std::size_t value_bytes = 0;
  std::function<Values()> make;
};

template <typename T>
Array array(std::string name, int components, std::size_t tuples,
            std::function<std::vector<T>()> make) {
  return {std::move(name),     vtkType<T>(), components,
          tuples * components, sizeof(T),    [m = std::move(make)]() { return Values(m()); }};
}

/// One XML element of a piece holding arrays: <PointData>, <CellData>, <Points>, <Verts>, ...
struct Section {
  std::string tag;
  std::string attributes;  // e.g. ` Scalars="speed"`
  std::vector<Array> arrays;
};

/// One .vtp piece: counts of points and cells and its sections.
struct Piece {
  std::size_t points = 0, verts = 0, polys = 0;
  std::vector<Section> sections;
};

/// "<?xml ...?>" and the opening <VTKFile> of a file of `type` (PolyData, PPolyData, Collection).
std::string fileHeader(const char* type);

/// Writes one .vtp piece atomically (temporary name, then rename); arrays are made, encoded and
/// dropped one at a time. Throws polydem::Error naming the path.
void writePiece(const std::string& path, const Piece& piece, bool binary);

/// Writes the .pvtp that lists `sources` (paths relative to the .pvtp) and declares the arrays of
/// `piece` (its topology sections Verts/Polys are not declared, as the format wants).
void writeParallelHeader(const std::string& path, const Piece& piece,
                         const std::vector<std::string>& sources);

}  // namespace polydem::output::vtk
