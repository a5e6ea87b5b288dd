// Loading one of osteon's plugins (libosteon_image.so, libosteon_dicom.so): the shared objects
// that alone link a library too costly to load at every start (OpenImageIO, GDCM). Where a
// plugin is looked for, first found wins:
//   1. $<env>, a path to the .so (when set, the only place tried);
//   2. the running executable's folder (/proc/self/exe);
//   3. the installed layout beside it: <exe folder>/<relative libdir>;
//   4. the build tree, where CMake builds the plugin;
//   5. the install prefix's library folder;
//   6. the dynamic loader's own search (LD_LIBRARY_PATH, ld.so.cache).
#pragma once

#include <array>
#include <cstdlib>
#include <dlfcn.h>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

#include "osteon/core/error.h"

namespace osteon {

struct PluginPlaces {
  const char* env;             // "OSTEON_IMAGE_PLUGIN"
  std::string name;            // "libosteon_image.so"
  std::string buildDir;        // where CMake builds it
  std::string relativeLibDir;  // the library folder relative to the executable's
  std::string installLibDir;   // the install prefix's library folder
};

inline std::vector<std::string> pluginCandidates(const PluginPlaces& at) {
  if (const char* forced = std::getenv(at.env); forced != nullptr && *forced != '\0') {
    return {forced};
  }
  std::vector<std::string> paths;
  const auto add = [&paths](const std::string& p) {
    for (const std::string& q : paths) {
      if (q == p) return;
    }
    paths.push_back(p);
  };
  std::array<char, 4096> buffer{};
  const ssize_t n = ::readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  const std::string exe = n > 0 ? std::string(buffer.data(), std::size_t(n)) : std::string();
  const std::size_t slash = exe.rfind('/');
  if (slash != std::string::npos) {
    const std::string exeDir = exe.substr(0, slash);
    add(exeDir + "/" + at.name);
    add(exeDir + "/" + at.relativeLibDir + "/" + at.name);
  }
  add(at.buildDir + "/" + at.name);
  add(at.installLibDir + "/" + at.name);
  add(at.name);
  return paths;
}

// Opens the first candidate that loads and that `accept(handle, path, error)` takes (it looks
// up the symbols and checks the interface version; false with the reason in `error`). Returns
// the handle, never closed. Throws InputError "<name>: cannot load <what>: <reason> (tried
// ...; set <env> to its path)".
inline void* loadPlugin(
    const PluginPlaces& at, const std::string& what,
    const std::function<bool(void*, const std::string&, std::string&)>& accept) {
  std::string firstReal;  // the reason of the first candidate that exists but would not load
  std::string last;
  std::string tried;
  for (const std::string& path : pluginCandidates(at)) {
    const bool searched = path.find('/') == std::string::npos;
    if (!searched && ::access(path.c_str(), F_OK) != 0) {
      last = path + ": no such file";
    } else if (void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL); handle == nullptr) {
      const char* reason = ::dlerror();
      last = reason != nullptr ? reason : path + ": dlopen failed";
      if (firstReal.empty() && !searched) firstReal = last;
    } else if (accept(handle, path, last)) {
      return handle;
    } else {
      ::dlclose(handle);
      if (firstReal.empty() && !searched) firstReal = last;
    }
    tried += (tried.empty() ? "" : ", ") + (searched ? path + " on the loader path" : path);
  }
  throw InputError(at.name + ": cannot load " + what + ": " +
                   (firstReal.empty() ? last : firstReal) + " (tried " + tried + "; set " + at.env +
                   " to its path)");
}

}  // namespace osteon
