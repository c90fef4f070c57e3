#include "polydem/contact/contact.h"

namespace polydem::contact {

Body placeBody(const geometry::ConvexPolyhedron& shape, const Vec3& position, const Mat3& rotation,
               std::vector<Vec3>& storage) {
  const auto& local = shape.vertices();
  storage.resize(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) storage[i] = position + rotation * local[i];
  Body body;
  body.shape = &shape;
  body.position = position;
  body.rotation = rotation;
  body.vertices = storage;
  return body;
}

}  // namespace polydem::contact
