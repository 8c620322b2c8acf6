#include "settings_schema.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "closest_name.hpp"
#include "format.hpp"

namespace ballast::schema {

const char* typeName(Type type) {
  switch (type) {
    case Type::kBool: return "bool";
    case Type::kInteger: return "integer";
    case Type::kNumber: return "number";
    case Type::kString: return "string";
    case Type::kChoice: return "choice";
    case Type::kPath: return "path";
    case Type::kNumbers: return "list of numbers";
    case Type::kIntegers: return "list of integers";
    case Type::kStrings: return "list of strings";
    case Type::kPaths: return "list of paths";
    case Type::kNumberMap: return "map of numbers";
    case Type::kGroupMap: return "map of lists of names";
    case Type::kCustom: return "map";
    case Type::kFrame: return "frame";
    case Type::kFrames: return "list of frames";
  }
  return "?";
}

bool Key::isNumeric() const {
  return type == Type::kInteger || type == Type::kNumber || type == Type::kNumbers ||
         type == Type::kIntegers || type == Type::kNumberMap;
}

std::string Key::section() const {
  const std::string n = name;
  const auto dot = n.find('.');
  return dot == std::string::npos ? "" : n.substr(0, dot);
}

std::string Key::bounds() const {
  if (type == Type::kChoice) return std::string("one of ") + unit;
  if (!isNumeric()) return "";
  std::string b = "[" + formatNumber(min) + ", " + formatNumber(max) + "]";
  if (*unit) b += std::string(" ") + unit;
  return b;
}

std::string Key::shortType() const {
  switch (type) {
    case Type::kNumbers:
      return length == 2 || length == 3 ? "vec" + std::to_string(length) : "numbers";
    case Type::kIntegers: return "integers";
    case Type::kStrings: return "strings";
    case Type::kPaths: return "paths";
    case Type::kFrames: return "frames";
    case Type::kNumberMap:
    case Type::kGroupMap:
    case Type::kCustom: return "map";
    default: return typeName(type);
  }
}

bool FrameRef::placed() const {
  return offset != std::array<double, 3>{} || rpy != std::array<double, 3>{};
}

std::string FrameRef::frameName(const std::string& role) const {
  return placed() ? role + "@" + link : link;
}

std::string describe(const YAML::Node& node) {
  if (!node || node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list of " + std::to_string(node.size());
  if (node.IsMap()) return "a map";
  return "'" + node.Scalar() + "'";
}

std::string closest(const std::string& name, const std::vector<std::string>& candidates) {
  return closestName(name, candidates, [](const std::string& n) { return n; });
}

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

bool isAngle(const Key& k) { return std::string(k.unit) == "rad"; }

bool fail(Problem& p, const YAML::Mark& mark, std::string key, std::string what) {
  p.mark = mark;
  p.key = std::move(key);
  p.what = std::move(what);
  return false;
}

/// One number of key k: an integer (decimal or 0x hexadecimal) or a real (with "deg" on an
/// angle), within the key's bounds.
bool readNumber(const Key& k, const YAML::Node& node, bool integer, const std::string& name,
                double& out, Problem& p) {
  const std::string expected = integer ? "expected an integer" : "expected a number";
  if (!node.IsScalar()) return fail(p, node.Mark(), name, expected + ", got " + describe(node));
  std::string s = node.Scalar();
  double scale = 1.0;
  if (isAngle(k) && s.size() > 3 && s.compare(s.size() - 3, 3, "deg") == 0) {
    s.resize(s.size() - 3);
    scale = kDegree;
  }
  bool ok = false;
  double v = 0.0;
  if (integer && s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X') &&
      s.find_first_not_of("0123456789abcdefABCDEF", 2) == std::string::npos && s.size() <= 18) {
    v = static_cast<double>(std::strtoll(s.c_str() + 2, nullptr, 16));
    ok = true;
  } else if (integer && !s.empty() &&
             s.find_first_not_of("0123456789", s[0] == '-' || s[0] == '+' ? 1 : 0) ==
                 std::string::npos &&
             s.size() > (s[0] == '-' || s[0] == '+' ? 1u : 0u)) {
    errno = 0;
    v = static_cast<double>(std::strtoll(s.c_str(), nullptr, 10));
    ok = errno != ERANGE;
  } else {
    ok = !s.empty() && YAML::convert<double>::decode(YAML::Node(s), v);
    if (ok && integer && std::isfinite(v) && v != std::floor(v))
      return fail(p, node.Mark(), name, expected + ", got '" + node.Scalar() + "'");
  }
  if (!ok)
    return fail(p, node.Mark(), name,
                expected + (isAngle(k) ? " (rad, or with a deg suffix)" : "") + ", got '" +
                    node.Scalar() + "'");
  v *= scale;
  if (!(v >= k.min && v <= k.max) || std::isinf(v))
    return fail(p, node.Mark(), name,
                node.Scalar() + " is out of range [" + formatNumber(k.min) + ", " +
                    formatNumber(k.max) + "]" + (*k.unit ? std::string(" ") + k.unit : ""));
  out = v;
  return true;
}

bool readText(const YAML::Node& node, const std::string& name, std::string& out, Problem& p) {
  if (node.IsNull()) {
    out.clear();
    return true;
  }
  if (!node.IsScalar()) return fail(p, node.Mark(), name, "expected a string, got " + describe(node));
  out = node.Scalar();
  return true;
}

const char* elementWord(Type t) {
  switch (t) {
    case Type::kNumbers: return "numbers";
    case Type::kIntegers: return "integers";
    case Type::kPaths: return "paths";
    default: return "strings";
  }
}

/// One frame: a link name, or a map {link, offset[, rpy]} (rpy only if the key says "rpy").
bool readFrame(const Key& k, const YAML::Node& node, const std::string& name, FrameRef& out,
               Problem& p) {
  const bool oriented = std::string(k.unit) == "rpy";
  const std::string expected = std::string("expected a URDF link name or {link: NAME, offset: [x, y, z]") +
                               (oriented ? ", rpy: [r, p, y]}" : "}");
  out = FrameRef{};
  if (node.IsScalar()) {
    if (node.Scalar().empty()) return fail(p, node.Mark(), name, expected + ", got ''");
    out.link = node.Scalar();
    return true;
  }
  if (!node.IsMap()) return fail(p, node.Mark(), name, expected + ", got " + describe(node));
  bool hasLink = false;
  for (const auto& e : node) {
    const std::string field = e.first.IsScalar() ? e.first.Scalar() : "";
    const std::string at = name + "." + field;
    if (field == "link") {
      if (!e.second.IsScalar() || e.second.Scalar().empty())
        return fail(p, e.second.Mark(), at, "expected a URDF link name, got " + describe(e.second));
      out.link = e.second.Scalar();
      hasLink = true;
    } else if (field == "offset" || (field == "rpy" && oriented)) {
      std::array<double, 3>& v = field == "offset" ? out.offset : out.rpy;
      if (!e.second.IsSequence() || e.second.size() != 3)
        return fail(p, e.second.Mark(), at, "expected a list of 3 numbers, got " + describe(e.second));
      Key element{};
      element.type = Type::kNumber;
      element.unit = field == "rpy" ? "rad" : "m";
      for (std::size_t i = 0; i < 3; ++i)
        if (!readNumber(element, e.second[i], false, at + "[" + std::to_string(i) + "]", v[i], p))
          return false;
    } else {
      return fail(p, e.first.Mark(), at,
                  std::string("unknown field: a frame has link, offset") + (oriented ? ", rpy" : "") +
                      (field == "rpy" ? " (a contact point is a point: no rpy)" : ""));
    }
  }
  if (!hasLink) return fail(p, node.Mark(), name, "a frame needs its link: {link: NAME, offset: [x, y, z]}");
  return true;
}

}  // namespace

bool readEntry(const Key& k, const std::string& entry, const YAML::Node& node, Value& out,
               Problem& p) {
  const std::string name = std::string(k.name) + "." + entry;
  if (k.type == Type::kNumberMap) {
    double x = 0.0;
    if (!readNumber(k, node, false, name, x, p)) return false;
    out.numberMap[entry] = x;
    return true;
  }
  if (!node.IsSequence()) return fail(p, node.Mark(), name, "expected a list of names, got " + describe(node));
  std::vector<std::string> names;
  for (std::size_t i = 0; i < node.size(); ++i) {
    std::string s;
    if (!readText(node[i], name + "[" + std::to_string(i) + "]", s, p)) return false;
    names.push_back(s);
  }
  out.groupMap[entry] = names;
  return true;
}

bool read(const Key& k, const YAML::Node& node, Value& out, Problem& p) {
  const std::string name = k.name;
  switch (k.type) {
    case Type::kBool:
      if (!node.IsScalar() || !YAML::convert<bool>::decode(node, out.flag))
        return fail(p, node.Mark(), name, "expected true or false, got " + describe(node));
      return true;
    case Type::kInteger: {
      double x = 0.0;
      if (!readNumber(k, node, true, name, x, p)) return false;
      out.integer = static_cast<long long>(x);
      return true;
    }
    case Type::kNumber:
      return readNumber(k, node, false, name, out.number, p);
    case Type::kString:
    case Type::kPath:
      return readText(node, name, out.text, p);
    case Type::kChoice: {
      if (node.IsScalar()) {
        std::stringstream choices(k.unit);
        int i = 0;
        for (std::string c; std::getline(choices, c, '|'); ++i)
          if (c == node.Scalar()) {
            out.text = c;
            out.choice = i;
            return true;
          }
      }
      return fail(p, node.Mark(), name,
                  std::string("expected one of ") + k.unit + ", got " + describe(node));
    }
    case Type::kNumbers:
    case Type::kIntegers:
    case Type::kStrings:
    case Type::kPaths: {
      const std::string what = elementWord(k.type);
      if (!node.IsSequence())
        return fail(p, node.Mark(), name, "expected a list of " + what + ", got " + describe(node));
      if (k.length && static_cast<int>(node.size()) != k.length)
        return fail(p, node.Mark(), name,
                    "expected a list of " + std::to_string(k.length) + " " + what + ", got " +
                        describe(node));
      out.numbers.clear();
      out.integers.clear();
      out.strings.clear();
      for (std::size_t i = 0; i < node.size(); ++i) {
        const std::string element = name + "[" + std::to_string(i) + "]";
        if (k.type == Type::kNumbers || k.type == Type::kIntegers) {
          double x = 0.0;
          if (!readNumber(k, node[i], k.type == Type::kIntegers, element, x, p)) return false;
          out.numbers.push_back(x);
          out.integers.push_back(static_cast<long long>(x));
        } else {
          std::string s;
          if (!node[i].IsScalar())
            return fail(p, node[i].Mark(), element, "expected a string, got " + describe(node[i]));
          out.strings.push_back(node[i].Scalar());
        }
      }
      return true;
    }
    case Type::kNumberMap:
    case Type::kGroupMap: {
      out.numberMap.clear();
      out.groupMap.clear();
      if (node.IsNull()) return true;
      if (!node.IsMap())
        return fail(p, node.Mark(), name,
                    std::string("expected a map of name: ") +
                        (k.type == Type::kNumberMap ? "number" : "[names]") + ", got " +
                        describe(node));
      std::map<std::string, YAML::Mark> seen;
      for (const auto& e : node) {
        if (!e.first.IsScalar())
          return fail(p, e.first.Mark(), name, "keys must be names, got " + describe(e.first));
        const std::string entry = e.first.Scalar();
        if (const auto before = seen.find(entry); before != seen.end()) {
          fail(p, e.first.Mark(), name + "." + entry, "given twice");
          p.first = before->second;
          return false;
        }
        seen.emplace(entry, e.first.Mark());
        if (!readEntry(k, entry, e.second, out, p)) return false;
      }
      return true;
    }
    case Type::kFrame:
      out.frames.assign(1, FrameRef{});
      return readFrame(k, node, name, out.frames[0], p);
    case Type::kFrames: {
      if (!node.IsSequence())
        return fail(p, node.Mark(), name, "expected a list of frames, got " + describe(node));
      if (k.length && static_cast<int>(node.size()) != k.length)
        return fail(p, node.Mark(), name,
                    "expected a list of " + std::to_string(k.length) + " frames, got " + describe(node));
      out.frames.assign(node.size(), FrameRef{});
      for (std::size_t i = 0; i < node.size(); ++i)
        if (!readFrame(k, node[i], name + "[" + std::to_string(i) + "]", out.frames[i], p)) return false;
      return true;
    }
    case Type::kCustom:
      break;
  }
  return fail(p, node.Mark(), name, "read by its own function");
}

// ---- locations

std::string Locations::where(const std::string& key) const {
  const auto it = location.find(key);
  const std::string at =
      it != location.end() ? it->second : (origin.empty() ? "<backend section>" : origin);
  return at + ": " + key + ": ";
}

Cursor::Cursor(const std::string& origin, Locations* out) : out_(out) {
  file_ = origin.empty() ? "<backend section>" : origin;
  const auto colon = origin.rfind(':');
  if (colon != std::string::npos && colon + 1 < origin.size() &&
      std::all_of(origin.begin() + static_cast<long>(colon) + 1, origin.end(),
                  [](char c) { return c >= '0' && c <= '9'; })) {
    file_ = origin.substr(0, colon);
    line_ = std::stoi(origin.substr(colon + 1));
    hasLine_ = true;
  }
}

std::string Cursor::at(const YAML::Mark& mark) const {
  if (mark.is_null()) return file_ + ":" + std::to_string(line_);
  return file_ + ":" + std::to_string(line_ + mark.line) + ":" + std::to_string(mark.column + 1);
}

std::string Cursor::message(const Problem& p) const {
  std::string m = at(p.mark) + ": " + p.key + ": " + p.what;
  if (!p.first.is_null()) m += " (first at " + at(p.first) + ")";
  return m;
}

void Cursor::fail(const YAML::Mark& mark, const std::string& key, const std::string& what) const {
  throw SettingsError(at(mark) + ": " + key + ": " + what);
}

double Cursor::number(const YAML::Node& node, double min, double max, const std::string& key) const {
  Key k;
  k.name = "";
  k.min = min;
  k.max = max;
  Value v;
  Problem p;
  k.type = Type::kNumber;
  if (!read(k, node, v, p)) fail(p.mark, key, p.what);
  return v.number;
}

long long Cursor::integer(const YAML::Node& node, double min, double max,
                          const std::string& key) const {
  Key k;
  k.type = Type::kInteger;
  k.min = min;
  k.max = max;
  Value v;
  Problem p;
  if (!read(k, node, v, p)) fail(p.mark, key, p.what);
  return v.integer;
}

std::string Cursor::text(const YAML::Node& node, const std::string& key) const {
  std::string s;
  Problem p;
  if (!readText(node, key, s, p)) fail(p.mark, key, p.what);
  return s;
}

void Cursor::record(const std::string& key, const YAML::Mark& mark) const {
  if (out_ && !mark.is_null()) out_->location[key] = at(mark);
}

void Cursor::checkKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
                       const std::string& key) const {
  for (const auto& e : map) {
    const std::string name = e.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
    const std::string best = closest(name, allowed);
    fail(e.first.Mark(), key + "." + name,
         "unknown key" + (best.empty() ? std::string() : " (did you mean " + best + "?)"));
  }
}

namespace detail {

void walkSection(const std::vector<const Key*>& keys, const YAML::Node& map,
                 const std::string& prefix, const Cursor& cursor, Locations& out,
                 const std::string& hint,
                 const std::function<void(const Key&, const YAML::Node&)>& take) {
  for (const auto& entry : map) {
    const YAML::Node& keyNode = entry.first;
    if (!keyNode.IsScalar())
      cursor.fail(keyNode.Mark(), prefix, "keys must be names, got " + describe(keyNode));
    const std::string name = prefix + keyNode.Scalar();
    const auto key = std::find_if(keys.begin(), keys.end(),
                                  [&](const Key* k) { return name == k->name; });
    if (key != keys.end()) {
      if (const auto before = out.location.find(name); before != out.location.end())
        cursor.fail(keyNode.Mark(), name, "given twice (first at " + before->second + ")");
      cursor.record(name, keyNode.Mark());
      take(**key, entry.second);
      continue;
    }
    const std::string group = name + ".";
    if (std::any_of(keys.begin(), keys.end(), [&](const Key* k) {
          return std::string(k->name).compare(0, group.size(), group) == 0;
        })) {
      if (entry.second.IsMap())
        walkSection(keys, entry.second, group, cursor, out, hint, take);
      else if (!entry.second.IsNull())
        cursor.fail(entry.second.Mark(), name,
                    "is a section: expected a map of its keys, got " + describe(entry.second));
      continue;
    }
    std::vector<std::string> names;
    for (const Key* k : keys) names.push_back(k->name);
    const std::string best = closest(name, names);
    cursor.fail(keyNode.Mark(), name,
                "unknown key" + (best.empty() ? std::string() : " (did you mean " + best + "?)") +
                    hint);
  }
}

}  // namespace detail

// ---- documentation

std::string troff(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

namespace {
std::string heading(const Key& k) { return *k.group ? k.group : k.section(); }

std::string docBounds(const Key& k) {
  std::string b = k.bounds();
  if (!b.empty() && isAngle(k)) b += " (or deg with a \"deg\" suffix)";
  return b;
}
}  // namespace

std::string manEntries(const std::vector<const Key*>& keys, const std::string& section) {
  std::ostringstream m;
  std::string group;
  bool first = true;
  const std::string prefix = section.empty() ? "" : section + ".";
  for (const Key* k : keys) {
    const std::string h = heading(*k);
    if (first || h != group) {
      group = h;
      m << ".SS "
        << (section.empty() ? (group.empty() ? "top level" : troff(group))
                            : troff(section) + (group.empty() ? "" : ": " + troff(group)))
        << "\n";
      first = false;
    }
    m << ".TP\n.B " << troff(prefix + k->name) << "\n";
    m << "(" << typeName(k->type);
    if (k->length) m << ", " << k->length << " elements";
    if (const std::string b = docBounds(*k); !b.empty()) m << ", " << troff(b);
    m << "; default: " << troff(*k->defaultYaml ? k->defaultYaml : "\"\"");
    if (k->restart) m << "; restart";
    m << ")\n" << troff(k->doc) << "\n";
  }
  return m.str();
}

std::string yamlDefaults(const std::vector<const Key*>& keys) {
  std::ostringstream y;
  std::string section;
  for (const Key* k : keys) {
    const std::string name = k->name;
    const std::string sec = k->section();
    const std::string leaf = sec.empty() ? name : name.substr(sec.size() + 1);
    if (sec != section) {
      section = sec;
      if (!sec.empty()) y << "\n" << section << ":\n";
    }
    const std::string indent = sec.empty() ? "" : "  ";
    y << indent << "# " << k->doc;
    if (const std::string b = docBounds(*k); !b.empty()) y << " " << b;
    if (k->restart) y << " (restart)";
    y << "\n" << indent << leaf << ": " << (*k->defaultYaml ? k->defaultYaml : "\"\"") << "\n";
  }
  return y.str();
}

const char* backendSectionDoc(const std::vector<const Key*>& keys, const char* name,
                              const char* format) {
  static std::string text;
  const std::string f = format ? format : "";
  if (f == "man") {
    text = manEntries(keys, std::string("backend.") + name);
  } else if (f == "yaml") {
    // Commented out, so that a profile of defaults stays one; uncommented (the first two
    // characters of each line) it is the section nested where a profile puts it.
    std::istringstream lines(yamlDefaults(keys));
    std::ostringstream out;
    out << "# backend:\n#   " << name << ":\n";
    for (std::string line; std::getline(lines, line);)
      out << (line.empty() ? "#" : "#     " + line) << "\n";
    text = out.str();
  } else {
    return nullptr;
  }
  return text.c_str();
}

std::string textReference(const std::vector<const Key*>& keys) {
  std::string out, group;
  char line[640];
  for (const Key* k : keys) {
    if (group != heading(*k)) {
      group = heading(*k);
      out += "\n" + group + "\n";
    }
    std::string bounds;
    if (k->type == Type::kChoice)
      bounds = k->unit;
    else if (k->isNumeric())
      bounds = "[" + formatNumber(k->min) + ", " + formatNumber(k->max) + "]";
    std::snprintf(line, sizeof line, "%-29s %-7s %-14s %-14s %s\n", k->name,
                  k->shortType().c_str(), k->defaultYaml, bounds.c_str(), k->doc);
    out += line;
  }
  return out;
}

}  // namespace ballast::schema
