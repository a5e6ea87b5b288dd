// Outputs that never destroy an input and never leave half a file: each output is written to
// a temporary file in its own folder and renamed into place only once it is complete.
#pragma once

#include <string>
#include <vector>

namespace osteon::geometry {

// One output in progress. Write to tempPath(), then commit() renames it onto path() (atomic
// on POSIX within one folder). Destroyed without commit(), it removes the temporary file.
// Throws InputError naming path() when the folder is not writable or the rename fails.
class OutputFile {
 public:
  explicit OutputFile(std::string path);
  ~OutputFile();
  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&&) = delete;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& path() const { return path_; }
  const std::string& tempPath() const { return tempPath_; }
  // Inside a run folder that is open (output_dir.h), the file is put in place with the rest of
  // its run's set; elsewhere at once.
  void commit();
  // Renames onto a path in the same folder at once, run folder or not: an output kept under a
  // name that says it is incomplete (a force log cut short by a full disk), or a failure's log.
  void commitTo(const std::string& otherPath);

 private:
  std::string path_;
  std::string tempPath_;
  bool committed_ = false;
};

// Writes `bytes` to path through an OutputFile.
void writeFileAtomically(const std::string& path, const std::string& bytes);

// True when both name the same existing file (after symlinks, and hard links alike).
bool sameFile(const std::string& a, const std::string& b);

// Refuses (InputError, naming both) any output that resolves to one of the inputs. Inputs or
// outputs that do not exist are skipped: a file that does not exist cannot be overwritten.
void refuseOverwritingInputs(const std::vector<std::string>& outputs,
                             const std::vector<std::string>& inputs);

}  // namespace osteon::geometry
