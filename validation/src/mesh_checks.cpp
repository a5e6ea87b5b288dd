#include "osteon/validation/mesh_checks.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

namespace osteon::validation {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Polygon = std::array<std::size_t, 3>;

struct Soup {
  std::vector<Point> points;
  std::vector<Polygon> triangles;
};

Soup toSoup(const geometry::TriangleMesh& mesh) {
  Soup soup;
  soup.points.reserve(mesh.positionsMm.size());
  for (const glm::dvec3& p : mesh.positionsMm) soup.points.emplace_back(p.x, p.y, p.z);
  soup.triangles.reserve(mesh.triangles.size());
  for (const glm::u32vec3& t : mesh.triangles) soup.triangles.push_back({t.x, t.y, t.z});
  return soup;
}

// Whether two soup triangles meet anywhere but in the vertices or edge they share (the test
// CGAL's self_intersections applies to adjacent faces; exact predicates throughout).
bool trianglesIntersect(const Soup& soup, const Polygon& f, const Polygon& g) {
  const auto& P = soup.points;
  std::array<int, 3> inG{-1, -1, -1};  // for each corner of f, its corner in g, or -1
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (f[std::size_t(i)] == g[std::size_t(j)]) {
        inG[std::size_t(i)] = j;
        ++shared;
      }
    }
  const Kernel::Triangle_3 tf(P[f[0]], P[f[1]], P[f[2]]);
  const Kernel::Triangle_3 tg(P[g[0]], P[g[1]], P[g[2]]);
  if (shared == 0) return CGAL::do_intersect(tf, tg);
  if (shared == 3) return true;  // the same triangle twice
  if (shared == 2) {
    // Sharing edge ab: they overlap only when coplanar with c and d on the same side of ab.
    int fOnly = 0;
    while (inG[std::size_t(fOnly)] != -1) ++fOnly;
    const Point& a = P[f[std::size_t((fOnly + 1) % 3)]];
    const Point& b = P[f[std::size_t((fOnly + 2) % 3)]];
    const Point& c = P[f[std::size_t(fOnly)]];
    std::size_t d = 0;
    for (std::size_t v : g) {
      if (v != f[0] && v != f[1] && v != f[2]) d = v;
    }
    return CGAL::coplanar(a, b, c, P[d]) &&
           CGAL::coplanar_orientation(a, b, c, P[d]) == CGAL::POSITIVE;
  }
  // Sharing vertex a only: the intersection, if more than a, is a segment from a ending on
  // the edge opposite a of one triangle, inside the other.
  int fa = 0;
  while (inG[std::size_t(fa)] == -1) ++fa;
  const int ga = inG[std::size_t(fa)];
  const Kernel::Segment_3 fOpp(P[f[std::size_t((fa + 1) % 3)]], P[f[std::size_t((fa + 2) % 3)]]);
  const Kernel::Segment_3 gOpp(P[g[std::size_t((ga + 1) % 3)]], P[g[std::size_t((ga + 2) % 3)]]);
  return CGAL::do_intersect(fOpp, tg) || CGAL::do_intersect(gOpp, tf);
}

// Fallback for soups that are not polygon meshes (pinched vertices, fins, flipped faces):
// box broad phase, then the exact pair test above.
std::size_t soupPairs(const Soup& soup, std::size_t cap) {
  using Box = CGAL::Box_intersection_d::Box_with_handle_d<double, 3, const Polygon*>;
  std::vector<Box> boxes;
  std::size_t degenerate = 0;
  for (const Polygon& t : soup.triangles) {
    const Point& p = soup.points[t[0]];
    const Point& q = soup.points[t[1]];
    const Point& r = soup.points[t[2]];
    // As CGAL does: a degenerate triangle counts as one intersecting pair.
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || CGAL::collinear(p, q, r)) {
      ++degenerate;
      continue;
    }
    boxes.emplace_back(p.bbox() + q.bbox() + r.bbox(), &t);
  }
  std::size_t count = std::min(degenerate, cap);
  if (count >= cap) return count;
  struct Full {};  // stops the broad phase once cap pairs are found
  try {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
      if (!trianglesIntersect(soup, *a.handle(), *b.handle())) return;
      if (++count >= cap) throw Full{};
    });
  } catch (const Full&) {
  }
  return count;
}

// The surface mesh of the soup, or false when the soup is not a polygon mesh (precondition
// of polygon_soup_to_polygon_mesh, which we do not repair: orienting would hide bugs).
bool toSurfaceMesh(const Soup& soup, Mesh& mesh) {
  if (!PMP::is_polygon_soup_a_polygon_mesh(soup.triangles)) return false;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.triangles, mesh);
  return true;
}

// The winding number inside each shell is its own (+1 outward, -1 inward) plus that of the
// shell around it (CGAL's nesting of the surface's components); outside every shell it is 0.
void windingNumbers(Mesh& surface, int& lowest, int& highest) {
  auto volumeIds =
      surface.add_property_map<Mesh::Face_index, std::size_t>("f:osteon_volume", 0).first;
  std::vector<std::size_t> levels;
  std::vector<bool> outward;
  std::vector<std::vector<std::size_t>> around;  // per shell: the shell(s) first met going outward
  PMP::volume_connected_components(surface, volumeIds,
                                   CGAL::parameters::nesting_levels(std::ref(levels))
                                       .is_cc_outward_oriented(std::ref(outward))
                                       .volume_inclusions(std::ref(around)));
  lowest = 0;
  highest = 0;
  for (std::size_t shell = 0; shell < outward.size(); ++shell) {
    int winding = 0;
    // Up the chain of enclosing shells (at most one per nesting level, so this ends).
    std::size_t k = shell;
    for (std::size_t step = 0; step <= outward.size(); ++step) {
      winding += outward[k] ? 1 : -1;
      if (k >= around.size() || around[k].empty()) break;
      k = around[k].front();
    }
    lowest = std::min(lowest, winding);
    highest = std::max(highest, winding);
  }
}

}  // namespace

std::size_t selfIntersectingPairs(const geometry::TriangleMesh& mesh, std::size_t cap) {
  if (cap == 0 || mesh.triangles.empty()) return 0;
  const Soup soup = toSoup(mesh);
  Mesh surface;
  if (!toSurfaceMesh(soup, surface)) return soupPairs(soup, cap);
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections(surface, std::back_inserter(pairs),
                          CGAL::parameters::maximum_number(static_cast<unsigned int>(cap)));
  return std::min(pairs.size(), cap);
}

bool doesSelfIntersect(const geometry::TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return false;
  const Soup soup = toSoup(mesh);
  Mesh surface;
  if (!toSurfaceMesh(soup, surface)) return soupPairs(soup, 1) > 0;
  return PMP::does_self_intersect(surface);
}

MeshReport checkMesh(const geometry::TriangleMesh& mesh, std::size_t intersectionCap) {
  MeshReport report;
  report.topology = geometry::analyzeTopology(mesh);
  report.volumeMm3 = geometry::signedVolumeMm3(mesh);
  if (mesh.triangles.empty()) return report;
  double areaMm2 = 0.0;
  for (const glm::u32vec3& t : mesh.triangles) {
    const glm::dvec3 &a = mesh.positionsMm[t.x], &b = mesh.positionsMm[t.y],
                     &c = mesh.positionsMm[t.z];
    areaMm2 += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  report.flat =
      report.topology.closed() && std::abs(report.volumeMm3) <= 1e-9 * std::pow(areaMm2, 1.5);
  const Soup soup = toSoup(mesh);
  Mesh surface;
  const bool polygonMesh = toSurfaceMesh(soup, surface);
  if (polygonMesh) {
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    PMP::self_intersections(
        surface, std::back_inserter(pairs),
        CGAL::parameters::maximum_number(static_cast<unsigned int>(intersectionCap)));
    report.selfIntersections = std::min(pairs.size(), intersectionCap);
  } else {
    report.selfIntersections = soupPairs(soup, intersectionCap);
  }
  report.selfIntersectionsCapped = report.selfIntersections >= intersectionCap;
  // is_outward_oriented's preconditions: closed, and no self-intersection.
  if (polygonMesh && report.watertight() && report.selfIntersections == 0 &&
      CGAL::is_closed(surface)) {
    report.outwardOriented = PMP::is_outward_oriented(surface);
    windingNumbers(surface, report.windingNumberMin, report.windingNumberMax);
  }
  if (report.watertight() && report.topology.components == 1) {
    report.genus = (2 - report.topology.eulerCharacteristic) / 2;
  }
  return report;
}

Accuracy compareMeshes(const geometry::TriangleMesh& surface,
                       const geometry::TriangleMesh& reference, double pointsPerMm2) {
  Accuracy a;
  const Soup s = toSoup(surface), r = toSoup(reference);
  Mesh ms, mr;
  if (!toSurfaceMesh(s, ms) || !toSurfaceMesh(r, mr)) {
    throw std::invalid_argument("compareMeshes: both meshes must be polygon meshes");
  }
  // Fixed seeds for the sample points, so the nightly report gives the same distance for the
  // same meshes. CGAL 5.5 places points per area unit with its thread's default generator,
  // which is seeded from the clock and ignores random_seed; it is reseeded here for each side.
  const auto params = CGAL::parameters::number_of_points_per_area_unit(pointsPerMm2).random_seed(1);
  CGAL::get_default_random() = CGAL::Random(1);
  a.surfaceToReferenceMm =
      PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(ms, mr, params);
  CGAL::get_default_random() = CGAL::Random(2);
  a.referenceToSurfaceMm =
      PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(mr, ms, params);
  a.hausdorffMm = std::max(a.surfaceToReferenceMm, a.referenceToSurfaceMm);
  const double vs = geometry::signedVolumeMm3(surface), vr = geometry::signedVolumeMm3(reference);
  a.volumeDifferenceMm3 = vs - vr;
  a.volumeDifferencePercent = vr != 0.0 ? 100.0 * (vs - vr) / std::abs(vr) : 0.0;
  return a;
}

}  // namespace osteon::validation
