// Element types of checkpoint datasets: the native memory type and the explicit little-endian
// file type of each (used by hdf5_file.cpp,
// hdf5_dataset.cpp and the checkpoint benchmark).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>

#include "polydem/core/error.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::hdf5 {

template <typename T>
struct Type;
template <>
struct Type<double> {
  static constexpr int kCode = 0;
  static hid_t mem() { return H5T_NATIVE_DOUBLE; }
  static hid_t file() { return H5T_IEEE_F64LE; }
  static constexpr const char* kName = "64-bit float";
};
template <>
struct Type<std::uint64_t> {
  static constexpr int kCode = 1;
  static hid_t mem() { return H5T_NATIVE_UINT64; }
  static hid_t file() { return H5T_STD_U64LE; }
  static constexpr const char* kName = "64-bit unsigned integer";
};
template <>
struct Type<std::int64_t> {
  static constexpr int kCode = 2;
  static hid_t mem() { return H5T_NATIVE_INT64; }
  static hid_t file() { return H5T_STD_I64LE; }
  static constexpr const char* kName = "64-bit integer";
};
template <>
struct Type<std::uint32_t> {
  static constexpr int kCode = 3;
  static hid_t mem() { return H5T_NATIVE_UINT32; }
  static hid_t file() { return H5T_STD_U32LE; }
  static constexpr const char* kName = "32-bit unsigned integer";
};
template <>
struct Type<std::int32_t> {
  static constexpr int kCode = 4;
  static hid_t mem() { return H5T_NATIVE_INT32; }
  static hid_t file() { return H5T_STD_I32LE; }
  static constexpr const char* kName = "32-bit integer";
};
template <>
struct Type<std::uint8_t> {
  static constexpr int kCode = 5;
  static hid_t mem() { return H5T_NATIVE_UINT8; }
  static hid_t file() { return H5T_STD_U8LE; }
  static constexpr const char* kName = "8-bit unsigned integer";
};

/// Codes of the kinds of replicated datasets besides the element types' kCode.
inline constexpr int kStrings = 6, kText = 7;
/// File type, memory type and element size of an element type code (0..5).
hid_t fileTypeOf(int code);
hid_t memTypeOf(int code);
int bytesOf(int code);

/// Throws CheckpointError(what + ": " + HDF5's message) if `id` (an hid_t or herr_t) is negative.
template <typename Id>
Id check(Id id, const std::string& what) {
  if (id < 0) throw CheckpointError(what + ": " + hdf5ErrorMessage());
  return id;
}

/// "64-bit float", "32-bit unsigned integer", "fixed-length string"...
std::string describeType(hid_t type);
/// A fixed-length, NUL-padded string type of `size` bytes (at least 1).
Handle stringType(std::size_t size);

/// "10 x 3", "a scalar".
std::string describeDims(const std::vector<std::uint64_t>& dims);

}  // namespace polydem::hdf5
