// The convex hull of a point set by Qhull (mesh_hull.h).
#include "mesh_hull.h"

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <map>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace ohrp::collision {

bool ConvexHull(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>* vertices,
                std::vector<int>* faces, std::string* error) {
  vertices->clear();
  faces->clear();
  if (points.size() < 4) {
    *error = "has " + std::to_string(points.size()) + " vertices: a hull needs at least 4";
    return false;
  }
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const Eigen::Vector3d& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  // Qhull's messages go to a memory stream, for the error text
  char* text = nullptr;
  size_t text_size = 0;
  FILE* messages = open_memstream(&text, &text_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, messages);
  char command[] = "qhull Qt";  // triangulated output
  const int status = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                  command, nullptr, messages);
  if (status == 0) {
    std::map<int, int> index;  // point id -> position in `vertices`
    facetT* facet;
    FORALLfacets {
      int ids[3], n = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) {
        if (n < 3) ids[n] = qh_pointid(qh, vertex->point);
        ++n;
      }
      if (n != 3) continue;  // Qt triangulates every facet
      int local[3];
      for (int k = 0; k < 3; ++k) {
        const auto [it, added] = index.emplace(ids[k], static_cast<int>(vertices->size()));
        if (added) vertices->push_back(points[ids[k]]);
        local[k] = it->second;
      }
      // counter-clockwise from outside: the triangle's normal along the facet's outer normal
      const Eigen::Vector3d& a = (*vertices)[local[0]];
      const Eigen::Vector3d normal = ((*vertices)[local[1]] - a).cross((*vertices)[local[2]] - a);
      const Eigen::Vector3d outer(facet->normal[0], facet->normal[1], facet->normal[2]);
      if (normal.dot(outer) < 0) std::swap(local[1], local[2]);
      faces->insert(faces->end(), {3, local[0], local[1], local[2]});
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(messages);
  const std::string said = text ? std::string(text, text_size) : std::string();
  std::free(text);
  if (status != 0 || faces->empty()) {
    // Qhull's first line says what was wrong (flat input, too few distinct points)
    *error = "has no convex hull: its vertices span no volume (Qhull: " +
             said.substr(0, said.find('\n')) + ")";
    vertices->clear();
    faces->clear();
    return false;
  }
  return true;
}

}  // namespace ohrp::collision
