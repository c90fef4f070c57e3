#include "polydem/sim/contact_model.h"

namespace polydem::sim {

ModelledContact ContactModelStep::evaluate(const contact::Kernel& kernel,
                                           dynamics::ContactModel model, bool overlap_centroid,
                                           const contact::Body& a, const contact::Body& b,
                                           contact::PairState* warm) {
  const bool sub_contacts = model == dynamics::ContactModel::kSubContacts;
  ModelledContact m;
  m.contact = sub_contacts ? kernel.collideForSubContacts(a, b, warm) : kernel.collide(a, b, warm);
  // Potential kernels integrate over the overlap: their contact is never split.
  m.split = sub_contacts && m.contact.model == contact::ForceModel::kPenalty;
  if (overlap_centroid && !m.split) m.contact = overlap_.apply(a, b, m.contact);
  return m;
}

}  // namespace polydem::sim
