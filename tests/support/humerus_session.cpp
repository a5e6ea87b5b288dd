#include "support/humerus_session.h"

#include "osteon/geometry/voxels/voxelizer.h"

namespace osteon::test {

simulation::Session humerusSession(const simulation::SessionOptions& options) {
  return simulation::Session::fromMesh(geometry::defaultHumerusModel().mesh, options, "default");
}

simulation::Session humerusGridSession(const simulation::SessionOptions& options) {
  geometry::VoxelizeOptions vo;
  vo.voxelSizeMm = 1.2;
  return simulation::Session::fromGrid(geometry::voxelize(geometry::defaultHumerusModel().mesh, vo),
                                       options, "humerus");
}

simulation::PortalPlan humerusMeshPortalPlan(const simulation::Session& session, double durationS) {
  const geometry::TriangleMesh& mesh = geometry::defaultHumerusModel().mesh;
  simulation::PortalPathOptions po;
  po.durationS = durationS;
  return simulation::makePortalPath(simulation::Portal::FiveOClock,
                                    simulation::fitHumeralHead(mesh), mesh,
                                    session.simulation().tool().parts[0].outerRadiusMm, po);
}

simulation::DrillPath portalFivePath(const simulation::Session& session, double durationS) {
  simulation::PortalPathOptions po;
  po.durationS = durationS;
  return session.portalPath(simulation::Portal::FiveOClock, po).path;
}

HumerusParts::HumerusParts(double pathS) {
  geometry::VoxelizeOptions vo;
  vo.voxelSizeMm = 1.2;
  grid = geometry::voxelize(model.mesh, vo);
  hierarchy = geometry::DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
  sim = std::make_unique<simulation::DrillingSimulation>(
      grid, hierarchy, nullptr, simulation::ToolKind::Drill, simulation::ToolOptions{},
      simulation::DrillingOptions{});
  simulation::PortalPathOptions po;
  po.durationS = pathS;
  plan = simulation::makePortalPath(simulation::Portal::FiveOClock,
                                    simulation::fitHumeralHead(model.mesh), model.mesh,
                                    sim->tool().parts[0].outerRadiusMm, po);
}

}  // namespace osteon::test
