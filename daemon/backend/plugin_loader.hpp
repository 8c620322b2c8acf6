// Loading backend plugins (plugins/backend_abi.hpp) by name or path.
//
// A name like "simbody" is looked up as libballast_backend_simbody.so in, in order: the
// directories the profile gives, $BALLAST_PLUGIN_PATH (colon-separated), the build tree's plugin
// directory and the install tree's. A name containing '/' is a path. Every failure raises
// PluginError naming what was searched, the symbol and dlerror(): no such file, not a shared
// library, not a ballast backend (no entry symbol), another ABI version.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_abi.hpp"

namespace ballast::backend {

struct PluginError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Destroys a Backend through its plugin's destroy().
struct BackendDeleter {
  void (*destroy)(Backend*) = nullptr;
  void operator()(Backend* b) const {
    if (b && destroy) destroy(b);
  }
};
using BackendPtr = std::unique_ptr<Backend, BackendDeleter>;

class Plugin {
 public:
  /// Loads the plugin; throws PluginError.
  static std::shared_ptr<Plugin> load(const std::string& nameOrPath,
                                      const std::vector<std::string>& extraDirs = {});
  ~Plugin();
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  const BackendEntry& entry() const { return *entry_; }
  const std::string& path() const { return path_; }
  /// A new backend instance. Keep the Plugin alive while it exists.
  BackendPtr create() const;

 private:
  Plugin(void* handle, const BackendEntry* entry, std::string path)
      : handle_(handle), entry_(entry), path_(std::move(path)) {}
  void* handle_;
  const BackendEntry* entry_;
  std::string path_;
};

/// Where plugins are looked up after the profile's directories.
std::vector<std::string> defaultPluginDirs();
/// The names of the plugins found there (libballast_backend_<name>.so), sorted, each once.
std::vector<std::string> availablePlugins();
/// libballast_backend_<name>.so
std::string pluginFileName(const std::string& name);

}  // namespace ballast::backend
