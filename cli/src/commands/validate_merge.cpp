// `osteon validate --merge`: the reports of a run's shards (`--shard K/N`) as the one report
// the whole run writes, after checking that they are one run.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands/validate_report.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "support/files.h"

namespace osteon::cli {

using nlohmann::json;

namespace {

// Crack images sort by the model index that leads their folder (images/<model>_<method>/), as
// a whole run writes them; a shard writes those of the models whose first group it owns.
std::size_t imageModelIndex(const std::string& image) {
  const std::string prefix = "images/";
  if (image.rfind(prefix, 0) != 0) return 0;
  std::size_t i = prefix.size(), index = 0;
  while (i < image.size() && std::isdigit(static_cast<unsigned char>(image[i])))
    index = index * 10 + std::size_t(image[i++] - '0');
  return index;
}

// An open file, closed when it goes out of scope.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// A shard's file opened for reading only if it is a plain file under that very name: a link is
// refused, never followed (O_NOFOLLOW), and a FIFO or device never blocks the merge. -1 and
// `why` set when it is not.
int openShardFile(const std::string& path, std::string& why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    why = errno == ELOOP
              ? "is a symbolic link (a shard's outputs are its own files: links are not followed)"
              : std::string("cannot be opened (") + std::strerror(errno) + ")";
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    why = "is not a regular file (a shard's outputs are plain files)";
    return -1;
  }
  return fd;
}

// Passes all of an open file to `sink` block by block; false on a read error (errno set) or
// when the sink returns false.
template <typename Sink>
bool readBlocks(int fd, Sink sink) {
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) return true;
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (!sink(buffer, std::size_t(n))) return false;
  }
}

// The files of a shard's output folder `rel` (images, plots, forces, and their sub-folders),
// relative to the shard, by the names the folder holds. Only real folders and regular files:
// anything else (a link above all, which could lead the copy out of --out-dir) is refused.
void listShardFiles(const std::string& dir, const std::string& rel, int depth,
                    std::vector<std::string>& files) {
  namespace fs = std::filesystem;
  const auto bad = [&](const std::string& why) {
    return InputError("--merge " + dir + ": " + why);
  };
  std::error_code ec;
  for (fs::directory_iterator it(dir + "/" + rel, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string sub = rel + "/" + it->path().filename().string();
    const fs::file_status status = it->symlink_status(ec);
    if (ec) break;
    if (fs::is_symlink(status))
      throw bad(
          sub +
          " is a symbolic link (a shard's outputs are its own files: links are not followed)");
    if (fs::is_directory(status)) {
      if (depth >= 4) throw bad(sub + " is nested deeper than validate writes");
      listShardFiles(dir, sub, depth + 1, files);
    } else if (!fs::is_regular_file(status)) {
      throw bad(sub + " is not a regular file (a shard's outputs are plain files)");
    } else if (it->path().filename().string().rfind("plots.gp", 0) != 0) {
      files.push_back(sub);
    }
  }
  if (ec) throw bad("cannot read " + rel + " (" + ec.message() + ")");
}

// What a shard's images, plots and force logs are, checked before anything is copied; not
// the shard's gnuplot script, which names the shard's own files.
std::vector<std::string> shardFiles(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  for (const char* sub : {"images", "plots", "forces"}) {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(dir + "/" + sub, ec);
    if (!fs::exists(status)) continue;
    if (fs::is_symlink(status)) {
      throw InputError(
          "--merge " + dir + ": " + sub +
          " is a symbolic link (a shard's outputs are its own files: links are not followed)");
    }
    if (!fs::is_directory(status))
      throw InputError("--merge " + dir + ": " + sub + " is not a folder");
    listShardFiles(dir, sub, 1, files);
  }
  return files;
}

// A folder of the merged report inside --out-dir, made if need be; it must be a real folder,
// not a link, so that every copy lands inside --out-dir.
void makeOutputFolder(const std::string& outDir, const std::string& rel) {
  namespace fs = std::filesystem;
  std::string path = outDir;
  for (const fs::path& part : fs::path(rel)) {
    path += "/" + part.string();
    std::error_code ec;
    fs::create_directory(path, ec);
    if (!fs::is_directory(fs::symlink_status(path, ec))) {
      throw InputError(
          "--out-dir " + outDir + ": " + path.substr(outDir.size() + 1) +
          " is not a folder of its own (a link or a file: a merge writes only inside --out-dir)");
    }
  }
}

// One shard file (`rel`, a name listShardFiles found) copied to the same name inside --out-dir,
// through a temporary file and a rename: a link already at the target is replaced, not followed.
void copyShardFile(const std::string& dir, const std::string& rel, const std::string& outDir) {
  std::string why;
  const FileDescriptor in{openShardFile(dir + "/" + rel, why)};
  if (in.fd < 0) throw InputError("--merge " + dir + ": " + rel + " " + why);
  makeOutputFolder(outDir, std::filesystem::path(rel).parent_path().string());
  geometry::OutputFile out(outDir + "/" + rel);
  FileDescriptor to{
      ::open(out.tempPath().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644)};
  if (to.fd < 0)
    throw InputError(out.path() + ": cannot open for writing (" + std::strerror(errno) + ")");
  bool written = true;
  const bool read = readBlocks(in.fd, [&](const char* p, std::size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(to.fd, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return written = false;
      p += w;
      n -= std::size_t(w);
    }
    return true;
  });
  const int error = errno;
  if (::close(std::exchange(to.fd, -1)) != 0) written = false;
  if (!written) throw InputError(out.path() + ": writing failed (disk full or not writable?)");
  if (!read)
    throw InputError("--merge " + dir + ": cannot read " + rel + " (" + std::strerror(error) + ")");
  out.commit();
}

// A shard's validate.log, if it has one (a plain file, as its outputs).
std::string shardLog(const std::string& dir) {
  const std::string path = dir + "/validate.log";
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return "";
  std::string why, bytes;
  const FileDescriptor in{openShardFile(path, why)};
  if (in.fd < 0) throw InputError("--merge " + dir + ": validate.log " + why);
  if (!readBlocks(in.fd, [&](const char* p, std::size_t n) { return bytes.append(p, n), true; })) {
    throw InputError("--merge " + dir + ": cannot read validate.log (" + std::strerror(errno) +
                     ")");
  }
  return bytes;
}

// One run: the same osteon, options, shard count and case list in every report.
void checkSameRun(const std::vector<ShardReport>& shards) {
  const ShardReport& first = shards.front();
  for (const ShardReport& s : shards) {
    const std::string pair = first.dir + " and " + s.dir;
    if (s.report["osteon_version"] != first.report["osteon_version"]) {
      throw InputError("--merge: " + pair + " come from different osteon versions (" +
                       first.report["osteon_version"].get<std::string>() + ", " +
                       s.report["osteon_version"].get<std::string>() + ")");
    }
    if (s.count != first.count) {
      throw InputError("--merge: " + pair + " are shards of different splits (of " +
                       std::to_string(first.count) + " and of " + std::to_string(s.count) +
                       " shards)");
    }
    if (s.report["shard"]["case_list"] != first.report["shard"]["case_list"]) {
      throw InputError("--merge: " + pair +
                       " are shards of different runs (their case lists differ)");
    }
    if (s.report["options"] != first.report["options"]) {
      throw InputError("--merge: " + pair + " are shards of different runs (their options differ)");
    }
  }
}

// The shards in index order: each once, none missing.
std::vector<const ShardReport*> shardsByIndex(const std::vector<ShardReport>& shards) {
  const ShardReport& first = shards.front();
  // Each shard once. A map, not a table of N: N may be as large as --shard takes.
  std::map<std::size_t, const ShardReport*> slots;
  for (const ShardReport& s : shards) {
    const auto [slot, added] = slots.emplace(s.index, &s);
    if (!added) {
      throw InputError("--merge: " + slot->second->dir + " and " + s.dir + " are both shard " +
                       std::to_string(s.index) + "/" + std::to_string(s.count));
    }
  }
  if (slots.size() < first.count) {
    std::string missing;
    std::size_t listed = 0;
    for (std::size_t k = 0; k < first.count && listed < 8; ++k) {
      if (slots.count(k)) continue;
      missing +=
          (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(first.count);
      ++listed;
    }
    if (first.count - slots.size() > listed)
      missing += " and " + std::to_string(first.count - slots.size() - listed) + " more";
    std::string given;
    for (const ShardReport& s : shards) {
      given += (given.empty() ? "" : ", ") + s.dir + " (" + std::to_string(s.index) + "/" +
               std::to_string(s.count) + ")";
    }
    throw InputError("--merge: shard " + missing + " missing (given: " + given + ")");
  }
  std::vector<const ShardReport*> byIndex;
  for (const auto& slot : slots) byIndex.push_back(slot.second);
  return byIndex;
}

// Every case of the run in exactly one shard, then in the run's order.
json mergedCases(const std::vector<ShardReport>& shards) {
  const ShardReport& first = shards.front();
  std::map<std::string, const json*> caseOf;
  std::map<std::string, std::string> dirOf;
  for (const ShardReport& s : shards) {
    for (const json& c : s.report["cases"]) {
      const std::string key = caseKey(c);
      if (caseOf.count(key))
        throw InputError("--merge: " + dirOf[key] + " and " + s.dir + " both hold case " + key);
      caseOf[key] = &c;
      dirOf[key] = s.dir;
    }
  }
  json cases = json::array();
  for (const json& key : first.report["shard"]["case_list"]) {
    const auto it = caseOf.find(key.get<std::string>());
    if (it == caseOf.end())
      throw InputError("--merge: no shard holds case " + key.get<std::string>());
    cases.push_back(*it->second);
  }
  if (cases.size() != caseOf.size())
    throw InputError("--merge: a shard holds a case outside its run's case list");

  return cases;
}

// Outputs: never into a shard's own folder, never over an input.
void refuseMergeOutputs(const ValidateCommandOptions& options,
                        const std::vector<ShardReport>& shards) {
  namespace fs = std::filesystem;
  std::vector<std::string> inputs{options.compare};
  for (const ShardReport& s : shards) {
    std::error_code ec;
    if (fs::exists(options.outDir, ec) && fs::equivalent(options.outDir, s.dir, ec)) {
      throw InputError("--out-dir " + options.outDir + ": is the shard folder " + s.dir +
                       " (merge into another folder)");
    }
    inputs.push_back(s.dir + "/report.json");
  }
  geometry::refuseOverwritingInputs(
      {options.outDir + "/report.json", options.outDir + "/report.html",
       options.outDir + "/validate.log"},
      inputs);
  for (const char* owned : {"/forces", "/plots", "/images"})
    refuseInputsInside(options.outDir + owned, inputs);
}

}  // namespace

// --merge: the shards' reports as one, as the whole run would have written it.
int runValidateMerge(const ValidateCommandOptions& options) {
  namespace fs = std::filesystem;
  if (!options.runOptionsGiven.empty()) {
    throw InputError(
        "--merge: " + options.runOptionsGiven.front() +
        " is an option of a run, not of a merge (each shard's report holds its run's options)");
  }
  const json old = options.compare.empty() ? json() : readComparable(options.compare);
  std::vector<ShardReport> shards;
  for (const std::string& dir : options.merge)
    shards.push_back(readShard(dir, dir + "/report.json"));

  const ShardReport& first = shards.front();
  checkSameRun(shards);
  const std::vector<const ShardReport*> byIndex = shardsByIndex(shards);
  const json cases = mergedCases(shards);
  refuseMergeOutputs(options, shards);
  // What each shard brings, checked before anything is written.
  std::vector<std::vector<std::string>> files;
  std::vector<std::string> logs;
  for (const ShardReport* s : byIndex) {
    files.push_back(shardFiles(s->dir));
    logs.push_back(shardLog(s->dir));
  }
  geometry::OutputDir outDir(
      options.outDir, {"report.json", "report.html", "validate.log", "forces", "plots", "images"});
  for (const char* owned : {"images", "plots", "forces"}) makeOutputFolder(options.outDir, owned);

  std::set<std::string> plots;
  std::vector<std::string> images;
  std::string log;
  json mergedFrom = json::array(), shardSeconds = json::array();
  double seconds = 0.0;
  std::string started = byIndex.front()->report["started"];
  for (std::size_t k = 0; k < byIndex.size(); ++k) {
    const ShardReport* s = byIndex[k];
    for (const std::string& rel : files[k]) copyShardFile(s->dir, rel, options.outDir);
    for (const json& p : s->report["plots"]) plots.insert(p.get<std::string>());
    for (const json& i : s->report["images"]) images.push_back(i.get<std::string>());
    mergedFrom.push_back(s->dir);
    shardSeconds.push_back(s->report["seconds"]);
    seconds += s->report["seconds"].get<double>();
    started =
        std::min(started, s->report["started"].get<std::string>());  // ISO 8601 UTC sorts as text
    log += "# shard " + std::to_string(s->index) + "/" + std::to_string(s->count) + ": " + s->dir +
           "\n" + logs[k];
  }
  std::stable_sort(images.begin(), images.end(), [](const std::string& a, const std::string& b) {
    return imageModelIndex(a) < imageModelIndex(b);
  });
  geometry::writeFileAtomically(options.outDir + "/validate.log", log);
  json j = {{"schema", "osteon-validate/1"},
            {"started", started},
            {"seconds", seconds},
            {"osteon_version", first.report["osteon_version"]},
            {"options", first.report["options"]},
            {"environment", byIndex.front()->report.value("environment", json::object())},
            {"cases", cases},
            {"plots", std::vector<std::string>(plots.begin(), plots.end())},
            {"regressions", json::array()},
            {"merged_from", mergedFrom},
            {"shard_seconds", shardSeconds}};
  writeReport(j, options, old, images);
  outDir.commit();
  return printVerdict(j, options.outDir);
}

}  // namespace osteon::cli
