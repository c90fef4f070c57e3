// A read-only view of short integer lists stored one after another (compressed rows): list i is
// values[begin[i] .. begin[i + 1]). A polyhedron keeps its vertices' edges, faces and neighbours
// so, in one array each instead of a heap block per vertex.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace polydem::geometry {

class JaggedView {
 public:
  JaggedView(const std::vector<int>& begin, const std::vector<int>& values)
      : begin_(begin.data()), values_(values.data()), size_(begin.empty() ? 0 : begin.size() - 1) {}

  std::size_t size() const { return size_; }
  std::span<const int> operator[](std::size_t i) const {
    return {values_ + begin_[i], values_ + begin_[i + 1]};
  }

 private:
  const int* begin_;
  const int* values_;
  std::size_t size_;
};

}  // namespace polydem::geometry
