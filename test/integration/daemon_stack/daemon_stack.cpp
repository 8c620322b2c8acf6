#include "test/integration/daemon_stack/daemon_stack.hpp"

#include <stdexcept>

namespace ballast::test {

DaemonStack::DaemonStack(const std::string& profilePath) {
  daemon::DaemonOptions options;
  options.profile = profilePath;
  options.lockstep = true;
  options.serve = false;
  try {
    daemon_ = std::make_unique<daemon::Daemon>(options);
  } catch (const daemon::StartupError& e) {
    throw std::runtime_error(e.what());
  }
  loop_ = &daemon_->loop();
}

DaemonStack::~DaemonStack() = default;

bool DaemonStack::run(double seconds) {
  const double until = t() + seconds - 1e-9;
  while (t() < until) {
    loop_->tick();
    const control::LoopStatus s = loop_->status();
    if (s.mode == control::Mode::kDamp || s.fallen) return false;
  }
  return true;
}

control::Refusal DaemonStack::command(control::OperatorCommand c) {
  c.sequence = ++sequence_;
  if (!loop_->submit(c)) throw std::runtime_error("the command ring is full");
  control::CommandReply r;
  for (int i = 0; i < 100; ++i) {
    loop_->tick();
    while (loop_->popReply(r))
      if (r.sequence == c.sequence) return r.refusal;
  }
  throw std::runtime_error("no reply to a command");
}

control::Refusal DaemonStack::walk(double vx, double vy, double yawRate, double ttl) {
  control::OperatorCommand c;
  c.kind = control::CommandKind::kWalk;
  c.vx = vx;
  c.vy = vy;
  c.yaw_rate = yawRate;
  c.ttl = ttl;
  return command(c);
}

control::Refusal DaemonStack::push(const char* body, double fx, double fy, double fz,
                                   double duration) {
  control::OperatorCommand c;
  c.kind = control::CommandKind::kPush;
  control::copyText(c.push.body, body);
  c.push.force[0] = fx;
  c.push.force[1] = fy;
  c.push.force[2] = fz;
  c.push.duration = duration;
  return command(c);
}

bool DaemonStack::waitForMode(control::Mode mode, double seconds) {
  const double until = t() + seconds;
  while (t() < until) {
    if (loop_->status().mode == mode) return true;
    loop_->tick();
  }
  return loop_->status().mode == mode;
}

}  // namespace ballast::test
