// Plugins for the loader tests, built three ways from this one file:
//   TEST_PLUGIN_GOOD      a minimal valid backend (two joints that follow their PD command)
//   TEST_PLUGIN_OLD_ABI   a backend whose entry reports another ABI version
//   TEST_PLUGIN_NO_ENTRY  a shared library without the entry symbol
#include <cstring>

#include "backend_abi.hpp"

using namespace ballast::backend;

#ifndef TEST_PLUGIN_NO_ENTRY
namespace {
class TwoJoints final : public Backend {
 public:
  bool configure(const Config& config, Error& error) override {
    if (std::strstr(config.section_yaml, "fail")) {
      copyMessage(error, "test.yaml:3: fail: asked to fail");
      return false;
    }
    period_ = config.period;
    copyMessage(error, "");
    std::strcpy(caps_.name, "test");
    caps_.simulation = true;
    caps_.lockstep = true;
    caps_.num_joints = 2;
    std::strcpy(caps_.joint_names[0], "a");
    std::strcpy(caps_.joint_names[1], "b");
    return true;
  }
  const Capabilities& capabilities() const override { return caps_; }
  bool start(Error&) override { return true; }
  Status read(Sensors& s) override {
    s.time = time_;
    s.sequence = sequence_;
    s.num_joints = 2;
    for (int j = 0; j < 2; ++j) s.q[j] = q_[j];
    return Status::kOk;
  }
  Status write(const Commands& c) override {
    for (int j = 0; j < 2; ++j) q_[j] = c.joint[j].q_des;
    return Status::kOk;
  }
  Status advance(TickTiming&) override {
    time_ += period_;
    ++sequence_;
    return Status::kOk;
  }
  const Error& lastError() const override { return error_; }
  void stop() override {}

 private:
  Capabilities caps_;
  Error error_;
  double period_ = 0.001, time_ = 0.0, q_[2] = {};
  unsigned long sequence_ = 1;
};

Backend* create() { return new TwoJoints; }
void destroy(Backend* b) { delete b; }

#ifdef TEST_PLUGIN_OLD_ABI
constexpr std::uint32_t kVersion = kBackendAbiVersion + 1000;
#else
constexpr std::uint32_t kVersion = kBackendAbiVersion;
#endif
const BackendEntry kEntry{kVersion, "test", "loader test backend", &create, &destroy, nullptr, nullptr};
}  // namespace

extern "C" __attribute__((visibility("default"))) const BackendEntry* ballast_backend_entry() {
  return &kEntry;
}
#else
extern "C" __attribute__((visibility("default"))) int not_a_backend() { return 42; }
#endif
