// The recording's column table (control/telemetry_columns.cpp): every column declared once and
// described, kept to its stated resolution through a .blog, and the .blog of a synthetic walk
// within issue 18's size goal; ballastd(8) lists the table as it is.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "blog/blog.hpp"
#include "control/telemetry.hpp"
#include "test/unit/control/telemetry_walk.hpp"
#include "test/unit/test_support.hpp"

namespace ballast::control {
namespace {

std::string tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("ballast-telemetry-" + std::to_string(getpid()) + "-" + name);
}

TEST(TelemetryColumns, EveryColumnIsNamedOnceAndDescribed) {
  std::vector<std::string> joints;
  for (int j = 0; j < kMaxJoints; ++j) joints.push_back("joint" + std::to_string(j));
  const auto columns = telemetryColumnsDescribed(joints);
  EXPECT_EQ(columns.size(), kMaxTelemetryColumns);
  std::set<std::string> names;
  for (const blog::Column& c : columns) {
    EXPECT_TRUE(names.insert(c.name).second) << c.name << " twice";
    EXPECT_EQ(c.name.find_first_of(" \t,"), std::string::npos) << c.name;
    EXPECT_FALSE(c.unit.empty()) << c.name;
    EXPECT_EQ(c.unit.find(' '), std::string::npos) << c.name;
    EXPECT_FALSE(c.doc.empty()) << c.name;
    if (c.type == blog::Type::kI32) {
      EXPECT_GT(c.resolution, 0.0) << c.name;
    } else {
      EXPECT_EQ(c.resolution, 0.0) << c.name;
    }
  }
  EXPECT_EQ(columns.front().name, "t");  // `ballast plot` and every slice rely on it
  // Lossless where it matters: the time, the mode, the contact flags, the operator's commands.
  for (const blog::Column& c : columns)
    if (c.name == "t" || c.name == "mode" || c.name.rfind("contact_", 0) == 0 ||
        c.name.rfind("cmd_", 0) == 0) {
      EXPECT_NE(c.type, blog::Type::kI32) << c.name;
    }
  TelemetryFrame f;
  f.num_joints = kMaxJoints;
  double values[kMaxTelemetryColumns];
  EXPECT_EQ(telemetryValues(f, values), kMaxTelemetryColumns);
}

/// The synthetic walk written to path as a .blog; returns the file's bytes.
std::uint64_t writeWalk(const std::string& path) {
  const test::WalkFrames& w = test::walkFrames();
  blog::Header h;
  h.profile = "sim-flat";
  h.robot = "humanoid";
  h.columns = telemetryColumnsDescribed(w.joints);
  blog::Writer writer;
  std::string error;
  EXPECT_TRUE(writer.open(path, h, error)) << error;
  std::vector<double> values(kMaxTelemetryColumns);
  for (const TelemetryFrame& f : w.frames) {
    telemetryValues(f, values.data());
    writer.append(values.data());
  }
  return writer.close();
}

TEST(TelemetryColumns, AWalkReadsBackWithinEachColumnsResolution) {
  const test::WalkFrames& w = test::walkFrames();
  const std::string path = tempFile("walk.blog");
  writeWalk(path);
  blog::Reader r;
  std::string error;
  ASSERT_TRUE(r.open(path, error)) << error;
  const auto& columns = r.header().columns;
  const auto expected = telemetryColumnsDescribed(w.joints);
  ASSERT_EQ(columns.size(), expected.size());
  for (std::size_t c = 0; c < columns.size(); ++c) {
    EXPECT_EQ(columns[c].name, expected[c].name);
    EXPECT_EQ(columns[c].unit, expected[c].unit);
    EXPECT_EQ(columns[c].type, expected[c].type);
    EXPECT_EQ(columns[c].resolution, expected[c].resolution) << columns[c].name;
    EXPECT_EQ(columns[c].doc, expected[c].doc);
  }
  std::vector<double> block, values(kMaxTelemetryColumns);
  std::size_t n = 0, frame = 0, rounded = 0;
  const std::size_t nc = columns.size();
  while (r.nextBlock(block, n)) {
    for (std::size_t i = 0; i < n; ++i, ++frame) {
      telemetryValues(w.frames[frame], values.data());
      for (std::size_t c = 0; c < nc; ++c) {
        const double x = values[c], y = block[i * nc + c];
        if (std::isnan(x)) {
          ASSERT_TRUE(std::isnan(y)) << columns[c].name;
        } else if (columns[c].type == blog::Type::kI32) {
          // Half a step, and the double's rounding of count x step.
          ASSERT_LE(std::abs(y - x), 0.5 * columns[c].resolution * (1 + 1e-9))
              << columns[c].name << " frame " << frame;
          rounded += y != x;
        } else {
          ASSERT_EQ(y, x) << columns[c].name << " frame " << frame;  // exact
        }
      }
    }
  }
  EXPECT_EQ(frame, w.frames.size());
  EXPECT_GT(rounded, 0u);
  std::filesystem::remove(path);
}

TEST(TelemetryColumns, AWalkTakesUnderTheSizeGoal) {
  // Issue 18: 10 minutes at 1 kHz of every column <= 150 MB, 250 bytes per frame. The encoding
  // is deterministic, so the synthetic walk's size is a fixed figure (BM_TelemetryWrite reports
  // it with the writer's time).
  const std::string path = tempFile("size.blog");
  const std::uint64_t bytes = writeWalk(path);
  const double per_frame = double(bytes) / double(test::walkFrames().frames.size());
  std::printf("synthetic walk: %.1f bytes per frame, %.1f MB per 10 minutes at 1 kHz\n", per_frame,
              per_frame * 600000 / 1e6);
  EXPECT_LE(per_frame, 250.0);
  std::filesystem::remove(path);
}

// ballastd(8) lists the columns as the table declares them.
TEST(TelemetryColumns, TheManPageListsTheTable) {
  const std::string man = test::sourceFile("man/ballastd.8");
  const auto intro = man.find("Columns, in file order");
  ASSERT_NE(intro, std::string::npos);
  const auto begin = man.find(".PD 0\n", intro), end = man.find(".PP\n", begin);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(man.substr(begin, end - begin), telemetryColumnsMan())
      << "man/ballastd.8's TELEMETRY columns differ from daemon/control/telemetry_columns.cpp";
}

}  // namespace
}  // namespace ballast::control
