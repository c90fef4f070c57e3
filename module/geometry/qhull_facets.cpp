#include "polydem/geometry/qhull_facets.h"

#include <libqhull_r/libqhull_r.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "polydem/core/error.h"

namespace polydem::geometry {

namespace {

/// Owns one qhull run: its qhT and the in-memory stream that receives all of qhull's messages.
class QhullRun {
 public:
  QhullRun() : qh_(std::make_unique<qhT>()) {
    messages_ = open_memstream(&buffer_, &buffer_size_);
    qh_zero(qh_.get(), messages_);
  }
  ~QhullRun() {
    int curlong = 0, totlong = 0;
    qh_freeqhull(qh_.get(), !qh_ALL);
    qh_memfreeshort(qh_.get(), &curlong, &totlong);
    if (messages_) std::fclose(messages_);
    std::free(buffer_);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;

  qhT* get() { return qh_.get(); }
  FILE* messages() { return messages_; }

  /// Qhull's messages so far, trimmed to the first error line and its explanation.
  std::string text() {
    if (!messages_) return {};
    std::fflush(messages_);
    std::string all(buffer_, buffer_size_);
    const auto start = all.find("QH");
    if (start != std::string::npos) all.erase(0, start);
    const auto cut = all.find("\n\n");
    if (cut != std::string::npos) all.resize(cut);
    return all;
  }

 private:
  std::unique_ptr<qhT> qh_;
  FILE* messages_ = nullptr;
  char* buffer_ = nullptr;
  std::size_t buffer_size_ = 0;
};

/// Calls f(element) for each element of a qhull set (a NULL-terminated array of pointers).
template <class T, class F>
void forEachInSet(setT* set, F&& f) {
  if (!set) return;
  for (T** p = reinterpret_cast<T**>(&set->e[0].p); *p; ++p) f(*p);
}

}  // namespace

std::vector<QhullFacet> qhullFacets(std::span<const Vec3> points) {
  std::vector<coordT> coords(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = points[i][k];
  }
  QhullRun run;
  qhT* qh = run.get();
  char command[] = "qhull";  // defaults: convex hull, facets coplanar to round-off merged
  const int exit_code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                     command, nullptr, run.messages());
  if (exit_code != 0) {
    throw GeometryError("convex hull of " + std::to_string(points.size()) +
                        " points failed in qhull: " + run.text());
  }

  std::vector<int> index_of_id(qh->facet_id + 1, -1);
  int count = 0;
  for (facetT* facet = qh->facet_list; facet && facet->next; facet = facet->next) {
    index_of_id[facet->id] = count++;
  }
  std::vector<QhullFacet> facets;
  facets.reserve(count);
  for (facetT* facet = qh->facet_list; facet && facet->next; facet = facet->next) {
    QhullFacet& out = facets.emplace_back();
    out.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]);
    out.offset = -facet->offset;  // qhull's plane is normal . x + offset = 0
    forEachInSet<vertexT>(facet->vertices, [&](vertexT* vertex) {
      out.points.push_back(static_cast<int>((vertex->point - qh->first_point) / 3));
    });
    forEachInSet<facetT>(facet->neighbors, [&](facetT* neighbour) {
      out.neighbours.push_back(index_of_id[neighbour->id]);
    });
  }
  return facets;
}

}  // namespace polydem::geometry
