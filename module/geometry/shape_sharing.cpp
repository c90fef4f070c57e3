// sameBits and PolyhedronPool (geometry/shape_sharing.h).
#include "polydem/geometry/shape_sharing.h"

#include <cstring>

namespace polydem::geometry {

namespace {

// Bitwise equality of doubles and fixed-size Eigen arrays: -0.0 and 0.0 differ, as they may in
// a kernel's result.
bool same(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same(int a, int b) {
  return a == b;
}

template <typename M>
bool same(const Eigen::MatrixBase<M>& a, const Eigen::MatrixBase<M>& b) {
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!same(a.derived().data()[i], b.derived().data()[i])) return false;
  }
  return true;
}

template <typename T, std::size_t N>
bool same(const std::array<T, N>& a, const std::array<T, N>& b) {
  for (std::size_t i = 0; i < N; ++i) {
    if (!same(a[i], b[i])) return false;
  }
  return true;
}

bool sameFaces(const std::vector<Face>& a, const std::vector<Face>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].vertices != b[i].vertices || a[i].edges != b[i].edges ||
        !same(a[i].normal, b[i].normal) || !same(a[i].offset, b[i].offset) ||
        !same(a[i].centroid, b[i].centroid) || !same(a[i].area, b[i].area)) {
      return false;
    }
  }
  return true;
}

bool sameEdges(const std::vector<Edge>& a, const std::vector<Edge>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].v0 != b[i].v0 || a[i].v1 != b[i].v1 || a[i].f0 != b[i].f0 || a[i].f1 != b[i].f1)
      return false;
  }
  return true;
}

bool sameBox(const BoxFrame* a, const BoxFrame* b) {
  if (a == nullptr || b == nullptr) return a == b;
  return same(a->centre, b->centre) && same(a->axis, b->axis) && same(a->half, b->half) &&
         same(a->edge_axis, b->edge_axis) && same(a->edge_sign, b->edge_sign) &&
         same(a->corner, b->corner) && same(a->face, b->face) && same(a->skew, b->skew);
}

bool sameVertices(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!same(a[i], b[i])) return false;
  }
  return true;
}

bool sameAdjacency(const VertexAdjacency& a, const VertexAdjacency& b) {
  return a.begin == b.begin && a.edges == b.edges && a.faces == b.faces &&
         a.neighbours == b.neighbours;
}

// FNV-1a over the bits of the vertices and of the face offsets.
std::uint64_t hashOf(const ConvexPolyhedron& p) {
  std::uint64_t h = 14695981039346656037ull;
  auto mix = [&h](const void* data, std::size_t n) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
  };
  for (const Vec3& v : p.vertices()) mix(v.data(), 3 * sizeof(double));
  for (const Face& f : p.faces()) mix(&f.offset, sizeof f.offset);
  return h;
}

}  // namespace

bool sameBits(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
  return sameVertices(a.vertices(), b.vertices()) && sameFaces(a.faces(), b.faces()) &&
         sameEdges(a.edges(), b.edges()) &&
         sameAdjacency(a.vertexAdjacency(), b.vertexAdjacency()) &&
         a.axisFaces() == b.axisFaces() && a.axisEdges() == b.axisEdges() &&
         sameBox(a.box(), b.box()) && same(a.volume(), b.volume()) &&
         same(a.centroid(), b.centroid()) && same(a.inertia(), b.inertia()) &&
         same(a.circumradius(), b.circumradius()) && same(a.inradius(), b.inradius()) &&
         same(a.incenter(), b.incenter());
}

std::shared_ptr<const ConvexPolyhedron> PolyhedronPool::share(
    std::shared_ptr<const ConvexPolyhedron> p) {
  auto& bucket = by_hash_[hashOf(*p)];
  for (const auto& q : bucket) {
    if (sameBits(*q, *p)) return q;
  }
  bucket.push_back(p);
  ++distinct_;
  return p;
}

}  // namespace polydem::geometry
