#include "flying_edges.h"

#include <vtkFlyingEdges3D.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

namespace osteon::bench {

using namespace osteon::geometry;

vtkSmartPointer<vtkImageData> imageOf(const VoxelGrid& g) {
  const glm::ivec3 d = g.dims();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(d.x, d.y, d.z);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* values = static_cast<unsigned char*>(image->GetScalarPointer());
  std::size_t at = 0;  // x fastest, then y, then z
  for (int z = 0; z < d.z; ++z)
    for (int y = 0; y < d.y; ++y)
      for (int x = 0; x < d.x; ++x)
        values[at++] = static_cast<unsigned char>(g.fill({x, y, z}) / kFillPerStep);
  return image;
}

std::size_t flyingEdges(vtkImageData* image) {
  vtkNew<vtkFlyingEdges3D> fe;
  fe->SetInputData(image);
  fe->SetValue(0, 127.5);
  fe->ComputeNormalsOff();
  fe->ComputeGradientsOff();
  fe->ComputeScalarsOff();
  fe->Update();
  return static_cast<std::size_t>(fe->GetOutput()->GetNumberOfPolys());
}

}  // namespace osteon::bench
