#include "messages.h"

#include <cmath>
#include <cstring>

#include "igtlImageMessage.h"
#include "igtlPolyDataMessage.h"
#include "igtlStringMessage.h"
#include "igtlTimeStamp.h"
#include "igtlTransformMessage.h"

namespace osteon::igtl {

namespace {

// LPS -> RAS: x and y change sign.
constexpr glm::dvec3 kLpsToRas{-1.0, -1.0, 1.0};

SharedBytes finish(::igtl::MessageBase& message, const std::string& name) {
  message.SetDeviceName(name.c_str());
  ::igtl::TimeStamp::Pointer now = ::igtl::TimeStamp::New();
  now->GetTime();
  message.SetTimeStamp(now);
  message.Pack();
  const auto* p = static_cast<const std::uint8_t*>(message.GetPackPointer());
  return std::make_shared<const Bytes>(p, p + message.GetPackSize());
}

}  // namespace

glm::dmat4 toolToRas(const simulation::ToolPose& pose) {
  glm::dmat4 m = glm::dmat4(glm::mat3_cast(pose.orientation));
  m[3] = glm::dvec4(pose.tipMm, 1.0);
  glm::dmat4 flip(1.0);
  flip[0][0] = kLpsToRas.x;
  flip[1][1] = kLpsToRas.y;
  // Conjugated by the flip: a rotation still (the tool model goes out flipped alike).
  return flip * m * flip;
}

SharedBytes packTransform(const std::string& name, const glm::dmat4& matrix) {
  ::igtl::TransformMessage::Pointer msg = ::igtl::TransformMessage::New();
  ::igtl::Matrix4x4 m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m[r][c] = static_cast<float>(matrix[c][r]);
  }
  msg->SetMatrix(m);
  return finish(*msg, name);
}

SharedBytes packImage(const std::string& name, const geometry::VoxelGrid& grid,
                      ImageContent content, glm::ivec3 lo, glm::ivec3 hi) {
  ::igtl::ImageMessage::Pointer msg = ::igtl::ImageMessage::New();
  const glm::ivec3 dims = grid.dims();
  int whole[3] = {dims.x, dims.y, dims.z};
  msg->SetDimensions(whole);
  const glm::ivec3 size = hi - lo;
  int sub[3] = {size.x, size.y, size.z};
  int offset[3] = {lo.x, lo.y, lo.z};
  msg->SetSubVolume(sub, offset);
  const auto spacing = static_cast<float>(grid.voxelSizeMm());
  msg->SetSpacing(spacing, spacing, spacing);
  const bool density = content == ImageContent::Density;
  msg->SetScalarType(density ? ::igtl::ImageMessage::TYPE_INT16 : ::igtl::ImageMessage::TYPE_UINT8);
  msg->SetEndian(::igtl::ImageMessage::ENDIAN_LITTLE);
  float t[3] = {-1.0f, 0.0f, 0.0f}, s[3] = {0.0f, -1.0f, 0.0f}, n[3] = {0.0f, 0.0f, 1.0f};
  msg->SetNormals(t, s, n);
  // OpenIGTLink's image origin is the centre of the whole volume.
  const glm::dvec3 centre = kLpsToRas * grid.worldFromGrid(glm::dvec3(dims) * 0.5);
  msg->SetOrigin(static_cast<float>(centre.x), static_cast<float>(centre.y),
                 static_cast<float>(centre.z));
  msg->AllocateScalars();
  auto* out = static_cast<std::uint8_t*>(msg->GetScalarPointer());
  std::size_t at = 0;
  for (int z = lo.z; z < hi.z; ++z) {
    for (int y = lo.y; y < hi.y; ++y) {
      for (int x = lo.x; x < hi.x; ++x) {
        geometry::Fill fill = 0;
        geometry::Density d = 0;
        grid.fillAndDensity({x, y, z}, fill, d);
        if (density) {
          const auto u = static_cast<std::uint16_t>(d);  // little-endian, as declared
          out[at++] = static_cast<std::uint8_t>(u & 0xFF);
          out[at++] = static_cast<std::uint8_t>(u >> 8);
        } else {
          out[at++] = static_cast<std::uint8_t>(fill / geometry::kFillPerStep);
        }
      }
    }
  }
  return finish(*msg, name);
}

SharedBytes packPolyData(const std::string& name, const std::vector<glm::dvec3>& pointsMm,
                         const std::vector<glm::u32vec3>& triangles, bool toRas) {
  ::igtl::PolyDataMessage::Pointer msg = ::igtl::PolyDataMessage::New();
  ::igtl::PolyDataPointArray::Pointer points = ::igtl::PolyDataPointArray::New();
  for (const glm::dvec3& p : pointsMm) {
    const glm::dvec3 q = toRas ? kLpsToRas * p : p;
    points->AddPoint(static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z));
  }
  ::igtl::PolyDataCellArray::Pointer polygons = ::igtl::PolyDataCellArray::New();
  for (const glm::u32vec3& tri : triangles) {
    // RAS mirrors two axes: a rotation, so the winding stays outward.
    igtlUint32 cell[3] = {tri.x, tri.y, tri.z};
    polygons->AddCell(3, cell);
  }
  msg->SetPoints(points);
  msg->SetPolygons(polygons);
  return finish(*msg, name);
}

SharedBytes packString(const std::string& name, const std::string& text) {
  ::igtl::StringMessage::Pointer msg = ::igtl::StringMessage::New();
  msg->SetString(text.c_str());
  return finish(*msg, name);
}

void toolModel(const simulation::Tool& tool, std::vector<glm::dvec3>& pointsMm,
               std::vector<glm::u32vec3>& triangles) {
  constexpr std::uint32_t kSides = 16;
  for (int i = 0; i < tool.partCount; ++i) {
    const simulation::ToolPart& part = tool.parts[static_cast<std::size_t>(i)];
    const glm::dvec3 axis = part.bMm - part.aMm;
    const double length = glm::length(axis);
    const glm::dvec3 w = length > 0.0 ? axis / length : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 u = glm::normalize(
        glm::cross(w, std::abs(w.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0)));
    const glm::dvec3 v = glm::cross(w, u);
    const double r = part.innerRadiusMm;
    const auto base = static_cast<std::uint32_t>(pointsMm.size());
    pointsMm.push_back(part.aMm);  // cap centres
    pointsMm.push_back(part.bMm);
    for (std::uint32_t k = 0; k < kSides; ++k) {
      const double a = 2.0 * M_PI * double(k) / double(kSides);
      const glm::dvec3 rim = r * (std::cos(a) * u + std::sin(a) * v);
      pointsMm.push_back(part.aMm + rim);
      pointsMm.push_back(part.bMm + rim);
    }
    for (std::uint32_t k = 0; k < kSides; ++k) {
      const std::uint32_t a0 = base + 2 + 2 * k, b0 = a0 + 1;
      const std::uint32_t a1 = base + 2 + 2 * ((k + 1) % kSides), b1 = a1 + 1;
      triangles.push_back({a0, a1, b1});
      triangles.push_back({a0, b1, b0});
      triangles.push_back({base, a1, a0});
      triangles.push_back({base + 1, b0, b1});
    }
  }
}

}  // namespace osteon::igtl
