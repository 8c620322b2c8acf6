#include "server/status_json.hpp"

#include <algorithm>

namespace ballast::server {

namespace {
using nlohmann::json;

json vec3(const double* v) {
  return json::array({v[0], v[1], v[2]});
}

json base(const control::BaseState& b) {
  return {{"position", vec3(b.position)},
          {"velocity", vec3(b.linear_velocity)},
          {"rpy", vec3(b.rpy)},
          {"angular_velocity", vec3(b.angular_velocity)},
          {"orientation",
           json::array({b.orientation[0], b.orientation[1], b.orientation[2], b.orientation[3]})}};
}
}  // namespace

json statusJson(const control::LoopStatus& s, const StatusExtras& x, bool joints) {
  json j;
  j["mode"] = control::modeName(s.mode);
  j["t"] = s.t;
  j["profile"] = x.profile;
  j["profile_path"] = x.profile_path;
  j["backend"] = x.backend;
  j["simulation"] = x.simulation;
  j["lockstep"] = s.lockstep;
  if (s.held) j["run_until"] = s.run_until;  // ballastd --hold: where the loop waits
  j["fallen"] = s.fallen;
  j["estop"] = s.estop;
  j["stand_up_progress"] = s.stand_up_progress;
  j["planner"] = s.planner_available ? "running" : "not built";
  j["base"] = base(s.base);
  const control::BaseCommand& c = s.command;
  j["command"] = {{"vx", c.vx},
                  {"vy", c.vy},
                  {"yaw_rate", c.yaw_rate},
                  {"ttl", c.velocity_active ? std::max(0.0, c.expires_at - s.t) : 0.0},
                  {"active", c.velocity_active},
                  {"height", c.height},
                  {"roll", c.roll},
                  {"pitch", c.pitch},
                  {"yaw", c.yaw}};
  j["contacts"] = json::array();
  for (bool b : s.contacts) j["contacts"].push_back(b);
  j["contact_frames"] = x.contact_frames;
  j["external_force"] = {s.external_force[0], s.external_force[1], s.external_force[2]};
  j["timing"] = {{"mpc_ms", s.mpc_ms},
                 {"wbc_ms", s.wbc_ms},
                 {"wbc_ms_max", s.wbc_ms_max},
                 {"tick_overruns", s.tick_overruns},
                 {"planner_failures", s.planner_failures},
                 {"position_fixes", s.position_fixes},
                 {"ticks", s.ticks}};
  // The real-time schedule (all zero in lockstep): lateness over the last window_s seconds.
  const control::TimingSummary& tm = s.timing;
  j["timing"]["lateness_ms"] = {{"last", tm.lateness_last * 1e3},
                                {"p50", tm.lateness_p50 * 1e3},
                                {"p99", tm.lateness_p99 * 1e3},
                                {"max", tm.lateness_max * 1e3}};
  j["timing"]["window_s"] = tm.window;
  j["timing"]["tick_ms"] = tm.work_last * 1e3;
  j["timing"]["tick_ms_max"] = tm.work_max * 1e3;
  j["timing"]["late_ticks"] = tm.late_ticks;
  j["timing"]["late_last_second"] = tm.late_in_last_second;
  j["timing"]["skipped_periods"] = tm.skipped_periods;
  j["timing"]["host_stalls"] = tm.host_stalls;
  j["timing"]["host_stall_ms_max"] = tm.host_stall_max * 1e3;
  j["faults"] = json::array();
  for (int i = 0; i < s.faults.size; ++i) {
    const control::Fault& f = s.faults.fault[i];
    j["faults"].push_back({{"kind", control::faultName(f.kind)},
                           {"t", f.t},
                           {"count", f.count},
                           {"message", f.message}});
  }
  if (s.has_truth)
    j["truth"] = {{"base", base(s.truth)}, {"non_foot_contact", s.truth_non_foot_contact}};
  j["lease"] = x.lease;
  j["recording"] = x.recording;
  j["settings_held"] = x.settings_held;
  j["map"] = x.map;
  j["terrain"] = {{"map_agrees", s.map_agrees}, {"map_error_m", s.map_disagreement}};
  if (joints) {
    json names = json::array(), q = json::array(), tau = json::array();
    for (int k = 0; k < s.num_joints; ++k) {
      names.push_back(k < static_cast<int>(x.joint_names.size()) ? x.joint_names[k] : "");
      q.push_back(s.q[k]);
      tau.push_back(s.tau[k]);
    }
    j["joints"] = {{"names", names}, {"q", q}, {"tau_ff", tau}};
  }
  return j;
}

}  // namespace ballast::server
