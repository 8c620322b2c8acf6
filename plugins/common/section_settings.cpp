#include "section_settings.hpp"

#include <cstdio>

#include "closest_name.hpp"

namespace ballast::plugin {

const char* typeName(KeyType t) {
  switch (t) {
    case KeyType::kNumber: return "number";
    case KeyType::kInteger: return "integer";
    case KeyType::kBool: return "bool";
    case KeyType::kString: return "string";
    case KeyType::kChoice: return "choice";
    case KeyType::kVec2: return "vec2";
    case KeyType::kVec3: return "vec3";
    case KeyType::kNamedNumbers: return "joints";
    case KeyType::kStrings: return "strings";
    case KeyType::kCustom: return "map";
  }
  return "?";
}

std::string SectionLocations::where(const std::string& key) const {
  const auto it = location.find(key);
  const std::string at =
      it != location.end() ? it->second : (origin.empty() ? "<backend section>" : origin);
  return at + ": " + key + ": ";
}

SectionCursor::SectionCursor(std::string file, int line, bool hasLine, SectionLocations& out)
    : file_(std::move(file)), line_(line), hasLine_(hasLine), out_(out) {}

SectionCursor::SectionCursor(const std::string& origin, SectionLocations& out) : out_(out) {
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

SectionCursor SectionCursor::forDefaults(SectionLocations& out) {
  return SectionCursor("<built-in default>", 1, false, out);
}

std::string SectionCursor::at(const YAML::Mark& mark) const {
  if (mark.is_null()) return file_ + ":" + std::to_string(line_);
  return file_ + ":" + std::to_string(line_ + mark.line) + ":" + std::to_string(mark.column + 1);
}

void SectionCursor::fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& what) const {
  throw SettingsError(at(mark) + ": " + key + ": " + what);
}

std::string SectionCursor::describe(const YAML::Node& node) {
  if (node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list of " + std::to_string(node.size());
  if (node.IsMap()) return "a map";
  return "'" + node.Scalar() + "'";
}

std::string SectionCursor::formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

double SectionCursor::number(const YAML::Node& node, double min, double max,
                             const std::string& key) const {
  double v = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v))
    fail(node.Mark(), key, "expected a number, got " + describe(node));
  if (!(v >= min && v <= max))
    fail(node.Mark(), key,
         node.Scalar() + " is out of range [" + formatNumber(min) + ", " + formatNumber(max) + "]");
  return v;
}

long long SectionCursor::integer(const YAML::Node& node, double min, double max,
                                 const std::string& key) const {
  // Hexadecimal too (CAN ids are written so: 0x100).
  const std::string text = node.IsScalar() ? node.Scalar() : "";
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X') &&
      text.find_first_not_of("0123456789abcdefABCDEF", 2) == std::string::npos && text.size() <= 10) {
    const long long v = std::stoll(text.substr(2), nullptr, 16);
    if (!(v >= min && v <= max))
      fail(node.Mark(), key,
           text + " is out of range [" + formatNumber(min) + ", " + formatNumber(max) + "]");
    return v;
  }
  const double v = number(node, min, max, key);
  if (v != std::floor(v)) fail(node.Mark(), key, "expected an integer, got " + node.Scalar());
  return static_cast<long long>(v);
}

std::string SectionCursor::text(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar() && !node.IsNull())
    fail(node.Mark(), key, "expected a string, got " + describe(node));
  return node.IsNull() ? "" : node.Scalar();
}

void SectionCursor::record(const std::string& key, const YAML::Mark& mark) const {
  if (!mark.is_null()) out_.location[key] = at(mark);
}

void SectionCursor::checkKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
                              const std::string& key) const {
  for (const auto& e : map) {
    const std::string name = e.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
    const std::string best = closest(name, allowed);
    fail(e.first.Mark(), key + "." + name,
         "unknown key" + (best.empty() ? std::string() : " (did you mean " + best + "?)"));
  }
}

std::string closest(const std::string& name, const std::vector<std::string>& names) {
  return closestName(name, names, [](const std::string& n) { return n; });
}

}  // namespace ballast::plugin
