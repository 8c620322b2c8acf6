#include "cli/status_view.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace ballast::cli {

using nlohmann::json;

namespace {

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

double num(const json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
}

std::string vec(const json& v, const char* format, double scale = 1.0) {
  std::string s;
  if (!v.is_array()) return "-";
  for (const auto& x : v)
    s += (s.empty() ? "" : " ") + (x.is_number() ? fmt(format, x.get<double>() * scale) : "-");
  return s;
}

std::string baseLine(const json& b) {
  return "x y z " + vec(b["position"], "%.3f") + " m   v " + vec(b["velocity"], "%+.2f") +
         " m/s   roll pitch yaw " + vec(b["rpy"], "%+.1f", 180.0 / M_PI) + " deg";
}

std::string text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : " ") + text(x);
    return s;
  }
  return v.dump();
}

}  // namespace

std::string renderStatus(const json& s) {
  std::ostringstream o;
  const double t = num(s, "t");
  o << "mode       " << s.value("mode", "?") << (s.value("estop", false) ? " (estop latched)" : "")
    << (s.value("fallen", false) ? "  FALLEN" : "") << "\n";
  o << "time       " << fmt("%.3f", t) << " s" << (s.value("lockstep", false) ? " (lockstep)" : "")
    << "\n";
  o << "profile    " << s.value("profile", "?") << "   backend " << s.value("backend", "?")
    << (s.value("simulation", false) ? " (simulation)" : "") << "\n";
  if (s.contains("base")) o << "base       " << baseLine(s["base"]) << "\n";
  if (s.contains("truth") && s["truth"].is_object())
    o << "truth      " << baseLine(s["truth"]["base"]) << "\n";
  if (s.contains("command")) {
    const json& c = s["command"];
    o << "command    vx " << fmt("%+.2f", num(c, "vx")) << " vy " << fmt("%+.2f", num(c, "vy"))
      << " m/s  yaw rate " << fmt("%+.2f", num(c, "yaw_rate")) << " rad/s  ttl "
      << fmt("%.1f", num(c, "ttl")) << " s   pose height " << fmt("%.3f", num(c, "height"))
      << " m  roll " << fmt("%+.1f", num(c, "roll") * 180 / M_PI) << " pitch "
      << fmt("%+.1f", num(c, "pitch") * 180 / M_PI) << " yaw "
      << fmt("%+.1f", num(c, "yaw") * 180 / M_PI) << " deg\n";
  }
  if (s.contains("contacts")) {
    o << "contacts  ";
    const json& names = s.value("contact_frames", json::array());
    for (std::size_t i = 0; i < s["contacts"].size(); ++i)
      o << " " << (i < names.size() ? names[i].get<std::string>() : std::to_string(i)) << " "
        << (s["contacts"][i].get<bool>() ? "[x]" : "[ ]");
    o << "\n";
  }
  if (s.contains("timing")) {
    const json& tm = s["timing"];
    o << "timing     controller " << fmt("%.3f", num(tm, "wbc_ms")) << " ms (max "
      << fmt("%.3f", num(tm, "wbc_ms_max")) << ")   planner " << fmt("%.3f", num(tm, "mpc_ms"))
      << " ms (" << s.value("planner", "?") << ")\n";
    if (s.value("lockstep", false)) {
      o << "schedule   lockstep (simulated time waits for the loop)\n";
    } else if (tm.contains("lateness_ms")) {
      const json& l = tm["lateness_ms"];
      o << "schedule   tick " << fmt("%.3f", num(tm, "tick_ms")) << " ms (max "
        << fmt("%.3f", num(tm, "tick_ms_max")) << ")   lateness last "
        << fmt("%.3f", num(l, "last")) << " p50 " << fmt("%.3f", num(l, "p50")) << " p99 "
        << fmt("%.3f", num(l, "p99")) << " max " << fmt("%.3f", num(l, "max")) << " ms (last "
        << fmt("%.0f", num(tm, "window_s")) << " s)   late " << tm.value("late_ticks", 0)
        << "   skipped " << tm.value("skipped_periods", 0) << "\n";
      if (tm.value("host_stalls", 0) > 0)
        o << "           host stalls " << tm.value("host_stalls", 0) << " (max "
          << fmt("%.1f", num(tm, "host_stall_ms_max"))
          << " ms): the simulated world waited for its host\n";
    }
  }
  o << "faults    ";
  if (!s.contains("faults") || s["faults"].empty()) o << " none";
  o << "\n";
  if (s.contains("faults"))
    for (const auto& f : s["faults"])
      o << "  " << f.value("kind", "?") << " at t=" << fmt("%.3f", num(f, "t")) << " (x"
        << f.value("count", 1) << "): " << f.value("message", "") << "\n";
  if (s.contains("lease") && s["lease"].is_object()) {
    const json& l = s["lease"];
    if (l.value("held", false))
      o << "lease      held by uid " << l.value("uid", 0) << " (pid " << l.value("pid", 0)
        << (l.value("client", "").empty() ? "" : ", " + l.value("client", "")) << "), idle "
        << fmt("%.0f", num(l, "idle_s")) << " s\n";
    else
      o << "lease      free\n";
  }
  if (s.contains("recording") && s["recording"].is_object()) {
    const json& r = s["recording"];
    if (r.value("active", false))
      o << "recording  " << r["path"].get<std::string>() << " (" << r.value("frames", 0)
        << " frames, " << r.value("dropped", 0) << " dropped)\n";
    else
      o << "recording  off\n";
  }
  if (s.contains("map") && s["map"].is_object())
    o << "map        " << s["map"].value("path", "") << "\n";
  if (s.contains("terrain") && s["terrain"].is_object() && !s["terrain"].value("map_agrees", true))
    o << "terrain    the map DISAGREES with the stance feet by " << fmt("%.3f", num(s["terrain"], "map_error_m"))
      << " m: planning on the plane they stood on until it agrees\n";
  return o.str();
}

bool lookup(const json& object, const std::string& path, std::string& out) {
  const json* v = &object;
  std::stringstream in(path);
  for (std::string part; std::getline(in, part, '.');) {
    if (v->is_object() && v->contains(part)) {
      v = &(*v)[part];
    } else if (v->is_array() && !part.empty() &&
               part.find_first_not_of("0123456789") == std::string::npos &&
               std::stoul(part) < v->size()) {
      v = &(*v)[std::stoul(part)];
    } else {
      return false;
    }
  }
  out = text(*v);
  return true;
}

}  // namespace ballast::cli
