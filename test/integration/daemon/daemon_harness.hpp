// Running ballastd and the ballast CLI from tests: a daemon per test in its own temporary
// directory (socket, lease files, recordings), CLI runs with their exit status and output,
// raw protocol connections, and status polling instead of sleeps.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test/unit/run_program.hpp"

namespace ballast::test {

namespace fs = std::filesystem;
using nlohmann::json;

/// A raw protocol connection (for what the CLI never sends).
class RawClient {
 public:
  explicit RawClient(const std::string& path) {
    fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
  }
  ~RawClient() { close(fd_); }
  bool connected() const { return connected_; }
  /// Sends text (a newline is added); false if the connection took not all of it.
  bool send(const std::string& text) {
    const std::string line = text + "\n";
    for (std::size_t done = 0; done < line.size();) {
      const ssize_t n = ::send(fd_, line.data() + done, line.size() - done, MSG_NOSIGNAL);
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }
  /// Sends text (a newline is added) and returns the next reply line (null on timeout).
  json ask(const std::string& text, double timeout_s = 10) {
    return send(text) ? next(timeout_s) : json();
  }
  json next(double timeout_s = 10) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      if (const auto nl = buffer_.find('\n'); nl != std::string::npos) {
        const std::string l = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return json::parse(l);
      }
      pollfd p{fd_, POLLIN, 0};
      if (std::chrono::steady_clock::now() > deadline || poll(&p, 1, 100) < 0) return json();
      if (!(p.revents & POLLIN)) continue;
      char buf[65536];
      const ssize_t n = recv(fd_, buf, sizeof(buf), 0);
      if (n <= 0) return json();
      buffer_.append(buf, static_cast<std::size_t>(n));
    }
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
  std::string buffer_;
};

inline std::string testName() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string n = std::string(info->test_suite_name()) + "." + info->name();
  for (char& c : n)
    if (c == '/') c = '_';
  return n;
}

/// A temporary directory for one test.
inline fs::path scratchDir() {
  const fs::path d =
      fs::temp_directory_path() / ("ballast-it-" + std::to_string(getpid()) + "-" + testName());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

inline std::string writeFile(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

inline std::string readFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Daemon {
 public:
  /// Starts ballastd --profile profile --lockstep in dir, and waits for its socket: dir's
  /// ballastd.sock, extra's --socket, or with defaultSocket the one ballastd finds by itself
  /// ($XDG_RUNTIME_DIR/ballast/ballastd.sock; the caller sets XDG_RUNTIME_DIR).
  Daemon(const fs::path& dir, const std::string& profile, std::vector<std::string> extra = {},
         bool lockstep = true, bool defaultSocket = false)
      : dir_(dir),
        socket_((dir / "ballastd.sock").string()),
        log_((dir / "ballastd.log").string()) {
    for (std::size_t i = 0; i + 1 < extra.size(); ++i)
      if (extra[i] == "--socket") socket_ = extra[i + 1];
    if (defaultSocket) socket_ = std::string(std::getenv("XDG_RUNTIME_DIR")) + "/ballast/ballastd.sock";
    std::vector<std::string> argv = {BALLASTD, "--profile", profile, "--log-level", "debug"};
    if (!defaultSocket && std::find(extra.begin(), extra.end(), "--socket") == extra.end()) {
      argv.push_back("--socket");
      argv.push_back(socket_);
    }
    if (lockstep) argv.push_back("--lockstep");
    argv.insert(argv.end(), extra.begin(), extra.end());
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> envStrings{"BALLAST_PLUGIN_PATH=" FAKE_PLUGIN_DIR};
    for (char** e = environ; *e; ++e) envStrings.push_back(*e);
    std::vector<char*> envp;
    for (auto& e : envStrings) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn(&pid_, BALLASTD, &actions, nullptr, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
      int status;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        pid_ = -1;
        return;
      }
      if (RawClient(socket_).connected()) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ~Daemon() {
    if (pid_ > 0) stop(SIGKILL);
  }
  bool running() const { return pid_ > 0; }
  /// The exit status after stop() or a failed start.
  int exitStatus() const { return exit_; }
  int stop(int signal = SIGTERM) {
    if (pid_ <= 0) return exit_;
    kill(pid_, signal);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return exit_;
  }
  void signal(int s) { kill(pid_, s); }
  /// Waits for the daemon to exit on its own; its exit status, or -2 if it is still running.
  int waitExit(double timeout_s) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (pid_ > 0 && std::chrono::steady_clock::now() < deadline) {
      int status;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return exit_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return pid_ > 0 ? -2 : exit_;
  }
  const std::string& socket() const { return socket_; }
  std::string log() const { return readFile(log_); }

  /// ballast --socket S --lease-file DIR/lease-CLIENT args...
  Outcome cli(const std::vector<std::string>& args, const std::string& client = "a") const {
    std::vector<std::string> argv = {BALLAST, "--socket", socket_, "--lease-file",
                                     (dir_ / ("lease-" + client)).string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return runProgram(argv);
  }
  json status() const {
    const Outcome r = cli({"--json", "status"});
    return r.status == 0 ? r.parsed() : json();
  }
  /// Polls status until pred holds (true) or timeout_s of wall time passes (false).
  bool waitFor(const std::function<bool(const json&)>& pred, double timeout_s = 30) const {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      RawClient c(socket_);
      const json r = c.ask(R"({"cmd":"status"})");
      if (r.is_object() && r.value("ok", false) && pred(r["status"])) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  bool waitForMode(const std::string& mode, double timeout_s = 30) const {
    return waitFor([&](const json& s) { return s["mode"] == mode; }, timeout_s);
  }

 private:
  fs::path dir_;
  std::string socket_, log_;
  pid_t pid_ = -1;
  int exit_ = -1;
};

}  // namespace ballast::test
