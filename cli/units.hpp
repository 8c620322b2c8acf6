// Values an operator types: durations ("3", "3s", "500ms", "2min"), times (the same, 0 too),
// angles ("0.1" rad, "5deg"),
// vectors ("40,0,0"). Each parser returns false with a message that shows the expected form.
#pragma once

#include <array>
#include <string>

namespace ballast::cli {

bool parseDuration(const std::string& text, double& seconds, std::string& error);
/// A point in controller time (the t of a recording): a duration or 0.
bool parseTime(const std::string& text, double& seconds, std::string& error);
bool parseAngle(const std::string& text, double& radians, std::string& error);
bool parseNumber(const std::string& text, double& value, std::string& error);
bool parseVector3(const std::string& text, std::array<double, 3>& v, std::string& error);

}  // namespace ballast::cli
