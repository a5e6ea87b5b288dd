// osteon::validation: what will live here (design.md, "Metrics").
//   - exact checks with CGAL: closed, manifold, self-intersections, orientation, genus, volume
//   - accuracy against the input: two-sided Hausdorff distance, volume difference
//   - the seed's pixel crack metric (section 3.4), by Embree ray casting, PNG via OpenImageIO
//   - the collision-miss cross-check along drill paths
//   - the nightly report (report.html, report.json)
// CGAL stays inside this module, in as few translation units as possible.
// Depends on osteon::simulation and osteon::geometry.
#pragma once

namespace osteon::validation {

inline constexpr int kInterfaceVersion = 0;

}  // namespace osteon::validation
