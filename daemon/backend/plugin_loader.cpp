#include "backend/plugin_loader.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

namespace ballast::backend {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, sep);)
    if (!part.empty()) out.push_back(part);
  return out;
}

std::string dlerrorText() {
  const char* e = dlerror();
  return e ? e : "no dlerror() message";
}

}  // namespace

namespace {
constexpr const char* kFilePrefix = "libballast_backend_";
constexpr const char* kFileSuffix = ".so";
}  // namespace

std::string pluginFileName(const std::string& name) { return kFilePrefix + name + kFileSuffix; }

std::vector<std::string> defaultPluginDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("BALLAST_PLUGIN_PATH")) dirs = split(env, ':');
  // Next to the running program first, so an installed tree moved elsewhere (or installed
  // with another prefix or DESTDIR) loads its own plugins, not the build tree's.
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    const std::string program(exe, static_cast<std::size_t>(n));
    const std::string dir =
        program.substr(0, program.rfind('/')) + "/" + BALLAST_PLUGIN_DIR_FROM_BINDIR;
    char canonical[PATH_MAX];
    dirs.push_back(realpath(dir.c_str(), canonical) ? std::string(canonical) : dir);
  }
  dirs.push_back(BALLAST_BUILD_PLUGIN_DIR);
  dirs.push_back(BALLAST_INSTALL_PLUGIN_DIR);
  return dirs;
}

std::vector<std::string> availablePlugins() {
  const std::string prefix = kFilePrefix, suffix = kFileSuffix;
  std::set<std::string> names;
  for (const std::string& dir : defaultPluginDirs()) {
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
      const std::string file = entry.path().filename().string();
      if (file.size() > prefix.size() + suffix.size() && file.rfind(prefix, 0) == 0 &&
          file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0)
        names.insert(file.substr(prefix.size(), file.size() - prefix.size() - suffix.size()));
    }
  }
  return {names.begin(), names.end()};
}

std::shared_ptr<Plugin> Plugin::load(const std::string& nameOrPath,
                                     const std::vector<std::string>& extraDirs) {
  std::string path;
  if (nameOrPath.find('/') != std::string::npos) {
    path = nameOrPath;
    if (access(path.c_str(), R_OK) != 0)
      throw PluginError("backend plugin " + path + ": no such readable file");
  } else {
    std::vector<std::string> dirs = extraDirs;
    for (const auto& d : defaultPluginDirs()) dirs.push_back(d);
    const std::string file = pluginFileName(nameOrPath);
    std::string searched;
    for (const auto& d : dirs) {
      const std::string candidate = d + "/" + file;
      if (access(candidate.c_str(), R_OK) == 0) {
        path = candidate;
        break;
      }
      searched += (searched.empty() ? "" : ", ") + d;
    }
    if (path.empty())
      throw PluginError("backend '" + nameOrPath + "': no " + file + " in " + searched +
                        " (add its directory to the profile's plugin directories or to BALLAST_PLUGIN_PATH)");
  }

  dlerror();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle)
    throw PluginError("backend plugin " + path + ": cannot load it: " + dlerrorText());
  dlerror();
  auto fn = reinterpret_cast<BallastBackendEntryFn>(dlsym(handle, kBackendEntrySymbol));
  if (!fn) {
    const std::string why = dlerrorText();
    dlclose(handle);
    throw PluginError("backend plugin " + path + ": not a ballast backend: no symbol '" +
                      kBackendEntrySymbol + "' (" + why + ")");
  }
  const BackendEntry* entry = fn();
  if (!entry || entry->abi_version != kBackendAbiVersion) {
    const std::string got = entry ? std::to_string(entry->abi_version) : "none";
    dlclose(handle);
    throw PluginError("backend plugin " + path + ": built for backend ABI version " + got +
                      ", this ballastd speaks version " + std::to_string(kBackendAbiVersion) +
                      ": rebuild the plugin against this tree's plugins/backend_abi.hpp");
  }
  if (!entry->create || !entry->destroy) {
    dlclose(handle);
    throw PluginError("backend plugin " + path + ": its entry has no create/destroy function");
  }
  return std::shared_ptr<Plugin>(new Plugin(handle, entry, path));
}

Plugin::~Plugin() {
  if (handle_) dlclose(handle_);
}

BackendPtr Plugin::create() const {
  return BackendPtr(entry_->create(), BackendDeleter{entry_->destroy});
}

}  // namespace ballast::backend
