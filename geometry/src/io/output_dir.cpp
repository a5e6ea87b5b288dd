#include "osteon/geometry/io/output_dir.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <signal.h>
#include <sstream>
#include <stdexcept>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <system_error>
#include <unistd.h>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

namespace {

std::mutex gMutex;  // guards gOpen and its held-back files (commits from any thread)
OutputDir* gOpen = nullptr;

// The process id in an OutputFile temporary's name (.NAME.tmpPID-N.EXT), 0 when it is not one.
long temporaryOwner(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return 0;
  for (std::size_t at = name.rfind(".tmp"); at != std::string::npos && at > 0;
       at = name.rfind(".tmp", at - 1)) {
    std::size_t i = at + 4;
    long pid = 0;
    const std::size_t digits = i;
    while (i < name.size() && name[i] >= '0' && name[i] <= '9' && pid < 100000000)
      pid = pid * 10 + (name[i++] - '0');
    if (i == digits || i >= name.size() || name[i] != '-') continue;
    const std::size_t counter = ++i;
    while (i < name.size() && name[i] >= '0' && name[i] <= '9') ++i;
    if (i > counter && (i == name.size() || name[i] == '.')) return pid;
  }
  return 0;
}

bool processAlive(long pid) {
  return ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

// The process holding a flock on the folder, from /proc/locks (Linux); 0 when unknown.
long lockHolder(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return 0;
  char id[64];
  std::snprintf(id, sizeof id, "%02x:%02x:%llu", major(st.st_dev), minor(st.st_dev),
                static_cast<unsigned long long>(st.st_ino));
  std::ifstream locks("/proc/locks");
  for (std::string line; std::getline(locks, line);) {
    std::istringstream fields(line);
    std::string number, kind, advisory, mode, device;
    long pid = 0;
    if (!(fields >> number >> kind) || kind == "->") continue;  // a waiter, not the holder
    if (!(fields >> advisory >> mode >> pid >> device)) continue;
    if (kind == "FLOCK" && device == id) return pid;
  }
  return 0;
}

// `path` inside `root`, both canonical (element by element, so /a/bc is not inside /a/b).
bool inside(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p) {
    if (r->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *r) return false;
  }
  return p != path.end();
}

// The folder resolved, the last name not: a rename onto a link replaces the link, so a link
// at the output's place is that entry of the folder, not the file it points to.
std::string canonicalKey(const std::string& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  if (ec || !absolute.has_filename()) return std::string();
  const fs::path folder = fs::weakly_canonical(absolute.parent_path(), ec);
  return ec ? std::string() : (folder / absolute.filename()).string();
}

}  // namespace

OutputDir::OutputDir(const std::string& folder, std::vector<std::string> owned,
                     const std::string& option)
    : folder_(folder), option_(option), owned_(std::move(owned)) {
  std::error_code ec;
  created_ = !fs::exists(folder_, ec);
  fs::create_directories(folder_, ec);
  if (ec || !fs::is_directory(folder_)) {
    throw InputError(option_ + " " + folder_ + ": cannot create the folder (" +
                     (ec ? ec.message() : std::string("not a folder")) + ")");
  }
  root_ = fs::canonical(folder_, ec).string();
  if (ec)
    throw InputError(option_ + " " + folder_ + ": cannot resolve the folder (" + ec.message() +
                     ")");
  // The lock is the folder's own (no lock file to leave behind), held until the run ends.
  lockFd_ = ::open(folder_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lockFd_ >= 0 && ::flock(lockFd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    if (error == EWOULDBLOCK) {
      const long pid = lockHolder(lockFd_);
      ::close(lockFd_);
      throw InputError(option_ + " " + folder_ + ": another osteon run" +
                       (pid > 0 ? " (process " + std::to_string(pid) + ")" : std::string()) +
                       " is writing into this folder; wait for it to end, or choose another " +
                       option_);
    }
    // A file system without locks: the run goes on unlocked.
  }
  try {
    removeLeftovers();
    interrupts_ = std::make_unique<InterruptScope>();
  } catch (...) {
    if (lockFd_ >= 0) ::close(lockFd_);
    throw;
  }
  std::lock_guard<std::mutex> lock(
      gMutex);  // registered last: a constructor that threw is no open folder
  if (gOpen) {
    interrupts_.reset();
    if (lockFd_ >= 0) ::close(lockFd_);
    throw std::logic_error("OutputDir: " + folder_ + " opened while " + gOpen->folder_ +
                           " is open");
  }
  gOpen = this;
}

OutputDir::~OutputDir() {
  std::lock_guard<std::mutex> lock(gMutex);
  if (!committed_) {
    for (const auto& [temp, final] : held_) std::remove(temp.c_str());
    removeEmptyFolders(true);
    std::error_code ec;
    if (created_ && fs::is_empty(folder_, ec)) fs::remove(folder_, ec);
  }
  gOpen = nullptr;
  interrupts_.reset();
  if (lockFd_ >= 0) ::close(lockFd_);
}

void OutputDir::commit() {
  throwIfInterrupted();  // an interrupted run's outputs are cut short: never put in place
  std::lock_guard<std::mutex> lock(gMutex);
  if (committed_) return;
  committed_ = true;  // from here on, a failure leaves what is in place (see the header)
  for (const auto& [temp, final] : held_) {
    std::error_code ec;
    fs::rename(temp, final, ec);
    if (ec) {
      for (const auto& held : held_) std::remove(held.first.c_str());
      throw InputError(final + ": cannot put the output in place (" + ec.message() + ")");
    }
  }
  removeStale();
  removeEmptyFolders(false);
}

bool OutputDir::holdBack(const std::string& tempPath, const std::string& finalPath) {
  std::lock_guard<std::mutex> lock(gMutex);
  if (!gOpen || gOpen->committed_) return false;
  const std::string key = canonicalKey(finalPath);
  if (key.empty() || !inside(key, gOpen->root_)) return false;
  const auto it = gOpen->heldIndex_.find(key);
  if (it != gOpen->heldIndex_.end()) {  // written twice in one run: the last one counts
    std::remove(gOpen->held_[it->second].first.c_str());
    gOpen->held_[it->second].first = tempPath;
    return true;
  }
  gOpen->heldIndex_[key] = gOpen->held_.size();
  gOpen->held_.emplace_back(tempPath, key);
  return true;
}

std::string OutputDir::currentPath(const std::string& path) {
  std::lock_guard<std::mutex> lock(gMutex);
  if (!gOpen) return path;
  const auto it = gOpen->heldIndex_.find(canonicalKey(path));
  return it == gOpen->heldIndex_.end() ? path : gOpen->held_[it->second].first;
}

void OutputDir::removeLeftovers() const {
  const long self = long(::getpid());
  const auto removeIfLeftover = [&](const fs::directory_entry& e) {
    std::error_code ec;
    if (!e.is_regular_file(ec) || e.is_symlink(ec)) return;
    const long pid = temporaryOwner(e.path().filename().string());
    if (pid > 0 && pid != self && !processAlive(pid)) fs::remove(e.path(), ec);
  };
  // Any command's run may have been killed here, so not only this run's entries are looked
  // at: the folder to a depth its commands write (runs/NAME/forces.csv), symlinks not
  // followed, bounded for a folder that is also a user's working folder.
  constexpr int kDepth = 3;
  constexpr std::size_t kMaxEntries = 20000;
  std::error_code ec;
  fs::recursive_directory_iterator it(folder_, fs::directory_options::skip_permission_denied, ec);
  std::size_t seen = 0;
  for (; !ec && it != fs::recursive_directory_iterator() && ++seen <= kMaxEntries;
       it.increment(ec)) {
    if (it.depth() >= kDepth - 1) it.disable_recursion_pending();
    removeIfLeftover(*it);
  }
}

void OutputDir::removeStale() const {
  std::set<std::string> kept;
  for (const auto& held : held_) kept.insert(held.second);
  const auto removeUnlessKept = [&](const fs::path& p) {
    std::error_code ec;
    const std::string name = p.filename().string();
    const long pid = temporaryOwner(name);
    if (pid > 0 && processAlive(pid)) return;  // another command's output in progress
    if (!kept.count(canonicalKey(p.string()))) fs::remove(p, ec);
  };
  for (const std::string& name : owned_) {
    const fs::path entry = fs::path(folder_) / name;
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(entry, ec);
    if (ec || !fs::exists(status)) continue;
    if (!fs::is_directory(status)) {
      removeUnlessKept(entry);
      continue;
    }
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(entry, ec)) {
      if (!e.is_directory(ec) || e.is_symlink(ec)) files.push_back(e.path());
    }
    for (const fs::path& f : files) removeUnlessKept(f);
  }
}

void OutputDir::removeEmptyFolders(bool includeOwnedRoots) const {
  for (const std::string& name : owned_) {
    const fs::path entry = fs::path(folder_) / name;
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(entry, ec))) continue;
    std::vector<fs::path> folders;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(entry, ec)) {
      if (e.is_directory(ec) && !e.is_symlink(ec)) folders.push_back(e.path());
    }
    // Deepest first, so a folder emptied by its children's removal goes too.
    std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) {
      return a.string().size() > b.string().size();
    });
    for (const fs::path& f : folders) {
      if (fs::is_empty(f, ec)) fs::remove(f, ec);
    }
    if (includeOwnedRoots && fs::is_empty(entry, ec)) fs::remove(entry, ec);
  }
}

}  // namespace osteon::geometry
