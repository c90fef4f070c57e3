// Editing checkpoint files behind polydem's back, for the tests of what the reader refuses:
// serial HDF5 edits, and "resealing" (recomputing the whole-file digest after an edit, as a
// deliberate forger or a buggy writer would) so that a test can reach the checks behind the
// digest.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "polydem/hdf5/file_digest.h"

namespace polydem::checkpoint::testing {

/// Opens `path` serially for writing, calls `edit` with the file id, closes it.
inline void editFile(const std::filesystem::path& path, const std::function<void(hid_t)>& edit) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  edit(f);
  H5Fclose(f);
}

/// Replaces (or creates) the scalar or vector attribute `name` of `object`; replaced rather than
/// rewritten because H5Awrite fails on densely stored attributes.
template <typename T>
void setAttribute(hid_t file, const char* object, const char* name, hid_t file_type, hid_t mem_type,
                  const std::vector<T>& values) {
  if (H5Aexists_by_name(file, object, name, H5P_DEFAULT) > 0) {
    H5Adelete_by_name(file, object, name, H5P_DEFAULT);
  }
  const hsize_t n = values.size();
  const hid_t space = n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr);
  const hid_t a = H5Acreate_by_name(file, object, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT,
                                    H5P_DEFAULT);
  H5Awrite(a, mem_type, values.data());
  H5Aclose(a);
  H5Sclose(space);
}

/// Recomputes the whole-file digest of `path` and stores it, so that the file passes the digest
/// check whatever was changed.
inline void reseal(const std::filesystem::path& path) {
  editFile(path, [](hid_t f) {
    const std::uint64_t digest = hdf5::fileDigest(f, "").digest;
    setAttribute<std::uint64_t>(f, "/", hdf5::kDigestAttribute, H5T_STD_U64LE, H5T_NATIVE_UINT64,
                                {digest});
  });
}

}  // namespace polydem::checkpoint::testing
