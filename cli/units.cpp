#include "cli/units.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ballast::cli {

namespace {
/// A finite number followed by one of the suffixes (scale each), or none (scale 1).
bool parseWithSuffix(const std::string& text,
                     const std::initializer_list<std::pair<const char*, double>>& suffixes,
                     double& out) {
  std::string s = text;
  double scale = 1.0;
  for (const auto& [suffix, factor] : suffixes) {
    const std::string sfx = suffix;
    if (s.size() > sfx.size() && s.compare(s.size() - sfx.size(), sfx.size(), sfx) == 0) {
      s.resize(s.size() - sfx.size());
      scale = factor;
      break;
    }
  }
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return false;
  out = v * scale;
  return true;
}
}  // namespace

bool parseNumber(const std::string& text, double& value, std::string& error) {
  if (parseWithSuffix(text, {}, value)) return true;
  error = "'" + text + "' is not a number";
  return false;
}

namespace {
/// Seconds with an optional unit; "ms" before "s": the first suffix that matches wins.
bool parseSeconds(const std::string& text, double& seconds) {
  return parseWithSuffix(text, {{"ms", 1e-3}, {"min", 60.0}, {"s", 1.0}}, seconds);
}
}  // namespace

bool parseDuration(const std::string& text, double& seconds, std::string& error) {
  if (parseSeconds(text, seconds) && seconds > 0) return true;
  error = "'" + text + "' is not a duration: give seconds, e.g. 3, 2.5s, 500ms or 1min";
  return false;
}

bool parseTime(const std::string& text, double& seconds, std::string& error) {
  if (parseSeconds(text, seconds) && seconds >= 0) return true;
  error = "'" + text + "' is not a time: give controller seconds, e.g. 0, 12.5, 12.5s or 2min";
  return false;
}

bool parseAngle(const std::string& text, double& radians, std::string& error) {
  if (parseWithSuffix(text, {{"deg", M_PI / 180.0}, {"rad", 1.0}}, radians)) return true;
  error = "'" + text + "' is not an angle: give radians (0.1) or degrees (5deg)";
  return false;
}

bool parseVector3(const std::string& text, std::array<double, 3>& v, std::string& error) {
  std::stringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 3 || !parseWithSuffix(part, {}, v[n])) {
      n = -1;
      break;
    }
    ++n;
  }
  if (n == 3) return true;
  error = "'" + text + "' is not three numbers: give FX,FY,FZ, e.g. 40,0,0";
  return false;
}

}  // namespace ballast::cli
