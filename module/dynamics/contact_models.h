// The registry of contact models (contact_model_list.inc): how a kernel's contact becomes forces.
// "sub-contacts" splits a penalty contact into springs at the corners of the face overlap
// (sub_contact_law.h); "point" applies the whole force at the kernel's point (contact_law.h).
// Potential kernels integrate over the overlap and are never split.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace polydem::dynamics {

enum class ContactModel {
#define POLYDEM_CONTACT_MODEL(name, enumerator, help) enumerator,
#include "polydem/dynamics/contact_model_list.inc"
#undef POLYDEM_CONTACT_MODEL
};

struct ContactModelInfo {
  std::string_view name;
  ContactModel model;
  std::string_view help;
};

/// Every contact model, in the order of contact_model_list.inc (the first is the default).
inline const std::vector<ContactModelInfo>& contactModels() {
  static const std::vector<ContactModelInfo> models = {
#define POLYDEM_CONTACT_MODEL(name, enumerator, help) {name, ContactModel::enumerator, help},
#include "polydem/dynamics/contact_model_list.inc"
#undef POLYDEM_CONTACT_MODEL
  };
  return models;
}

/// The model called `name`, or nothing.
inline std::optional<ContactModel> findContactModel(std::string_view name) {
  for (const auto& m : contactModels()) {
    if (m.name == name) return m.model;
  }
  return std::nullopt;
}

/// The names, in registry order.
inline std::vector<std::string> contactModelNames() {
  std::vector<std::string> names;
  for (const auto& m : contactModels()) names.emplace_back(m.name);
  return names;
}

}  // namespace polydem::dynamics
