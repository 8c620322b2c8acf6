// Numbers in messages and documentation: the shortest form printf's %g gives (0.001, 1e-08,
// 2e+07). Shared by the daemon and the plugins so that a bound reads the same everywhere.
#pragma once

#include <cstdio>
#include <string>

namespace ballast {

inline std::string formatNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace ballast
