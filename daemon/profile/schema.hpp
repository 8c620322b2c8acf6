// The profile schema: every key a profile may hold, declared once (schema.cpp) with its type,
// default, bounds, unit and a line of documentation, Redis-style. Loading, validation,
// `ballastd --dump-schema` and the ballast-profile(5) man page all read this one table.
//
// Keys are "section.name". Numbers with unit "rad" also accept "<x>deg". Lists may have a fixed
// length. Maps (name -> number, name -> list of names) merge entry by entry across `extends`.
// A key marked restart cannot change under a running daemon: `ballast profile use` and SIGHUP
// refuse a profile that changes it.
//
// To add a key: one row in the table in schema.cpp, then regenerate the man page
// (`build/bin/ballastd --dump-schema=man > man/ballast-profile.5`; a test compares them).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace ballast::profile {

enum class KeyType {
  kBool,
  kInt,
  kNumber,
  kString,
  kEnum,  ///< one of the '|'-separated choices in `unit`
  kPath,  ///< a file; relative paths are relative to the profile file that sets it
  kNumberList,
  kIntList,
  kStringList,
  kPathList,
  kNumberMap,  ///< name -> number (joint -> angle, joint group -> gain)
  kGroupMap,   ///< name -> list of names (joint groups)
  kSection,    ///< a map whose keys another component validates (a backend's own section)
};

/// "bool", "integer", "number", ...: the names messages and the man page use.
const char* typeName(KeyType type);

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

struct Key {
  const char* name;  ///< "section.key"
  KeyType type;
  const char* fallback;  ///< the default, as YAML text
  double min, max;       ///< bounds of every number in the value (elements of lists and maps)
  const char* unit;      ///< numbers: unit; enums: the choices "a|b"
  const char* doc;       ///< one line
  int length = 0;        ///< lists: exact number of elements (0: any)
  bool restart = false;  ///< cannot change on a running daemon

  constexpr Key needsRestart() const {
    Key k = *this;
    k.restart = true;
    return k;
  }
  constexpr Key ofLength(int n) const {
    Key k = *this;
    k.length = n;
    return k;
  }
  bool isMap() const { return type == KeyType::kNumberMap || type == KeyType::kGroupMap; }
};

/// The whole table, in documentation order.
const std::vector<Key>& schema();
/// The key of that name, nullptr if none. "backend.<name>" (the backend's own section) is not
/// in the table under that name: see isBackendSection.
const Key* findKey(const std::string& name);
/// True for "backend.X" where X is not a declared backend key: a backend's own section.
bool isBackendSection(const std::string& name);
/// True if some key starts with name + "." (name is a section).
bool isSection(const std::string& name);
/// The declared key closest to name (for "did you mean ...?"), "" if none is close.
std::string closestKey(const std::string& name);

/// ballast-profile(5), generated from the table (troff).
std::string schemaManPage();
/// Every key with its default and doc, as a commented YAML profile.
std::string schemaYaml();

}  // namespace ballast::profile
