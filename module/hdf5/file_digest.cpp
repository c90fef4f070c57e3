#include "polydem/hdf5/file_digest.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/checksum.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::hdf5 {

namespace {

herr_t collectName(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

herr_t collectAttribute(hid_t, const char* name, const H5A_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

class Walker {
 public:
  Walker(hid_t file, std::string context) : file_(file), context_(std::move(context)) {}

  FileDigest run() {
    object("/");
    FileDigest d;
    d.stream = std::move(out_);
    d.digest = checksumOfBytes(d.stream);
    d.datasets = std::move(datasets_);
    return d;
  }

 private:
  template <typename Id>
  Id check(Id id, const std::string& what) const {
    if (id < 0) throw CheckpointError(context_ + what + ": " + hdf5::hdf5ErrorMessage());
    return id;
  }

  void text(const std::string& s) {
    out_ += s;
    out_.push_back('\0');
  }

  /// "f8", "i4", "u1", "s12", "v"...: the descriptor of an HDF5 type.
  static std::string typeName(hid_t type) {
    const std::size_t size = H5Tget_size(type);
    const char* order = H5Tget_order(type) == H5T_ORDER_BE ? "be" : "";
    switch (H5Tget_class(type)) {
      case H5T_INTEGER:
        return cat(H5Tget_sign(type) == H5T_SGN_NONE ? "u" : "i", size, order);
      case H5T_FLOAT:
        return cat("f", size, order);
      case H5T_STRING:
        return H5Tis_variable_str(type) > 0 ? std::string("v") : cat("s", size);
      default:
        return cat("c", static_cast<int>(H5Tget_class(type)));
    }
  }

  void object(const std::string& path) {
    // H5Iget_type of the opened object: the same call in every HDF5 version since 1.8.
    H5I_type_t kind = H5I_BADID;
    {
      Handle obj(check(H5Oopen(file_, path.c_str(), H5P_DEFAULT), "cannot open " + path), H5Oclose);
      kind = H5Iget_type(obj.get());
    }
    if (kind == H5I_GROUP) {
      out_ += 'G';
      text(path);
      attributes(path);
      members(path);
    } else if (kind == H5I_DATASET) {
      out_ += 'D';
      text(path);
      Handle d(check(H5Dopen2(file_, path.c_str(), H5P_DEFAULT), "cannot open " + path), H5Dclose);
      Handle type(H5Dget_type(d.get()), H5Tclose);
      Handle space(H5Dget_space(d.get()), H5Sclose);
      text(typeName(type.get()));
      text(dims(space.get()));
      attributes(path);
      datasets_.push_back(path);
    } else {
      out_ += 'O';
      text(path);
    }
  }

  void members(const std::string& group) {
    std::vector<std::string> names;
    Handle g(check(H5Gopen2(file_, group.c_str(), H5P_DEFAULT), "cannot open " + group), H5Gclose);
    check(H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collectName, &names),
          "cannot list " + group);
    std::sort(names.begin(), names.end());
    for (const auto& name : names) {
      const std::string path = group == "/" ? "/" + name : group + "/" + name;
      H5L_info_t link{};
      check(H5Lget_info(file_, path.c_str(), &link, H5P_DEFAULT), "cannot inspect link " + path);
      if (link.type == H5L_TYPE_HARD) {
        object(path);
      } else if (link.type == H5L_TYPE_SOFT) {
        std::string target(link.u.val_size, '\0');
        check(H5Lget_val(file_, path.c_str(), target.data(), target.size(), H5P_DEFAULT),
              "cannot read link " + path);
        out_ += 'S';
        text(path);
        text(target.c_str());
      } else {
        out_ += 'E';
        text(path);
      }
    }
  }

  static std::string dims(hid_t space) {
    const int n = H5Sget_simple_extent_ndims(space);
    if (n <= 0) return n == 0 ? "" : "?";
    std::vector<hsize_t> d(static_cast<std::size_t>(n));
    H5Sget_simple_extent_dims(space, d.data(), nullptr);
    std::vector<std::string> parts;
    for (auto x : d) parts.push_back(cat(x));
    return join(parts, ",");
  }

  void attributes(const std::string& path) {
    std::vector<std::string> names;
    Handle obj(check(H5Oopen(file_, path.c_str(), H5P_DEFAULT), "cannot open " + path), H5Oclose);
    hsize_t index = 0;
    check(H5Aiterate2(obj.get(), H5_INDEX_NAME, H5_ITER_INC, &index, collectAttribute, &names),
          "cannot list the attributes of " + path);
    std::sort(names.begin(), names.end());
    for (const auto& name : names) {
      if (path == "/" && name == kDigestAttribute) continue;
      attribute(obj.get(), path, name);
    }
  }

  void attribute(hid_t obj, const std::string& path, const std::string& name) {
    const std::string what = "attribute " + name + " of " + path;
    Handle a(check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "cannot open " + what), H5Aclose);
    Handle type(H5Aget_type(a.get()), H5Tclose);
    Handle space(H5Aget_space(a.get()), H5Sclose);
    const hssize_t count = H5Sget_simple_extent_npoints(space.get());
    out_ += 'A';
    text(name);
    const std::string type_name = typeName(type.get());
    text(type_name);
    text(cat(count));
    const H5T_class_t cls = H5Tget_class(type.get());
    const bool fixed_string = cls == H5T_STRING && type_name != "v";
    if (count <= 0 || !(cls == H5T_INTEGER || cls == H5T_FLOAT || fixed_string)) return;
    // Numbers in native order (the file's little-endian types are the native ones on the
    // machines polydem supports, hdf5/checksum.cpp); strings as stored.
    Handle mem(fixed_string ? H5Tcopy(type.get()) : H5Tget_native_type(type.get(), H5T_DIR_ASCEND),
               H5Tclose);
    std::string bytes(static_cast<std::size_t>(count) * H5Tget_size(mem.get()), '\0');
    check(H5Aread(a.get(), mem.get(), bytes.data()), "cannot read " + what);
    out_ += bytes;
  }

  hid_t file_;
  std::string context_;
  std::string out_;
  std::vector<std::string> datasets_;
};

}  // namespace

FileDigest fileDigest(hid_t file, const std::string& context) {
  return Walker(file, context).run();
}

}  // namespace polydem::hdf5
