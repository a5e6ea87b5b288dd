// Scratch folders and file bytes for every suite. Header-only and standard C++ alone, so the
// devices suite, which links osteon::devices and nothing else, uses it too.
#pragma once

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace osteon::test {

// A fresh empty folder under the system temp dir, unique per call (tag, process, counter).
inline std::string makeTempDir(const std::string& tag) {
  static std::atomic<int> counter{0};
  std::ostringstream name;
  name << "osteon_" << tag << "_" << ::getpid() << "_" << counter++;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name.str();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// A fresh folder for one scope, removed with everything in it at the scope's end.
class ScopedTempDir {
 public:
  explicit ScopedTempDir(const std::string& tag = "scratch") : path_(makeTempDir(tag)) {}
  ~ScopedTempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Writes `bytes` as the whole file; throws when it cannot.
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

// The whole file ("" when it cannot be read).
inline std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace osteon::test
