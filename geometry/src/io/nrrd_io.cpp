#include "osteon/geometry/io/nrrd_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <vector>

#include "io/nrrd_grid_header.h"
#include "io/nrrd_header.h"
#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

std::string densityPathFor(const std::string& fillPath) {
  const std::string ext = ".nrrd";
  if (fillPath.size() > ext.size()) {
    std::string tail = fillPath.substr(fillPath.size() - ext.size());
    std::transform(tail.begin(), tail.end(), tail.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (tail == ext) {
      return fillPath.substr(0, fillPath.size() - ext.size()) + ".density" +
             fillPath.substr(fillPath.size() - ext.size());
    }
  }
  return fillPath + ".density.nrrd";
}

namespace {

// %.17g without the C locale's say over the decimal point: reads back to the same double.
std::string num(double v) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, 17);
  return std::string(buf, r.ptr);
}

std::string header(const VoxelGrid& grid, const char* type, const char* content) {
  const glm::ivec3 n = grid.dims();
  const double vs = grid.voxelSizeMm();
  const glm::dvec3 o = grid.originMm();
  const glm::dvec3 c = grid.voxelCentreMm(glm::ivec3(0));  // NRRD's origin: a voxel centre
  const std::string v = num(vs);
  std::string h = "NRRD0004\n# osteon voxel grid: " + std::string(content) + "\n";
  h += "type: " + std::string(type) + "\n";
  h += "dimension: 3\nspace: left-posterior-superior\n";
  h += "sizes: " + std::to_string(n.x) + " " + std::to_string(n.y) + " " + std::to_string(n.z) +
       "\n";
  h += "space directions: (" + v + ",0,0) (0," + v + ",0) (0,0," + v + ")\n";
  h += "kinds: domain domain domain\nendian: little\nencoding: raw\n";
  h += "space units: \"mm\" \"mm\" \"mm\"\n";
  h += "space origin: (" + num(c.x) + "," + num(c.y) + "," + num(c.z) + ")\n";
  h += "osteon_voxel_size_mm:=" + v + "\n";
  h += "osteon_origin_mm:=" + num(o.x) + " " + num(o.y) + " " + num(o.z) + "\n\n";
  return h;
}

// fn(brick, x0, y0, w, h) for each brick of the grid's brick layer bz: its index, its first
// voxel's x and y, and its width and height inside the grid.
template <typename Fn>
void forEachBrickInLayer(const VoxelGrid& grid, int bz, Fn&& fn) {
  const glm::ivec3 n = grid.dims();
  const glm::ivec3 nb = grid.brickDims();
  for (int by = 0; by < nb.y; ++by) {
    const int y0 = by * kBrickEdge;
    const int h = std::min(kBrickEdge, n.y - y0);
    for (int bx = 0; bx < nb.x; ++bx) {
      const int x0 = bx * kBrickEdge;
      fn(grid.brickIndex({bx, by, bz}), x0, y0, std::min(kBrickEdge, n.x - x0), h);
    }
  }
}

// One z-slice of a grid's values (x fastest), gathered brick row by brick row.
template <typename T, typename BrickValues, typename UniformValue>
void gatherSlice(const VoxelGrid& grid, int z, std::vector<T>& slice, BrickValues brickValues,
                 UniformValue uniformValue) {
  const std::size_t nx = std::size_t(grid.dims().x);
  const int lz = z % kBrickEdge;
  forEachBrickInLayer(grid, z / kBrickEdge, [&](std::size_t brick, int x0, int y0, int w, int h) {
    T* dst = slice.data() + std::size_t(y0) * nx + std::size_t(x0);
    if (const VoxelGrid::Brick* b = grid.brickData(brick)) {
      const T* src = brickValues(*b) + VoxelGrid::voxelInBrick({0, 0, lz});
      for (int y = 0; y < h; ++y) std::copy_n(src + y * kBrickEdge, w, dst + std::size_t(y) * nx);
    } else {
      const T value = uniformValue(brick);
      for (int y = 0; y < h; ++y) std::fill_n(dst + std::size_t(y) * nx, w, value);
    }
  });
}

// Puts one brick layer of z-slices (x fastest, depth slices) into the grid: a brick whose
// voxels are all alike stays uniform, any other is stored.
void placeBrickLayer(VoxelGrid& grid, int bz, int depth, const std::vector<Fill>& fills,
                     const std::vector<Density>& densities) {
  const glm::ivec3 n = grid.dims();
  const std::size_t sliceVoxels = std::size_t(n.x) * std::size_t(n.y);
  const auto at = [&](int x, int y, int lz) {
    return std::size_t(lz) * sliceVoxels + std::size_t(y) * std::size_t(n.x) + std::size_t(x);
  };
  forEachBrickInLayer(grid, bz, [&](std::size_t brick, int x0, int y0, int w, int h) {
    const Fill f0 = fills[at(x0, y0, 0)];
    const Density d0 = densities[at(x0, y0, 0)];
    bool uniform = true;
    for (int lz = 0; lz < depth && uniform; ++lz) {
      for (int y = 0; y < h && uniform; ++y) {
        const std::size_t row = at(x0, y0 + y, lz);
        for (int x = 0; x < w; ++x) {
          if (fills[row + std::size_t(x)] != f0 || densities[row + std::size_t(x)] != d0) {
            uniform = false;
            break;
          }
        }
      }
    }
    if (uniform) {
      grid.setBrickUniform(brick, f0, d0);
      return;
    }
    VoxelGrid::Brick& b = grid.materialiseBrick(brick);
    for (int lz = 0; lz < depth; ++lz) {
      for (int y = 0; y < h; ++y) {
        const std::size_t row = at(x0, y0 + y, lz);
        const std::size_t local = std::size_t(VoxelGrid::voxelInBrick({0, y, lz}));
        std::copy_n(fills.begin() + std::ptrdiff_t(row), w, b.fill.begin() + std::ptrdiff_t(local));
        std::copy_n(densities.begin() + std::ptrdiff_t(row), w,
                    b.density.begin() + std::ptrdiff_t(local));
      }
    }
  });
}

// Byte order is spelt out rather than taken from the host.
template <typename T>
void encodeLittle(const std::vector<T>& values, std::vector<unsigned char>& bytes) {
  using U = std::make_unsigned_t<T>;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const U u = static_cast<U>(values[i]);
    for (std::size_t b = 0; b < sizeof(T); ++b) {
      bytes[i * sizeof(T) + b] = static_cast<unsigned char>((u >> (8 * b)) & 0xffu);
    }
  }
}

// Writes values of type T as type Out (each divided by `divisor`).
template <typename T, typename Out, typename BrickValues, typename UniformValue>
void writeVolume(const VoxelGrid& grid, const OutputFile& file, const char* type,
                 const char* content, T divisor, BrickValues brickValues,
                 UniformValue uniformValue) {
  const std::string& path = file.path();
  std::ofstream out(file.tempPath(), std::ios::binary | std::ios::trunc);
  if (!out) {
    throw InputError(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  }
  out << header(grid, type, content);
  const glm::ivec3 n = grid.dims();
  std::vector<T> slice(std::size_t(n.x) * std::size_t(n.y));
  std::vector<Out> converted(slice.size());
  std::vector<unsigned char> bytes(slice.size() * sizeof(Out));
  for (int z = 0; z < n.z && out; ++z) {
    gatherSlice(grid, z, slice, brickValues, uniformValue);
    for (std::size_t i = 0; i < slice.size(); ++i) converted[i] = Out(slice[i] / divisor);
    encodeLittle(converted, bytes);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  out.close();
  if (!out) throw InputError(path + ": write failed (disk full or not writable?)");
}

// ---- Reading ----

using nrrd::GridHeader;
using nrrd::GridValue;

// Reads `count` values into `values`, converting from the file's byte order.
// Reads `count` values of `width` bytes each into `values` (times `scale`), converting from
// the file's byte order.
template <typename T>
void readValues(const std::string& path, std::ifstream& in, bool bigEndian, std::size_t width,
                T scale, std::size_t count, std::vector<unsigned char>& bytes,
                std::vector<T>& values) {
  bytes.resize(count * width);
  values.resize(count);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()))) {
    throw InputError(path + ": read failed in the data");
  }
  using U = std::make_unsigned_t<T>;
  for (std::size_t i = 0; i < count; ++i) {
    U u = 0;
    for (std::size_t b = 0; b < width; ++b) {
      const std::size_t shift = 8 * (bigEndian ? width - 1 - b : b);
      u = static_cast<U>(u | (U(bytes[i * width + b]) << shift));
    }
    values[i] = static_cast<T>(u * scale);
  }
}

}  // namespace

namespace {

// True when every fill is a whole number of the voxelizer's 1/255 steps (a grid fresh from
// voxelization): then uint8 holds it exactly and every viewer reads it.
bool fillFitsInSteps(const VoxelGrid& grid) {
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    if (const VoxelGrid::Brick* b = grid.brickData(brick)) {
      for (Fill f : b->fill) {
        if (f % kFillPerStep != 0) return false;
      }
    } else if (grid.brickUniformFill(brick) % kFillPerStep != 0) {
      return false;
    }
  }
  return true;
}

}  // namespace

void writeNrrd(const VoxelGrid& grid, const std::string& fillPath, bool withDensity) {
  const auto brickFill = [](const VoxelGrid::Brick& b) { return b.fill.data(); };
  const auto uniformFill = [&grid](std::size_t brick) { return grid.brickUniformFill(brick); };
  // Both files are complete before either replaces what was there: a pair is never mixed.
  OutputFile fillFile(fillPath);
  if (fillFitsInSteps(grid)) {
    writeVolume<Fill, std::uint8_t>(grid, fillFile, "uint8", "fill, 0 empty .. 255 full",
                                    kFillPerStep, brickFill, uniformFill);
  } else {
    writeVolume<Fill, std::uint16_t>(grid, fillFile, "uint16", "fill, 0 empty .. 16320 full",
                                     Fill(1), brickFill, uniformFill);
  }
  const std::string densityPath = densityPathFor(fillPath);
  if (withDensity) {
    OutputFile densityFile(densityPath);
    writeVolume<Density, Density>(
        grid, densityFile, "int16", "density (drilling difficulty)", Density(1),
        [](const VoxelGrid::Brick& b) { return b.density.data(); },
        [&grid](std::size_t brick) { return grid.brickUniformDensity(brick); });
    fillFile.commit();
    densityFile.commit();
  } else {
    fillFile.commit();
    // A stale density file beside the new fill would be paired with it on reading.
    std::error_code ec;
    fs::remove(densityPath, ec);
  }
}

NrrdReadResult readNrrd(const std::string& fillPath, bool allowOutsideData) {
  std::ifstream fillIn;
  const GridHeader fillHeader =
      nrrd::readGridHeader(fillPath, fillIn, GridValue::Fill, allowOutsideData);

  const std::string densityPath = densityPathFor(fillPath);
  std::error_code ec;
  const bool densityLoaded = fs::exists(densityPath, ec);
  std::ifstream densityIn;
  GridHeader densityHeader;
  if (densityLoaded) {
    densityHeader =
        nrrd::readGridHeader(densityPath, densityIn, GridValue::Int16, allowOutsideData);
    const glm::ivec3 a = fillHeader.sizes;
    const glm::ivec3 b = densityHeader.sizes;
    if (a != b) {
      throw InputError(densityPath + ": sizes " + std::to_string(b.x) + " " + std::to_string(b.y) +
                       " " + std::to_string(b.z) + " do not match the fill file's " +
                       std::to_string(a.x) + " " + std::to_string(a.y) + " " + std::to_string(a.z));
    }
    const double vs = fillHeader.voxelSizeMm;
    const glm::dvec3 d = glm::abs(densityHeader.originMm - fillHeader.originMm);
    if (!(std::abs(densityHeader.voxelSizeMm - vs) <= 1e-6 * vs) ||
        std::max({d.x, d.y, d.z}) > 1e-6 * vs) {
      throw InputError(densityPath + ": spacing or origin does not match the fill file's");
    }
  }

  NrrdReadResult result;
  try {
    result.grid = VoxelGrid(fillHeader.sizes, fillHeader.originMm, fillHeader.voxelSizeMm);
  } catch (const std::invalid_argument& e) {
    throw InputError(fillPath + ": " + e.what());
  }
  result.densityLoaded = densityLoaded;
  VoxelGrid& grid = result.grid;
  const glm::ivec3 n = grid.dims();
  const glm::ivec3 nb = grid.brickDims();
  const std::size_t sliceVoxels = std::size_t(n.x) * std::size_t(n.y);

  // One brick layer of z-slices at a time: bounded memory, and each brick is seen whole.
  std::vector<unsigned char> bytes;
  std::vector<Fill> fills;
  std::vector<Density> densities;
  for (int bz = 0; bz < nb.z; ++bz) {
    const int z0 = bz * kBrickEdge;
    const int depth = std::min(kBrickEdge, n.z - z0);
    const std::size_t count = sliceVoxels * std::size_t(depth);
    const bool steps = fillHeader.valueBytes == 1;
    readValues(fillHeader.dataShown, fillIn, fillHeader.bigEndian, fillHeader.valueBytes,
               Fill(steps ? kFillPerStep : 1), count, bytes, fills);
    if (const auto over =
            std::find_if(fills.begin(), fills.end(), [](Fill f) { return f > kFillFull; });
        over != fills.end()) {
      throw InputError(fillPath + ": fill value " + std::to_string(*over) + " exceeds full (" +
                       std::to_string(kFillFull) + ")");
    }
    if (densityLoaded) {
      readValues(densityHeader.dataShown, densityIn, densityHeader.bigEndian, std::size_t(2),
                 Density(1), count, bytes, densities);
    } else {
      densities.assign(count, 0);
    }
    placeBrickLayer(grid, bz, depth, fills, densities);
  }
  grid.clearDirty();  // freshly loaded: nothing to re-mesh yet
  return result;
}

}  // namespace osteon::geometry
