// A backend plugin's profile section, declared as a table and parsed in one place.
//
// Each plugin declares every key it accepts once, in a table of SettingKey<S> (name, type,
// default, bounds or choices, documentation group, one line of doc, the field of its settings
// struct S), and parses its section with parseSection(). The daemon hands a plugin its section
// as YAML text with Config::section_origin = "file:line" where it starts; errors read
//     file:line:column: key: what is wrong
// with line = origin line + the YAML node's 0-based line and column = the node's column + 1.
// Unknown keys (with a "did you mean" for typos), keys given twice, wrong types and
// out-of-range values are errors; defaults go through the same code (so they obey the bounds).
// A key of type kCustom is parsed by its own function, with a SectionCursor for locations,
// bounds and messages (a plugin's per-joint motor entries, say).
//
// Plugins see only the backend ABI; this library is theirs, not the daemon's.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace ballast::plugin {

using Vec3d = std::array<double, 3>;
using NamedNumbers = std::map<std::string, double>;  ///< e.g. joint name -> angle

enum class KeyType {
  kNumber,
  kInteger,
  kBool,
  kString,
  kChoice,        ///< one of "a|b|c"
  kVec2,          ///< stored in a Vec3d (third element 0)
  kVec3,
  kNamedNumbers,  ///< a map name -> number, each within [min, max]
  kStrings,       ///< a list of strings
  kCustom,        ///< parsed by the key's own function
};
const char* typeName(KeyType type);

struct SettingsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Where each key of a section was given: settings structs derive from it.
struct SectionLocations {
  /// "file:line:column" of each key given in the section (entries of maps and custom keys as
  /// "key.entry"). For messages found after parsing.
  std::map<std::string, std::string> location;
  std::string origin;  ///< the section's "file:line"

  /// "file:line:column: key: " for a message about key (its location, else the section's).
  std::string where(const std::string& key) const;
};

/// Locations, bounds and messages while a section is parsed.
class SectionCursor {
 public:
  SectionCursor(const std::string& origin, SectionLocations& out);
  /// The default values' cursor: messages say "<built-in default>".
  static SectionCursor forDefaults(SectionLocations& out);

  std::string at(const YAML::Mark& mark) const;
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& what) const;
  /// A number within [min, max], else a message naming `key`.
  double number(const YAML::Node& node, double min, double max, const std::string& key) const;
  /// An integer within [min, max].
  long long integer(const YAML::Node& node, double min, double max, const std::string& key) const;
  std::string text(const YAML::Node& node, const std::string& key) const;
  /// Notes where `key` was written (for SectionLocations::where).
  void record(const std::string& key, const YAML::Mark& mark) const;
  /// A map node's keys must be among `allowed` (dotted under `key`), with a suggestion if not.
  void checkKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
                 const std::string& key) const;

  static std::string describe(const YAML::Node& node);
  static std::string formatNumber(double v);

 private:
  SectionCursor(std::string file, int line, bool hasLine, SectionLocations& out);
  std::string file_;
  int line_ = 1;
  bool hasLine_ = false;
  SectionLocations& out_;
};

/// The closest of `names` to `name` (a typo: edit distance ≤ 3), or "".
std::string closest(const std::string& name, const std::vector<std::string>& names);

template <class S>
using SettingField = std::variant<double S::*, int S::*, bool S::*, std::string S::*, Vec3d S::*,
                                  NamedNumbers S::*, std::vector<std::string> S::*>;

template <class S>
struct SettingKey {
  const char* name;         ///< dotted path in the section, e.g. "imu.gyro_bias"
  KeyType type;
  const char* defaultYaml;  ///< the default, as YAML (parsed by the same code as the profile)
  double min, max;          ///< numbers, integers, vector elements, named numbers
  const char* choices;      ///< kChoice: "a|b|c"
  const char* group;        ///< heading in the documentation
  const char* doc;
  SettingField<S> field;    ///< unused for kCustom
  void (*custom)(S&, const YAML::Node&, const SectionCursor&) = nullptr;
};

namespace detail {

template <class S>
const SettingKey<S>* findKey(const std::vector<SettingKey<S>>& keys, const std::string& name) {
  for (const auto& k : keys)
    if (name == k.name) return &k;
  return nullptr;
}

template <class S>
bool isGroup(const std::vector<SettingKey<S>>& keys, const std::string& name) {
  const std::string prefix = name + ".";
  return std::any_of(keys.begin(), keys.end(), [&](const SettingKey<S>& k) {
    return std::string(k.name).compare(0, prefix.size(), prefix) == 0;
  });
}

template <class S>
void assign(const SettingKey<S>& key, const YAML::Node& node, const YAML::Mark& mark,
            const std::string& name, const SectionCursor& c, S& out) {
  switch (key.type) {
    case KeyType::kNumber:
      out.*std::get<double S::*>(key.field) = c.number(node, key.min, key.max, name);
      return;
    case KeyType::kInteger:
      out.*std::get<int S::*>(key.field) = static_cast<int>(c.integer(node, key.min, key.max, name));
      return;
    case KeyType::kBool: {
      bool v = false;
      if (!node.IsScalar() || !YAML::convert<bool>::decode(node, v))
        c.fail(mark, name, "expected true or false, got " + SectionCursor::describe(node));
      out.*std::get<bool S::*>(key.field) = v;
      return;
    }
    case KeyType::kString:
      out.*std::get<std::string S::*>(key.field) = c.text(node, name);
      return;
    case KeyType::kChoice: {
      const std::string v = node.IsScalar() ? node.Scalar() : "";
      std::stringstream choices(key.choices);
      for (std::string choice; std::getline(choices, choice, '|');)
        if (choice == v) {
          out.*std::get<std::string S::*>(key.field) = v;
          return;
        }
      c.fail(mark, name,
             "expected one of " + std::string(key.choices) + ", got " + SectionCursor::describe(node));
    }
    case KeyType::kVec2:
    case KeyType::kVec3: {
      const std::size_t n = key.type == KeyType::kVec2 ? 2 : 3;
      if (!node.IsSequence() || node.size() != n)
        c.fail(mark, name, "expected a list of " + std::to_string(n) + " numbers, got " +
                               SectionCursor::describe(node));
      Vec3d v{0, 0, 0};
      for (std::size_t i = 0; i < n; ++i)
        v[i] = c.number(node[i], key.min, key.max, name + "[" + std::to_string(i) + "]");
      out.*std::get<Vec3d S::*>(key.field) = v;
      return;
    }
    case KeyType::kNamedNumbers: {
      if (!node.IsMap() && !node.IsNull())
        c.fail(mark, name, "expected a map of name: number, got " + SectionCursor::describe(node));
      NamedNumbers values;
      for (const auto& e : node) {
        const std::string entry = name + "." + e.first.Scalar();
        values[e.first.Scalar()] = c.number(e.second, key.min, key.max, entry);
        c.record(entry, e.first.Mark());
      }
      out.*std::get<NamedNumbers S::*>(key.field) = values;
      return;
    }
    case KeyType::kStrings: {
      if (!node.IsSequence())
        c.fail(mark, name, "expected a list of strings, got " + SectionCursor::describe(node));
      std::vector<std::string> values;
      for (std::size_t i = 0; i < node.size(); ++i)
        values.push_back(c.text(node[i], name + "[" + std::to_string(i) + "]"));
      out.*std::get<std::vector<std::string> S::*>(key.field) = values;
      return;
    }
    case KeyType::kCustom:
      key.custom(out, node, c);
      return;
  }
}

template <class S>
void walk(const std::vector<SettingKey<S>>& keys, const YAML::Node& map, const std::string& prefix,
          const SectionCursor& c, S& out) {
  for (const auto& entry : map) {
    const YAML::Node& keyNode = entry.first;
    const std::string name = prefix + keyNode.Scalar();
    if (const SettingKey<S>* key = findKey(keys, name)) {
      const auto before = out.location.find(name);
      if (before != out.location.end())
        c.fail(keyNode.Mark(), name, "given twice (first at " + before->second + ")");
      c.record(name, keyNode.Mark());
      assign(*key, entry.second, entry.second.Mark(), name, c, out);
      continue;
    }
    if (isGroup(keys, name)) {
      if (!entry.second.IsMap() && !entry.second.IsNull())
        c.fail(entry.second.Mark(), name, "expected a map of " + name + ".* keys");
      if (entry.second.IsMap()) walk(keys, entry.second, name + ".", c, out);
      continue;
    }
    std::vector<std::string> names;
    for (const auto& k : keys) names.push_back(k.name);
    const std::string best = closest(name, names);
    c.fail(keyNode.Mark(), name,
           "unknown key" + (best.empty() ? std::string() : " (did you mean " + best + "?)"));
  }
}

}  // namespace detail

/// Parses and validates a section (`what` names it in messages, e.g. "the simbody backend
/// section"); throws SettingsError "file:line:column: key: what is wrong".
template <class S>
S parseSection(const std::vector<SettingKey<S>>& keys, const std::string& yaml,
               const std::string& origin, const std::string& what) {
  S s;
  // Defaults first, through the same code as the profile (so they obey the bounds too).
  const SectionCursor defaults = SectionCursor::forDefaults(s);
  for (const auto& key : keys)
    detail::assign(key, YAML::Load(key.defaultYaml), YAML::Mark::null_mark(), key.name, defaults, s);
  s.location.clear();
  s.origin = origin;
  const SectionCursor cursor(origin, s);
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw SettingsError(cursor.at(e.mark) + ": " + e.msg);
  }
  if (root.IsNull()) return s;
  if (!root.IsMap()) throw SettingsError(cursor.at(root.Mark()) + ": " + what + " must be a map of keys");
  detail::walk(keys, root, "", cursor, s);
  return s;
}

/// The key reference as text: per group, one line per key (name, type, default, bounds, doc).
template <class S>
std::string sectionReference(const std::vector<SettingKey<S>>& keys) {
  std::string out, group;
  char line[640];
  for (const auto& k : keys) {
    if (group != k.group) {
      group = k.group;
      out += "\n" + group + "\n";
    }
    std::string bounds;
    if (k.type == KeyType::kChoice)
      bounds = k.choices;
    else if (k.type != KeyType::kBool && k.type != KeyType::kString &&
             k.type != KeyType::kStrings && k.type != KeyType::kCustom)
      bounds = "[" + SectionCursor::formatNumber(k.min) + ", " + SectionCursor::formatNumber(k.max) + "]";
    std::snprintf(line, sizeof line, "%-29s %-7s %-14s %-14s %s\n", k.name, typeName(k.type),
                  k.defaultYaml, bounds.c_str(), k.doc);
    out += line;
  }
  return out;
}

}  // namespace ballast::plugin
