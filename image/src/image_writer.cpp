// The loader of libosteon_image.so (see image_writer.h for why and where it is looked for).
#include "osteon/image/image_writer.h"

#include <array>
#include <cstdlib>
#include <dlfcn.h>
#include <mutex>
#include <unistd.h>
#include <vector>

#include "osteon/core/error.h"
#include "osteon/core/plugin_loader.h"
#include "plugin_abi.h"

namespace osteon::image {

namespace {

struct Plugin {
  std::string path;  // empty until loaded
  osteon_image_library_version_fn libraryVersion = nullptr;
  osteon_image_write_u8_fn writeU8 = nullptr;
};

// Checks a loaded candidate: its symbols and its interface version.
bool accept(void* handle, const std::string& path, Plugin& plugin, std::string& error) {
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
  return false;
}

std::mutex gMutex;
Plugin gPlugin;

// The loaded plugin, loading it on first use. Throws InputError naming what was tried.
const Plugin& plugin() {
  const std::lock_guard<std::mutex> lock(gMutex);
  if (!gPlugin.path.empty()) return gPlugin;
  const PluginPlaces places{"OSTEON_IMAGE_PLUGIN", OSTEON_IMAGE_PLUGIN_NAME, OSTEON_IMAGE_BUILD_DIR,
                            OSTEON_IMAGE_INSTALL_RELATIVE_LIBDIR, OSTEON_IMAGE_INSTALL_LIBDIR};
  loadPlugin(places, "osteon's image plugin (OpenImageIO), needed to write images",
             [](void* handle, const std::string& path, std::string& error) {
               return accept(handle, path, gPlugin, error);
             });
  return gPlugin;
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
