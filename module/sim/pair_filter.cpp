#include "polydem/sim/pair_filter.h"

#include <cstring>

#include "polydem/core/memory.h"

namespace polydem::sim {

namespace {

using particles::ParticleStorage;

// Min/max corner of a vertex set.
void bounds(std::span<const Vec3> v, Vec3& lo, Vec3& hi) {
  lo = hi = v[0];
  for (const Vec3& x : v) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
}

bool boxesOverlap(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi,
                  double slack) {
  return (alo.array() <= bhi.array() + slack).all() && (blo.array() <= ahi.array() + slack).all();
}

bool boxesOverlap(std::span<const Vec3> a, std::span<const Vec3> b, double slack) {
  Vec3 alo, ahi, blo, bhi;
  bounds(a, alo, ahi);
  bounds(b, blo, bhi);
  return boxesOverlap(alo, ahi, blo, bhi, slack);
}

// World vertices of entry i placed at `position` (used when an image shift moves the frame).
std::span<const Vec3> verticesAt(const ParticleStorage& s, const particles::ShapeTable& shapes,
                                 std::size_t i, const Vec3& position, std::vector<Vec3>& out) {
  const auto& body = shapes[s[i].shape].polyhedron->vertices();
  out.resize(body.size());
  const Mat3& r = s.rotation(i);
  for (std::size_t v = 0; v < body.size(); ++v) out[v] = position + r * body[v];
  return out;
}

}  // namespace

void PairFilter::prepare(const ParticleStorage& storage, const particles::ShapeTable& shapes) {
  bodies_.resize(storage.size());
  box_lo_.resize(storage.size());
  box_hi_.resize(storage.size());
  unshifted_.resize(storage.size());
  for (std::size_t i = 0; i < storage.size(); ++i) {
    bounds(storage.worldVertices(i), box_lo_[i], box_hi_[i]);
    unshifted_[i] = storage.shift(i).isZero(0.0);
    bodies_[i] = {shapes[storage[i].shape].polyhedron.get(), storage[i].position,
                  storage.rotation(i), storage.worldVertices(i), storage.worldFaceNormals(i)};
  }
}

bool PairFilter::accept(const ParticleStorage& storage, const particles::ShapeTable& shapes,
                        const OrderedPair& c, double margin, PairFrame& frame) {
  const auto& sa = shapes[storage[c.a].shape];
  const auto& sb = shapes[storage[c.b].shape];
  // Canonical frame: A where its owner stores it, B shifted by the difference of the images.
  const Vec3& xa = storage[c.a].position;
  const Vec3 xb = storage[c.b].position + (storage.shift(c.b) - storage.shift(c.a));
  const double reach = sa.circumradius + sb.circumradius + margin;
  if ((xb - xa).squaredNorm() > reach * reach) return false;
  // Tested per particle in prepare(): six comparisons per candidate pair otherwise.
  if (unshifted_[c.a] && unshifted_[c.b]) {
    if (!boxesOverlap(box_lo_[c.a], box_hi_[c.a], box_lo_[c.b], box_hi_[c.b], margin)) return false;
    // B's frame position is its stored one plus a zero shift difference: the same bits unless a
    // coordinate is a zero whose sign the addition changes; such a B gets a Body of its own.
    if (std::memcmp(xb.data(), storage[c.b].position.data(), sizeof(double) * 3) == 0) {
      frame = {xa, xb, &bodies_[c.a], &bodies_[c.b]};
      return true;
    }
    placeOwn(storage, shapes, c, xb, storage.worldVertices(c.a), storage.worldVertices(c.b), frame);
    return true;
  }
  const auto va = verticesAt(storage, shapes, c.a, xa, scratch_a_);
  const auto vb = verticesAt(storage, shapes, c.b, xb, scratch_b_);
  if (!boxesOverlap(va, vb, margin)) return false;
  placeOwn(storage, shapes, c, xb, va, vb, frame);
  return true;
}

void PairFilter::placeOwn(const ParticleStorage& storage, const particles::ShapeTable& shapes,
                          const OrderedPair& c, const Vec3& xb, std::span<const Vec3> va,
                          std::span<const Vec3> vb, PairFrame& frame) {
  const Vec3& xa = storage[c.a].position;
  shifted_a_ = {shapes[storage[c.a].shape].polyhedron.get(), xa, storage.rotation(c.a), va,
                storage.worldFaceNormals(c.a)};
  shifted_b_ = {shapes[storage[c.b].shape].polyhedron.get(), xb, storage.rotation(c.b), vb,
                storage.worldFaceNormals(c.b)};
  frame = {xa, xb, &shifted_a_, &shifted_b_};
}

std::uint64_t PairFilter::heapBytes() const {
  return capacityBytes(box_lo_) + capacityBytes(box_hi_) + capacityBytes(unshifted_) +
         capacityBytes(bodies_) + capacityBytes(scratch_a_) + capacityBytes(scratch_b_);
}

}  // namespace polydem::sim
