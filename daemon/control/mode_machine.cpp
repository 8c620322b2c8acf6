#include "control/mode_machine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ballast::control {

const char* modeName(Mode mode) {
  switch (mode) {
    case Mode::kPassive:
      return "passive";
    case Mode::kStandUp:
      return "stand-up";
    case Mode::kStand:
      return "stand";
    case Mode::kWalk:
      return "walk";
    case Mode::kDamp:
      return "damp";
    case Mode::kRecover:
      return "recover";
  }
  return "unknown";
}

const char* faultName(FaultKind kind) {
  switch (kind) {
    case FaultKind::kBackendFault:
      return "backend_fault";
    case FaultKind::kBackendStale:
      return "backend_stale";
    case FaultKind::kNotANumber:
      return "nan";
    case FaultKind::kFall:
      return "fall";
    case FaultKind::kEstop:
      return "estop";
    case FaultKind::kPlanner:
      return "planner";
    case FaultKind::kCommandGap:
      return "command_gap";
    case FaultKind::kLateTicks:
      return "late_ticks";
    case FaultKind::kException:
      return "exception";
  }
  return "unknown";
}

bool FaultList::add(FaultKind kind, double t, const char* message) {
  for (int i = 0; i < size; ++i)
    if (fault[i].kind == kind) {
      ++fault[i].count;
      return false;
    }
  if (size == kCapacity) return false;
  Fault& f = fault[size++];
  f.kind = kind;
  f.t = t;
  f.count = 1;
  copyText(f.message, message);
  return true;
}

bool FaultList::has(FaultKind kind) const {
  for (int i = 0; i < size; ++i)
    if (fault[i].kind == kind) return true;
  return false;
}

void ModeMachine::configure(const ControlSettings& settings, double nominal_height) {
  const bool first = settings_ == nullptr;
  settings_ = &settings;
  nominal_height_ = nominal_height;
  if (first) command_.height = nominal_height;
}

void ModeMachine::start(Mode initial, double t) {
  command_ = BaseCommand{};
  command_.height = nominal_height_;
  faults_.clear();
  estop_ = false;
  setMode(initial, t);
}

void ModeMachine::setMode(Mode mode, double t) {
  if (mode == Mode::kStandUp && mode_ != Mode::kStandUp) stand_up_start_ = t;
  if (mode != Mode::kWalk) {
    command_.vx = command_.vy = command_.yaw_rate = 0.0;
    command_.velocity_active = false;
  }
  mode_ = mode;
}

double ModeMachine::standUpProgress(double t) const {
  if (mode_ != Mode::kStandUp) return 1.0;
  const double d = settings_->stand_up_duration;
  return d <= 0.0 ? 1.0 : std::clamp((t - stand_up_start_) / d, 0.0, 1.0);
}

Refusal ModeMachine::checkPose(const OperatorCommand& c, char (&message)[kMessageLength]) const {
  const ControlSettings& s = *settings_;
  const double h = std::isnan(c.height) ? nominal_height_ : c.height;
  if (h < s.min_pose_height || h > s.max_pose_height) {
    std::snprintf(message, kMessageLength,
                  "height %.3f m is outside %s..%s [%.3f, %.3f] m: pick a height inside it", h,
                  settingName(s, &s.min_pose_height, "the lowest"),
                  settingName(s, &s.max_pose_height, "the highest pose height"), s.min_pose_height,
                  s.max_pose_height);
    return Refusal::kOutOfRange;
  }
  const double tilt[2] = {c.roll, c.pitch};
  const char* names[2] = {"roll", "pitch"};
  for (int i = 0; i < 2; ++i)
    if (std::abs(tilt[i]) > s.max_pose_tilt) {
      std::snprintf(message, kMessageLength,
                    "%s %.3f rad is beyond %s %.3f rad: pick a smaller angle", names[i], tilt[i],
                    settingName(s, &s.max_pose_tilt, "the tilt limit"), s.max_pose_tilt);
      return Refusal::kOutOfRange;
    }
  if (std::abs(c.yaw) > s.max_pose_yaw) {
    std::snprintf(message, kMessageLength,
                  "yaw %.3f rad is beyond %s %.3f rad: pick a smaller angle", c.yaw,
                  settingName(s, &s.max_pose_yaw, "the yaw limit"), s.max_pose_yaw);
    return Refusal::kOutOfRange;
  }
  if (c.yaw != 0.0 && !s.feet_cannot_yaw.empty()) {
    std::snprintf(message, kMessageLength,
                  "yaw %.3f rad: this robot cannot turn its base over its feet: %s", c.yaw,
                  s.feet_cannot_yaw.c_str());
    return Refusal::kOutOfRange;
  }
  return Refusal::kNone;
}

Refusal ModeMachine::handle(const OperatorCommand& c, double t, const Situation& situation,
                            char (&message)[kMessageLength]) {
  message[0] = '\0';
  const ControlSettings& s = *settings_;
  auto refuse = [&](Refusal r, const char* text) {
    copyText(message, text);
    return r;
  };
  auto refuseDamped = [&](const char* verb) {
    if (estop_)
      std::snprintf(message, kMessageLength,
                    "estop is latched (robot damped): run `ballast reset`, then `ballast %s`",
                    verb);
    else
      std::snprintf(message, kMessageLength,
                    "the robot is damped after a fault (see the faults in `ballast status`): "
                    "run `ballast reset`, then `ballast %s`",
                    verb);
    return Refusal::kRefused;
  };

  switch (c.kind) {
    case CommandKind::kStand:
      switch (mode_) {
        case Mode::kDamp:
          return refuseDamped("stand");
        case Mode::kPassive:
          if (situation.fallen)
            return refuse(Refusal::kRefused,
                          "the robot has fallen (tilted or too low): put it on its feet, then "
                          "run `ballast stand`");
          setMode(Mode::kStandUp, t);
          return Refusal::kNone;
        case Mode::kWalk:
          setMode(Mode::kStand, t);
          return Refusal::kNone;
        case Mode::kStandUp:
        case Mode::kStand:
        case Mode::kRecover:  // the planner ends the steps when they have done their work
          return Refusal::kNone;
      }
      break;

    case CommandKind::kWalk:
      if (!situation.planner_available)
        return refuse(Refusal::kUnavailable,
                      "walking needs the planner and this ballastd runs without one: the robot "
                      "keeps standing; use `ballast pose` to move the base in place");
      if (mode_ == Mode::kDamp) return refuseDamped("stand");
      if (!plannedMode(mode_))
        return refuse(Refusal::kRefused,
                      mode_ == Mode::kStandUp
                          ? "the robot is still standing up: wait until `ballast status` says "
                            "stand, then walk"
                          : "walk needs the robot standing: run `ballast stand` first");
      {
        const double lim[3] = {s.max_vx, s.max_vy, s.max_yaw_rate};
        const double val[3] = {c.vx, c.vy, c.yaw_rate};
        const double* field[3] = {&s.max_vx, &s.max_vy, &s.max_yaw_rate};
        for (int i = 0; i < 3; ++i)
          if (std::abs(val[i]) > lim[i]) {
            std::snprintf(message, kMessageLength, "%s %.3f is beyond the profile's %s %.3f: ask for less",
                          i == 2 ? "yaw rate" : (i == 0 ? "vx" : "vy"), val[i],
                          settingName(s, field[i], "limit"), lim[i]);
            return Refusal::kOutOfRange;
          }
        // Turning needs a foot that turns relative to the pelvis; walking straight with a yaw
        // asked for would go where the operator did not mean to. Refuse, and say why.
        if (c.yaw_rate != 0.0 && !s.feet_cannot_yaw.empty()) {
          std::snprintf(message, kMessageLength,
                        "yaw rate %.3f: this robot cannot turn: %s; walk with yaw rate 0 (vx and "
                        "vy as asked)", c.yaw_rate, s.feet_cannot_yaw.c_str());
          return Refusal::kOutOfRange;
        }
        const double ttl = c.ttl > 0.0 ? c.ttl : s.command_ttl;
        if (ttl > s.max_command_ttl) {
          std::snprintf(message, kMessageLength,
                        "ttl %.1f s is beyond %s %.1f s: send shorter commands (and repeat them)",
                        ttl, settingName(s, &s.max_command_ttl, "the longest ttl"), s.max_command_ttl);
          return Refusal::kOutOfRange;
        }
        setMode(Mode::kWalk, t);
        command_.vx = c.vx;
        command_.vy = c.vy;
        command_.yaw_rate = c.yaw_rate;
        command_.velocity_active = true;
        command_.expires_at = t + ttl;
      }
      return Refusal::kNone;

    case CommandKind::kPose: {
      if (mode_ != Mode::kStandUp && !plannedMode(mode_))
        return mode_ == Mode::kDamp
                   ? refuseDamped("stand")
                   : refuse(Refusal::kRefused,
                            "pose needs the robot standing: run `ballast stand` first");
      const Refusal r = checkPose(c, message);
      if (r != Refusal::kNone) return r;
      command_.height = std::isnan(c.height) ? nominal_height_ : c.height;
      command_.roll = c.roll;
      command_.pitch = c.pitch;
      command_.yaw = c.yaw;
      return Refusal::kNone;
    }

    case CommandKind::kStop:
      if (mode_ == Mode::kWalk) setMode(Mode::kStand, t);
      command_.vx = command_.vy = command_.yaw_rate = 0.0;
      command_.velocity_active = false;
      return Refusal::kNone;

    case CommandKind::kEstop:
      estop_ = true;
      faults_.add(FaultKind::kEstop, t, "estop requested by the operator");
      setMode(Mode::kDamp, t);
      return Refusal::kNone;

    case CommandKind::kReset:
      estop_ = false;
      faults_.clear();
      if (mode_ == Mode::kDamp) setMode(Mode::kPassive, t);
      return Refusal::kNone;

    case CommandKind::kPassive:
      if (estop_) return refuseDamped("passive");
      setMode(Mode::kPassive, t);
      return Refusal::kNone;

    case CommandKind::kPush:
    case CommandKind::kSwitchSettings:
    case CommandKind::kAdvance:
      break;
  }
  return refuse(Refusal::kRefused, "internal: this command is not the mode machine's");
}

bool ModeMachine::fault(FaultKind kind, double t, const char* message) {
  const bool fresh = faults_.add(kind, t, message);
  setMode(Mode::kDamp, t);
  return fresh;
}

void ModeMachine::recovering(bool stepping, double t) {
  if (stepping && mode_ == Mode::kStand) setMode(Mode::kRecover, t);
  if (!stepping && mode_ == Mode::kRecover) setMode(Mode::kStand, t);
}

void ModeMachine::update(double t) {
  if (mode_ == Mode::kStandUp && standUpProgress(t) >= 1.0) setMode(Mode::kStand, t);
  if (mode_ == Mode::kWalk && command_.velocity_active && t >= command_.expires_at)
    setMode(Mode::kStand, t);
}

}  // namespace ballast::control
