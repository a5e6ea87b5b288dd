// VTK's vtkFlyingEdges3D, the peer surface extraction is measured against, on an osteon grid
// (bench only, when VTK is installed).
#pragma once

#include <cstddef>
#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::bench {

// The grid as VTK image data, one uint8 per voxel (fill in 1/255 steps).
vtkSmartPointer<vtkImageData> imageOf(const geometry::VoxelGrid& g);
// FlyingEdges on the image at iso 127.5, marching cubes only (no normals, gradients or
// scalars); returns the triangle count.
std::size_t flyingEdges(vtkImageData* image);

}  // namespace osteon::bench
