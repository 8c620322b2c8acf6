// Loading backend plugins: a good one works through the ABI; each broken case says why.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "backend/plugin_loader.hpp"

namespace ballast::backend {
namespace {

const std::string kDir = TEST_PLUGIN_DIR;

std::string loadError(const std::string& nameOrPath, const std::vector<std::string>& dirs = {}) {
  try {
    Plugin::load(nameOrPath, dirs);
  } catch (const PluginError& e) {
    return e.what();
  }
  return "";
}

TEST(PluginLoader, LoadsByNameFromAGivenDirectoryAndRunsATick) {
  const auto plugin = Plugin::load("testgood", {kDir});
  EXPECT_EQ(plugin->path(), kDir + "/libballast_backend_testgood.so");
  EXPECT_STREQ(plugin->entry().name, "test");
  BackendPtr backend = plugin->create();
  Config config;
  Error error;
  ASSERT_TRUE(backend->configure(config, error)) << error.message;
  EXPECT_EQ(backend->capabilities().num_joints, 2);
  Commands cmd;
  cmd.num_joints = 2;
  cmd.joint[1].q_des = 0.5;
  Sensors s;
  EXPECT_EQ(backend->write(cmd), Status::kOk);
  EXPECT_EQ(backend->advance(), Status::kOk);
  EXPECT_EQ(backend->read(s), Status::kOk);
  EXPECT_DOUBLE_EQ(s.q[1], 0.5);
  EXPECT_DOUBLE_EQ(s.time, 0.001);
}

TEST(PluginLoader, ConfigureErrorsComeBackAsText) {
  const auto plugin = Plugin::load(kDir + "/libballast_backend_testgood.so");
  BackendPtr backend = plugin->create();
  Config config;
  config.section_yaml = "fail: true";
  Error error;
  EXPECT_FALSE(backend->configure(config, error));
  EXPECT_STREQ(error.message, "test.yaml:3: fail: asked to fail");
}

TEST(PluginLoader, MissingPluginNamesEveryDirectorySearched) {
  const std::string msg = loadError("nosuch", {"/opt/first"});
  EXPECT_NE(msg.find("backend 'nosuch': no libballast_backend_nosuch.so in /opt/first, "),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find(BALLAST_BUILD_PLUGIN_DIR), std::string::npos) << msg;
  EXPECT_EQ(loadError("/no/such/file.so"), "backend plugin /no/such/file.so: no such readable file");
}

TEST(PluginLoader, AFileThatIsNotASharedLibraryGivesDlerror) {
  const std::string path = ::testing::TempDir() + "/libballast_backend_text.so";
  std::ofstream(path) << "this is not an ELF file\n";
  const std::string msg = loadError(path);
  EXPECT_NE(msg.find("backend plugin " + path + ": cannot load it: "), std::string::npos) << msg;
  EXPECT_NE(msg.find("file too short"), std::string::npos) << msg;  // dlerror()'s words
}

TEST(PluginLoader, ALibraryWithoutTheEntrySymbolIsNotABackend) {
  const std::string msg = loadError("testnoentry", {kDir});
  EXPECT_NE(msg.find("not a ballast backend: no symbol 'ballast_backend_entry' ("),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("undefined symbol"), std::string::npos) << msg;
}

TEST(PluginLoader, AnotherAbiVersionIsRefusedBeforeUse) {
  const std::string msg = loadError("testoldabi", {kDir});
  EXPECT_NE(msg.find("built for backend ABI version " + std::to_string(kBackendAbiVersion + 1000) +
                     ", this ballastd speaks version " + std::to_string(kBackendAbiVersion)),
            std::string::npos)
      << msg;
}

TEST(PluginLoader, EnvironmentPathIsSearched) {
  setenv("BALLAST_PLUGIN_PATH", ("/nonexistent:" + kDir).c_str(), 1);
  EXPECT_NO_THROW(Plugin::load("testgood"));
  unsetenv("BALLAST_PLUGIN_PATH");
}

}  // namespace
}  // namespace ballast::backend
