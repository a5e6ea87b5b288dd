// The generated half of the bad-input table (tests/data/bad/README.md): every valid seed of
// tests/data/seeds cut at each structural boundary, the inputs too big to keep in the
// repository, and files that are not regular files. Also writes the binary seeds themselves.
//
//   osteon_bad_inputs seeds DIR             the seed files (tests/data/seeds is this output)
//   osteon_bad_inputs generate SEEDS OUT    the cases, and OUT/table.tsv listing them
//
// table.tsv rows: loader, file (relative to OUT), expected exit code, a reason the error line
// must contain (empty: any reason; the exit code and the one-line shape are still checked).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "support/volume_files.h"

namespace fs = std::filesystem;
using osteon::test::writeBytes;

namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

template <typename T>
void put(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));  // test hosts are little-endian
}

// A closed tetrahedron, outward facing, 10 mm edges along the axes.
const float kTetra[4][3] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
const int kTetraFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

std::string binaryStl(const std::string& header80, std::uint32_t count, int facets) {
  std::string b = header80;
  b.resize(80, ' ');
  put(b, count);
  for (int f = 0; f < facets; ++f) {
    for (int k = 0; k < 3; ++k) put(b, 0.0f);
    for (int v : kTetraFaces[f % 4]) {
      for (int k = 0; k < 3; ++k) put(b, kTetra[v][k]);
    }
    put(b, std::uint16_t(0));
  }
  return b;
}

std::string binaryPly() {
  std::string b =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (const auto& v : kTetra) {
    for (int k = 0; k < 3; ++k) put(b, v[k]);
  }
  for (const auto& f : kTetraFaces) {
    put(b, std::uint8_t(3));
    for (int k = 0; k < 3; ++k) put(b, std::int32_t(f[k]));
  }
  return b;
}

// An 8^3 volume, a 4^3 block in its middle: as labels (0/1) or as HU (air and bone).
osteon::test::TestVolume blockVolume(double outside, double inside) {
  osteon::test::TestVolume v;
  v.sizes = glm::ivec3(8);
  v.spacingMm = 2.0;
  for (int z = 0; z < 8; ++z) {
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 8; ++x) {
        const bool in = x >= 2 && x < 6 && y >= 2 && y < 6 && z >= 2 && z < 6;
        v.values.push_back(in ? inside : outside);
      }
    }
  }
  return v;
}

void writeSeeds(const std::string& dir) {
  fs::create_directories(dir);
  writeBytes(dir + "/tetra_binary.stl", binaryStl("osteon seed: binary STL tetrahedron", 4, 4));
  // Binary, though its header starts with "solid" (as some exporters write): its size decides.
  writeBytes(dir + "/tetra_binary_solid_header.stl", binaryStl("solid tetra (binary)", 4, 4));
  writeBytes(dir + "/tetra_binary.ply", binaryPly());
  using osteon::test::encodeAs;
  const osteon::test::TestVolume labels = blockVolume(0, 1);
  osteon::test::writeTestNrrd(dir + "/labels.nrrd", labels, "uint8",
                              encodeAs<std::uint8_t>(labels.values), false);
  osteon::test::writeTestNrrd(dir + "/labels_gzip.nrrd", labels, "uint8",
                              encodeAs<std::uint8_t>(labels.values), true);
  osteon::test::writeTestNrrd(dir + "/labels_detached.nhdr", labels, "uint8",
                              encodeAs<std::uint8_t>(labels.values), false, "labels_detached.raw");
  const osteon::test::TestVolume ct = blockVolume(-1000, 1200);
  osteon::test::writeTestNifti(dir + "/ct.nii", ct, 4, 16, encodeAs<std::int16_t>(ct.values),
                               false);
  osteon::test::writeTestNifti(dir + "/ct.nii.gz", ct, 4, 16, encodeAs<std::int16_t>(ct.values),
                               true);
}

struct Table {
  std::string out;
  std::ofstream tsv;
  int cases = 0;
  void add(const std::string& loader, const std::string& name, const std::string& bytes,
           int exitCode = 2, const std::string& reason = "") {
    fs::create_directories(out + "/" + loader);
    writeBytes(out + "/" + loader + "/" + name, bytes);
    row(loader, loader + "/" + name, exitCode, reason);
  }
  void row(const std::string& loader, const std::string& file, int exitCode,
           const std::string& reason) {
    tsv << loader << '\t' << file << '\t' << exitCode << '\t' << reason << '\n';
    ++cases;
  }
};

bool blank(const std::string& s) {
  return s.find_first_not_of(" \t\r\n") == std::string::npos;
}

// Cut `seed` at `at` bytes unless only whitespace would be lost (that prefix is the same file).
void cut(Table& t, const std::string& loader, const std::string& stem, const std::string& ext,
         const std::string& seed, std::size_t at, const std::string& reason = "") {
  if (at >= seed.size() || blank(seed.substr(at))) return;
  t.add(loader, stem + "_cut" + std::to_string(at) + ext, seed.substr(0, at), 2, reason);
}

// Text with declared counts or a closing keyword: every line end and every token end inside a
// line is a boundary, and every such prefix is invalid.
void cutText(Table& t, const std::string& loader, const std::string& stem, const std::string& ext,
             const std::string& seed, std::size_t from = 0, std::size_t until = std::string::npos) {
  for (std::size_t i = from; i < std::min(until, seed.size()); ++i) {
    if (seed[i] == '\n' || seed[i] == ' ' || seed[i] == ',') cut(t, loader, stem, ext, seed, i);
  }
}

// Line-oriented text without counts (OBJ, CSV): a line cut after its first field is invalid
// (a vertex, face or row with too few values); a cut at a line end may be a valid shorter file.
void cutFields(Table& t, const std::string& loader, const std::string& stem, const std::string& ext,
               const std::string& seed, char separator, std::size_t from = 0) {
  std::size_t lineStart = from;
  while (lineStart < seed.size()) {
    const std::size_t sep = seed.find(separator, lineStart);
    const std::size_t end = seed.find('\n', lineStart);
    if (sep != std::string::npos && sep < end) cut(t, loader, stem, ext, seed, sep + 1);
    if (end == std::string::npos) break;
    lineStart = end + 1;
  }
}

// Truncations of every seed.
void addTruncations(Table& t, const std::string& seeds) {
  const std::string stlText = readAll(seeds + "/tetra_ascii.stl");
  cutText(t, "stl", "tetra_ascii", ".stl", stlText, 1,
          stlText.rfind("endsolid") + 8);  // "endsolid" alone ends it
  const std::string stlBinary = readAll(seeds + "/tetra_binary.stl");
  for (std::size_t at :
       {std::size_t(40), std::size_t(80), std::size_t(82), std::size_t(84), std::size_t(84 + 12),
        std::size_t(84 + 50), std::size_t(84 + 149), std::size_t(84 + 199)}) {
    cut(t, "stl", "tetra_binary", ".stl", stlBinary, at);
  }
  cutFields(t, "obj", "tetra", ".obj", readAll(seeds + "/tetra.obj"), ' ');
  cutText(t, "ply", "tetra_ascii", ".ply", readAll(seeds + "/tetra_ascii.ply"));
  const std::string plyBinary = readAll(seeds + "/tetra_binary.ply");
  const std::size_t body = plyBinary.find("end_header\n") + 11;
  cutText(t, "ply", "tetra_binary", ".ply", plyBinary.substr(0, body));
  for (std::size_t at = body + 4; at < plyBinary.size(); at += 13)
    cut(t, "ply", "tetra_binary", ".ply", plyBinary, at);
  cutText(t, "off", "tetra", ".off", readAll(seeds + "/tetra.off"));
  for (const char* nrrd : {"labels", "labels_gzip"}) {
    const std::string seed = readAll(seeds + "/" + nrrd + ".nrrd");
    const std::size_t data = seed.find("\n\n") + 2;
    cutText(t, "nrrd", nrrd, ".nrrd", seed.substr(0, data - 1));
    for (std::size_t at : {data, data + 1, data + (seed.size() - data) / 2, seed.size() - 1}) {
      cut(t, "nrrd", nrrd, ".nrrd", seed, at);
    }
  }
  for (const char* nii : {"ct.nii", "ct.nii.gz"}) {
    const std::string seed = readAll(seeds + "/" + nii);
    for (std::size_t at :
         {std::size_t(4), std::size_t(40), std::size_t(200), std::size_t(347), std::size_t(348),
          std::size_t(352), std::size_t(352 + 512), seed.size() - 2}) {
      if (at < seed.size())
        t.add("nifti", "cut" + std::to_string(at) + "_" + nii, seed.substr(0, at));
    }
  }
  cutFields(t, "path", "path", ".csv", readAll(seeds + "/path.csv"), ',');
  cutFields(t, "recording", "recording", ".csv", readAll(seeds + "/recording.csv"), ',');
}

// Counts past the file, past 32 bits, past any machine.
void addHugeCounts(Table& t, const std::string& out) {
  t.add("stl", "binary_count_max.stl", binaryStl("binary", 0xffffffffu, 0), 2, "");
  t.add("stl", "binary_count_short.stl", binaryStl("binary", 5, 4), 2, "");
  t.add("stl", "binary_solid_header_count_short.stl", binaryStl("solid but binary", 9, 4), 2, "");
  t.add(
      "ply", "vertex_count_1e15.ply",
      "ply\nformat ascii 1.0\nelement vertex 1000000000000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 "
      "0\n");
  t.add(
      "ply", "face_count_2p64.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 18446744073709551617\nproperty list uchar int "
      "vertex_indices\n"
      "end_header\n" +
          std::string(36, '\0'));
  t.add("off", "counts_1e15.off", "OFF\n1000000000000000 1000000000000000 0\n0 0 0\n");
  t.add("nrrd", "sizes_1e12.nrrd",
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 10000 10000 10000\nencoding: raw\n\n" +
            std::string(64, '\1'),
        2, "exceed 2^32 voxels");
  t.add("nrrd", "sizes_1e12_gzip.nrrd",
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 10000 10000 10000\nencoding: gzip\n\n" +
            osteon::test::gzipBytes(std::string(4096, '\1')));
  // A short gzip stream behind a header asking for 1.6 GB: refused before that is allocated.
  t.add("nrrd", "sizes_1p6e9_gzip_short.nrrd",
        "NRRD0004\ntype: short\ndimension: 3\nsizes: 1000 1000 800\nendian: little\nspacings: 1 1 "
        "1\nencoding: gzip\n\n" +
            osteon::test::gzipBytes(std::string(4096, '\1')));
  {
    osteon::test::TestVolume huge = blockVolume(0, 1);
    huge.sizes = glm::ivec3(32767);
    osteon::test::writeTestNifti(out + "/tmp.nii", huge, 2, 8, std::string(512, '\1'), false);
    t.add("nifti", "dims_32767_cubed.nii", readAll(out + "/tmp.nii"));
    fs::remove(out + "/tmp.nii");
  }
}

// Lines too long to be a header or a number.
void addLongLines(Table& t) {
  const std::string longLine(10u << 20, '7');
  t.add("obj", "long_line.obj", "v 0 0 " + longLine + "\n");
  t.add("stl", "long_line.stl", "solid " + longLine + "\n");
  t.add("path", "long_line.csv", "t,x,y,z,drill_on\n0,10,10,30," + longLine + "\n");
  t.add("recording", "long_line.csv",
        std::string("t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n") + longLine + "\n");
  t.add("nrrd", "long_comment.nrrd", "NRRD0004\n# " + longLine + "\ntype: uint8\n");
}

// Names that are not regular, readable files.
void addNonFiles(Table& t, const std::string& out) {
  for (const char* loader : {"stl", "obj", "ply", "off", "nrrd", "nifti", "path", "recording"}) {
    const std::string ext = std::string(loader) == "nifti" ? ".nii"
                            : std::string(loader) == "path" || std::string(loader) == "recording"
                                ? ".csv"
                                : "." + std::string(loader);
    const std::string dir = out + "/" + loader;
    fs::create_directories(dir);
    fs::create_directories(dir + "/a_directory" + ext);
    t.row(loader, std::string(loader) + "/a_directory" + ext, 2, "not a regular file");
    fs::create_symlink("/dev/zero", dir + "/dev_zero" + ext);
    t.row(loader, std::string(loader) + "/dev_zero" + ext, 2, "not a regular file");
    if (mkfifo((dir + "/fifo" + ext).c_str(), 0600) == 0)
      t.row(loader, std::string(loader) + "/fifo" + ext, 2, "not a regular file");
    fs::create_symlink("nowhere" + ext, dir + "/dangling" + ext);
    t.row(loader, std::string(loader) + "/dangling" + ext, 2, "");
    t.row(loader, std::string(loader) + "/missing" + ext, 2, "");
    t.add(loader, "empty" + ext, "");
    // Root reads any file whatever its mode: the case exists only for other users.
    if (geteuid() != 0) {
      t.add(loader, "unreadable" + ext, "x");
      fs::permissions(dir + "/unreadable" + ext, fs::perms::none);
    }
  }
}

void generate(const std::string& seeds, const std::string& out) {
  fs::create_directories(out);
  Table t{out, std::ofstream(out + "/table.tsv"), 0};
  t.tsv << "# loader\tfile\texit\treason (generated by osteon_bad_inputs; see "
           "tests/data/bad/README.md)\n";
  addTruncations(t, seeds);
  addHugeCounts(t, out);
  addLongLines(t);
  addNonFiles(t, out);
  std::cout << "osteon_bad_inputs: " << t.cases << " cases in " << out << "/table.tsv\n";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 2 && args[0] == "seeds") {
      writeSeeds(args[1]);
      return 0;
    }
    if (args.size() == 3 && args[0] == "generate") {
      generate(args[1], args[2]);
      return 0;
    }
    std::cerr << "usage: osteon_bad_inputs seeds DIR | generate SEEDS_DIR OUT_DIR\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "osteon_bad_inputs: " << e.what() << "\n";
    return 1;
  }
}
