#include "osteon/geometry/io/output_file.h"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_dir.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

namespace {

// A hidden name beside the output that no other run (process id) or output (counter) uses;
// it keeps the extension, by which image writers choose their format.
std::string temporaryNameFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  const std::string name = "." + p.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter.fetch_add(1)) + p.extension().string();
  return (p.parent_path() / name).string();
}

}  // namespace

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
  if (path_.empty()) throw InputError("output path is empty");
  std::error_code ec;
  if (fs::is_directory(path_, ec)) throw InputError(path_ + ": is a folder, not a file");
  tempPath_ = temporaryNameFor(path_);
}

OutputFile::OutputFile(OutputFile&& other) noexcept
    : path_(std::move(other.path_)),
      tempPath_(std::move(other.tempPath_)),
      committed_(other.committed_) {
  other.committed_ = true;  // the moved-from object owns no temporary file
}

OutputFile::~OutputFile() {
  if (!committed_ && !tempPath_.empty()) std::remove(tempPath_.c_str());
}

void OutputFile::commit() {
  if (committed_) return;
  // Inside an open run folder, the output waits for the rest of its run's set (output_dir.h).
  if (OutputDir::holdBack(tempPath_, path_)) {
    committed_ = true;
    return;
  }
  commitTo(path_);
}

void OutputFile::commitTo(const std::string& otherPath) {
  if (committed_) return;
  std::error_code ec;
  fs::rename(tempPath_, otherPath, ec);
  if (ec) {
    std::remove(tempPath_.c_str());
    committed_ = true;
    throw InputError(otherPath + ": cannot put the output in place (" + ec.message() + ")");
  }
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  OutputFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw InputError(path + ": writing failed (disk full or not writable?)");
  }
  file.commit();
}

bool sameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  const bool same = fs::equivalent(a, b, ec);
  return !ec && same;
}

void refuseOverwritingInputs(const std::vector<std::string>& outputs,
                             const std::vector<std::string>& inputs) {
  for (const std::string& out : outputs) {
    for (const std::string& in : inputs) {
      if (!out.empty() && !in.empty() && sameFile(out, in)) {
        throw InputError(out + ": the same file as the input " + in +
                         " (osteon never overwrites its input; choose another output)");
      }
    }
  }
}

}  // namespace osteon::geometry
