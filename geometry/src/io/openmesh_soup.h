// Adapters between OpenMesh's file readers/writers and our triangle soup. OpenMesh's own mesh
// kernels insist on 2-manifold topology and silently drop "complex" faces; these adapters take
// every face as it is, so a damaged mesh loads whole and its damage stays measurable.
// Coordinates are as OpenMesh 9 parses them: single precision, also for text files and PLY
// doubles (about 7 significant digits; 0.01 um at 100 mm).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include "osteon/geometry/io/mesh.h"

namespace osteon::geometry::detail {

// OpenMesh's handle and vector types, as both adapters' overrides spell them.
using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec3ui;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using OpenMesh::Vec4ui;
using OpenMesh::VertexHandle;
using StatusInfo = OpenMesh::Attributes::StatusInfo;

class SoupImporter final : public OpenMesh::IO::BaseImporter {
 public:
  // fileBytes bounds how many vertices a file can honestly hold.
  explicit SoupImporter(std::uint64_t fileBytes) : maxVertices_(fileBytes + 16) {}

  const std::optional<std::string>& error() const { return error_; }
  TriangleMesh takeMesh() { return std::move(mesh_); }
  std::size_t polygonsRead() const { return polygonsRead_; }
  std::size_t polygonsTriangulated() const { return polygonsTriangulated_; }
  std::size_t degenerateDropped() const { return degenerateDropped_; }

  VertexHandle add_vertex(const Vec3f& p) override { return addPoint(p[0], p[1], p[2]); }
  VertexHandle add_vertex(const Vec3d& p) override { return addPoint(p[0], p[1], p[2]); }
  VertexHandle add_vertex() override { return addPoint(0.0, 0.0, 0.0); }
  FaceHandle add_face(const VHandles& corners) override;
  void set_point(VertexHandle vh, const Vec3f& p) override;

  // Everything below carries attributes osteon does not use.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

  // Some readers look for custom properties through the kernel: give them an empty one.
  OpenMesh::BaseKernel* kernel() override { return &noProperties_; }
  size_t n_vertices() const override { return mesh_.positionsMm.size(); }
  size_t n_faces() const override { return polygonsRead_; }
  size_t n_edges() const override { return 0; }

 private:
  VertexHandle addPoint(double x, double y, double z);
  void fail(std::string message) {
    if (!error_) error_ = std::move(message);
  }

  TriangleMesh mesh_;
  std::uint64_t maxVertices_;
  std::size_t polygonsRead_ = 0;
  std::size_t polygonsTriangulated_ = 0;
  std::size_t degenerateDropped_ = 0;
  std::optional<std::string> error_;
  OpenMesh::BaseKernel noProperties_;
};

class SoupExporter final : public OpenMesh::IO::BaseExporter {
 public:
  explicit SoupExporter(const TriangleMesh& mesh) : mesh_(mesh) {}

  Vec3f point(VertexHandle vh) const override { return Vec3f(pointd(vh)); }
  Vec3d pointd(VertexHandle vh) const override;
  bool is_point_double() const override { return true; }
  unsigned int get_vhandles(FaceHandle fh, std::vector<VertexHandle>& corners) const override;
  Vec3f normal(FaceHandle fh) const override { return Vec3f(normald(fh)); }
  Vec3d normald(FaceHandle fh) const override;
  bool has_face_normals() const override { return true; }
  size_t n_vertices() const override { return mesh_.positionsMm.size(); }
  size_t n_faces() const override { return mesh_.triangles.size(); }
  size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }
  // The PLY writer walks custom properties through the kernel: give it an empty one.
  const OpenMesh::BaseKernel* kernel() override { return &noProperties_; }

  // Attributes osteon does not write.
  Vec3f normal(VertexHandle) const override { return Vec3f(0.f); }
  Vec3d normald(VertexHandle) const override { return Vec3d(0.0); }
  bool is_normal_double() const override { return true; }
  Vec3uc color(VertexHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(VertexHandle) const override { return Vec4uc(0); }
  Vec3ui colori(VertexHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(VertexHandle) const override { return Vec4ui(0); }
  Vec3f colorf(VertexHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(VertexHandle) const override { return Vec4f(0.f); }
  Vec2f texcoord(VertexHandle) const override { return Vec2f(0.f); }
  Vec2f texcoord(HalfedgeHandle) const override { return Vec2f(0.f); }
  StatusInfo status(VertexHandle) const override { return StatusInfo(); }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>&) const override { return 0; }
  Vec3uc color(FaceHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(FaceHandle) const override { return Vec4uc(0); }
  Vec3ui colori(FaceHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(FaceHandle) const override { return Vec4ui(0); }
  Vec3f colorf(FaceHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(FaceHandle) const override { return Vec4f(0.f); }
  StatusInfo status(FaceHandle) const override { return StatusInfo(); }
  Vec3uc color(EdgeHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(EdgeHandle) const override { return Vec4uc(0); }
  Vec3ui colori(EdgeHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(EdgeHandle) const override { return Vec4ui(0); }
  Vec3f colorf(EdgeHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(EdgeHandle) const override { return Vec4f(0.f); }
  StatusInfo status(EdgeHandle) const override { return StatusInfo(); }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  StatusInfo status(HalfedgeHandle) const override { return StatusInfo(); }

 private:
  const TriangleMesh& mesh_;
  OpenMesh::BaseKernel noProperties_;
};

}  // namespace osteon::geometry::detail
