// Operators 3 and 4 of the contact phase (contact_phase.h): the kernel call and the contact model.
// The model (dynamics/contact_models.h) decides which kernel entry is called (sub-contacts need
// the face features) and how its contact becomes forces: split into sub-contacts (penalty
// contacts only) or kept as one point, optionally moved to the overlap's centroid.
#pragma once

#include "polydem/contact/contact.h"
#include "polydem/contact/point/overlap_point.h"
#include "polydem/dynamics/contact_models.h"

namespace polydem::sim {

/// A pair's contact, as the law gets it.
struct ModelledContact {
  contact::Contact contact;
  bool split = false;  // forces from sub-contacts at the face overlap's corners
};

class ContactModelStep {
 public:
  /// Calls `kernel` on the pair (warm-started from and updating `warm`) and applies `model`;
  /// `overlap_centroid`: a single-point contact acts at the centroid of the overlap volume.
  ModelledContact evaluate(const contact::Kernel& kernel, dynamics::ContactModel model,
                           bool overlap_centroid, const contact::Body& a, const contact::Body& b,
                           particles::PairState* warm);

 private:
  contact::OverlapCentroid overlap_;
};

// Inline, and the kernel's contact built in place: no call, and no contact zeroed and then copied
// from the kernel's, for every pair of every step.
inline ModelledContact ContactModelStep::evaluate(const contact::Kernel& kernel,
                                                  dynamics::ContactModel model,
                                                  bool overlap_centroid, const contact::Body& a,
                                                  const contact::Body& b,
                                                  particles::PairState* warm) {
  const bool sub_contacts = model == dynamics::ContactModel::kSubContacts;
  ModelledContact m{sub_contacts ? kernel.collideForSubContacts(a, b, warm)
                                 : kernel.collide(a, b, warm)};
  // Potential kernels integrate over the overlap: their contact is never split.
  m.split = sub_contacts && m.contact.model == contact::ForceModel::kPenalty;
  if (overlap_centroid && !m.split) m.contact = overlap_.apply(a, b, m.contact);
  return m;
}

}  // namespace polydem::sim
