// The whole-file digest of a checkpoint (format version 2, docs/checkpoint.md "Digest"): one
// 64-bit hash over every group, dataset, link and attribute of the file, so that a file changed
// after it was written (an attribute edited, a dataset replaced by one from another checkpoint
// with its own valid checksum, a dataset added or removed) is refused as a whole. It is generic:
// it walks the file, so datasets and attributes added to the layout later are covered without
// code of their own.
//
// The walk visits the root group, then depth first each group's links in ascending bytewise
// order of their names, a group's own record before its members. It appends to a byte string:
//   group       'G' path NUL, then its attributes
//   dataset     'D' path NUL type NUL dims NUL, then its attributes
//   soft link   'S' path NUL target NUL;  external link 'E' path NUL; other object 'O' path NUL
//   attribute   'A' name NUL type NUL count NUL raw-bytes   (each object's in ascending name
//               order; the root's "digest" attribute is left out)
// where type is "f8", "i4", "u8", "u1"... (a trailing "be" if big-endian), "s<width>" for a
// fixed-length string, "v" for a variable-length one, "c<class>" otherwise; dims are decimal,
// comma-separated ("" for a scalar); raw bytes are the values in native (little-endian) order,
// fixed-length strings with their padding; variable-length and other values add no bytes.
// The digest is checksumOfBytes() of that string (polydem-sum64 over its bytes). A dataset's
// data enter through its "checksum" attribute, which the reader verifies against the data, and
// the reader refuses datasets it does not read. Like the checksums it guards against damage and
// mixing, not against someone who recomputes it on purpose.
// python_coupling/scripts/checkpoint_summary.py computes the same independently.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace polydem::hdf5 {

inline constexpr const char* kDigestAttribute = "digest";

struct FileDigest {
  std::uint64_t digest = 0;
  std::vector<std::string> datasets;  // every dataset's path, in walk order
  std::string stream;                 // the byte string hashed (see above)
};

/// Walks the open file `file` (HDF5 errors: CheckpointError with `context` in front).
FileDigest fileDigest(hid_t file, const std::string& context);

}  // namespace polydem::hdf5
