// The loader of libosteon_image.so (see image_writer.h for why and where it is looked for).
#include "osteon/image/image_writer.h"

#include <array>
#include <cstdlib>
#include <dlfcn.h>
#include <mutex>
#include <unistd.h>
#include <vector>

#include "osteon/core/error.h"
#include "plugin_abi.h"

namespace osteon::image {

namespace {

struct Plugin {
  std::string path;  // empty until loaded
  osteon_image_library_version_fn libraryVersion = nullptr;
  osteon_image_write_u8_fn writeU8 = nullptr;
};

std::string executableDir() {
  std::array<char, 4096> buffer{};
  const ssize_t n = ::readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  if (n <= 0) return {};
  const std::string exe(buffer.data(), std::size_t(n));
  const std::size_t slash = exe.rfind('/');
  return slash == std::string::npos ? std::string() : exe.substr(0, slash);
}

// The places to try, in order; a name without '/' asks the dynamic loader to search.
std::vector<std::string> candidates() {
  const std::string name = OSTEON_IMAGE_PLUGIN_NAME;
  if (const char* forced = std::getenv("OSTEON_IMAGE_PLUGIN");
      forced != nullptr && *forced != '\0') {
    return {forced};
  }
  std::vector<std::string> paths;
  const auto add = [&paths](const std::string& p) {
    for (const std::string& q : paths) {
      if (q == p) return;
    }
    paths.push_back(p);
  };
  if (const std::string exeDir = executableDir(); !exeDir.empty()) {
    add(exeDir + "/" + name);
    add(exeDir + "/" + OSTEON_IMAGE_INSTALL_RELATIVE_LIBDIR + "/" + name);
  }
  add(std::string(OSTEON_IMAGE_BUILD_DIR) + "/" + name);
  add(std::string(OSTEON_IMAGE_INSTALL_LIBDIR) + "/" + name);
  add(name);
  return paths;
}

// Opens one candidate; on failure returns false with the reason in `error`.
bool tryOpen(const std::string& path, Plugin& plugin, std::string& error) {
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* reason = ::dlerror();
    error = reason != nullptr ? reason : path + ": dlopen failed";
    return false;
  }
  const auto abi = reinterpret_cast<osteon_image_abi_fn>(::dlsym(handle, "osteon_image_abi"));
  const auto version = reinterpret_cast<osteon_image_library_version_fn>(
      ::dlsym(handle, "osteon_image_library_version"));
  const auto write =
      reinterpret_cast<osteon_image_write_u8_fn>(::dlsym(handle, "osteon_image_write_u8"));
  if (abi == nullptr || version == nullptr || write == nullptr) {
    error = path + ": not an osteon image plugin (missing symbols)";
  } else if (abi() != OSTEON_IMAGE_ABI) {
    error = path + ": built for image interface " + std::to_string(abi()) + ", this osteon needs " +
            std::to_string(OSTEON_IMAGE_ABI);
  } else {
    plugin.path = path;
    plugin.libraryVersion = version;
    plugin.writeU8 = write;
    return true;  // never closed: OpenImageIO keeps threads and static state until exit
  }
  ::dlclose(handle);
  return false;
}

std::mutex gMutex;
Plugin gPlugin;

// The loaded plugin, loading it on first use. Throws InputError naming what was tried.
const Plugin& plugin() {
  const std::lock_guard<std::mutex> lock(gMutex);
  if (!gPlugin.path.empty()) return gPlugin;
  const std::vector<std::string> paths = candidates();
  std::string firstReal;  // the reason of the first candidate that exists but would not load
  std::string last;
  std::string tried;
  for (const std::string& path : paths) {
    const bool searched = path.find('/') == std::string::npos;
    if (!searched && ::access(path.c_str(), F_OK) != 0) {
      last = path + ": no such file";
    } else if (tryOpen(path, gPlugin, last)) {
      return gPlugin;
    } else if (firstReal.empty() && !searched) {
      firstReal = last;
    }
    tried += (tried.empty() ? "" : ", ") + (searched ? path + " on the loader path" : path);
  }
  throw InputError(std::string(OSTEON_IMAGE_PLUGIN_NAME) +
                   ": cannot load osteon's image plugin (OpenImageIO), " +
                   "needed to write images: " + (firstReal.empty() ? last : firstReal) +
                   " (tried " + tried + "; set OSTEON_IMAGE_PLUGIN to its path)");
}

}  // namespace

std::string writeImageU8(const std::string& path, int width, int height, int channels,
                         const std::uint8_t* pixels) {
  const Plugin& p = plugin();
  std::array<char, 512> error{};
  if (p.writeU8(path.c_str(), width, height, channels, pixels, error.data(), error.size()) == 0)
    return {};
  return error[0] != '\0' ? std::string(error.data())
                          : std::string("OpenImageIO could not write it");
}

std::string openImageIOVersion() {
  return plugin().libraryVersion();
}

}  // namespace osteon::image
