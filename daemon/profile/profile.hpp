// Profiles: loading a YAML file and its `extends:` chain, checking every key against the
// schema (schema.hpp), and typed access to the merged result.
//
// Errors name the place: "file:line:column: key: what is wrong", one line per problem, all
// problems of a file at once. Load refuses the whole profile on any of them (ProfileError);
// the caller decides what that means (ballastd refuses to start; a switch at run time keeps
// the running profile).
//
// The daemon reads a profile through its settings (settings.hpp: the schema fills them). The
// getters below, for tests and tools, take a key declared in the schema and of the matching
// type; anything else is a programming error (std::logic_error).
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "profile/schema.hpp"

namespace ballast::profile {

struct ProfileError : std::runtime_error {
  explicit ProfileError(std::vector<std::string> problems);
  std::vector<std::string> problems;
};

/// Where a value came from: a file and a 1-based line and column, or the schema default.
struct Origin {
  std::string file;  ///< "" for a default
  int line = 0, column = 0;
  /// "file:line:column", or "default".
  std::string str() const;
};

class Profile {
 public:
  /// Loads a profile file. `search_dirs` are where `extends: NAME` looks after the file's own
  /// directory. Throws ProfileError.
  static Profile load(const std::string& path, const std::vector<std::string>& search_dirs = {});

  /// The file's base name without .yaml (e.g. "sim-flat").
  const std::string& name() const { return name_; }
  /// The file as given (made absolute).
  const std::string& path() const { return path_; }
  /// The files read, the profile first, then its bases.
  const std::vector<std::string>& files() const { return files_; }

  bool flag(const std::string& key) const;
  long long integer(const std::string& key) const;
  double number(const std::string& key) const;
  /// Strings, choices and paths (paths resolved against the file that set them).
  std::string text(const std::string& key) const;
  std::vector<double> numbers(const std::string& key) const;
  std::vector<long long> integers(const std::string& key) const;
  /// Lists of strings or paths.
  std::vector<std::string> strings(const std::string& key) const;
  std::map<std::string, double> numberMap(const std::string& key) const;
  std::map<std::string, std::vector<std::string>> groupMap(const std::string& key) const;

  /// The merged value of a declared key, as YAML (a map key's entries gathered in one map).
  YAML::Node value(const std::string& key) const;

  Origin origin(const std::string& key) const;
  /// Origin of one entry of a map key.
  Origin origin(const std::string& key, const std::string& entry) const;

  /// The backend's own section (backend.<backend.name>) for the plugin: YAML text ("{}" if
  /// absent) and "file:line" such that a node on line n (0-based) of the text is on line
  /// origin + n of that file. When one file defines the whole section the text is that file's
  /// own lines, so the plugin's messages point at the right place; a section merged from
  /// several files is re-emitted (locateBackendProblem then fixes the plugin's messages).
  struct BackendSection {
    std::string yaml, origin;
  };
  BackendSection backendSection() const;
  /// A plugin message "…: key: what" rewritten to start with key's own file:line:column, when
  /// key is one of the section's (dotted) keys; otherwise the message unchanged.
  std::string locateBackendProblem(const std::string& message) const;

  /// The merged profile as YAML, every value commented with its origin (`ballast profile show`).
  std::string describe() const;
  /// Keys marked restart whose values differ between two profiles.
  static std::vector<std::string> restartChanges(const Profile& running, const Profile& next);

  /// "file:line:column: key: message" for a key's origin (semantic checks outside this file).
  std::string problem(const std::string& key, const std::string& message) const;
  std::string problem(const std::string& key, const std::string& entry,
                      const std::string& message) const;
  /// The same at element `index` of a list key ("key[index]"), at that element's own place.
  std::string problemAtElement(const std::string& key, std::size_t index,
                               const std::string& message) const;

  struct Setting {
    YAML::Node node;
    Origin origin;
  };

 private:
  friend class Loader;
  const Setting& leaf(const std::string& key, std::initializer_list<KeyType> types) const;
  const std::map<std::string, Setting>& entries(const std::string& key, KeyType type) const;

  std::string name_, path_;
  std::vector<std::string> files_;
  std::map<std::string, Setting> leaves_;                       // plain keys
  std::map<std::string, std::map<std::string, Setting>> maps_;  // map keys and sections
  std::map<std::string, Origin> section_origins_;               // backend sections
  std::map<std::string, BackendSection> section_text_;          // ... verbatim, if block style
};

/// Where `profile use NAME` and `extends: NAME` look: $BALLAST_PROFILE_PATH (colon-separated),
/// the source tree's profiles/ and the installed share/ballast/profiles.
std::vector<std::string> defaultProfileDirs();
/// NAME (no '/') -> first dir/NAME.yaml that exists; a path is returned as is. Throws
/// ProfileError naming the directories searched.
std::string resolveProfile(const std::string& name_or_path, const std::vector<std::string>& dirs);

}  // namespace ballast::profile
