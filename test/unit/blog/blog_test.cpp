// The binary telemetry log: what goes in comes out (exactly for f64 and u8 columns, to the
// resolution for i32 columns, rounded to f32 for format 1's f32 columns), values print as they
// read back, a file cut anywhere reads up to its last complete block, a newer format version or
// a damaged block is said so, format 1 files still read.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "blog/blog.hpp"

namespace ballast::blog {
namespace {

std::string tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("ballast-blog-" + std::to_string(getpid()) + "-" + name);
}

Column column(const char* name, const char* unit, Type type, double resolution = 0,
              const char* doc = "") {
  return {name, unit, type, resolution, doc};
}

Header header(std::uint32_t per_block) {
  Header h;
  h.profile = "sim-flat";
  h.robot = "humanoid";
  h.start_unix_ns = 1764020882123456789;
  h.frames_per_block = per_block;
  h.limbs = {{"left_foot", {"left_hip", "left_knee"}}, {"right_foot", {"right_knee"}}};
  h.columns = {column("t", "s", Type::kF64, 0, "controller time"), column("mode", "-", Type::kU8),
               column("q_knee", "rad", Type::kF32),
               column("tau_knee", "N*m", Type::kI32, 0.01, "joint torque, measured")};
  return h;
}

std::vector<double> frameValues(int i) {
  const double t = i * 0.001;
  return {t, double(i / 700 % 4), 0.3 * std::sin(6 * t) + 1e-4 * std::cos(977.0 * i),
          i == 5 ? std::nan("") : 40 * std::cos(6 * t) + 1e-3 * std::sin(31.0 * i)};
}

std::vector<double> readAll(const std::string& path, Reader& r, std::string& error) {
  std::vector<double> all, block;
  if (!r.open(path, error)) return all;
  std::size_t n = 0;
  while (r.nextBlock(block, n)) all.insert(all.end(), block.begin(), block.end());
  return all;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(Blog, RoundTripsEveryColumnInItsType) {
  const std::string path = tempFile("roundtrip.blog");
  Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, header(100), error)) << error;
  constexpr int kFrames = 2345;  // 23 full blocks and a partial one
  for (int i = 0; i < kFrames; ++i) w.append(frameValues(i).data());
  const std::uint64_t bytes = w.close();
  EXPECT_EQ(bytes, std::filesystem::file_size(path));

  Reader r;
  const auto all = readAll(path, r, error);
  ASSERT_TRUE(error.empty()) << error;
  EXPECT_FALSE(r.truncated());
  EXPECT_EQ(r.header().profile, "sim-flat");
  EXPECT_EQ(r.header().robot, "humanoid");
  EXPECT_EQ(r.header().start_unix_ns, 1764020882123456789);
  ASSERT_EQ(r.header().limbs.size(), 2u);
  EXPECT_EQ(r.header().limbs[0].name, "left_foot");
  EXPECT_EQ(r.header().limbs[0].members, (std::vector<std::string>{"left_hip", "left_knee"}));
  EXPECT_EQ(r.header().limbs[1].members, (std::vector<std::string>{"right_knee"}));
  ASSERT_EQ(r.header().columns.size(), 4u);
  EXPECT_EQ(r.header().columns[3].name, "tau_knee");
  EXPECT_EQ(r.header().columns[3].unit, "N*m");
  EXPECT_EQ(r.header().columns[2].type, Type::kF32);
  EXPECT_EQ(r.header().columns[3].type, Type::kI32);
  EXPECT_EQ(r.header().columns[3].resolution, 0.01);
  EXPECT_EQ(r.header().columns[3].doc, "joint torque, measured");
  EXPECT_EQ(r.header().columns[0].doc, "controller time");
  EXPECT_EQ(r.header().columns[1].doc, "");
  ASSERT_EQ(all.size(), 4u * kFrames);
  for (int i = 0; i < kFrames; ++i) {
    const auto v = frameValues(i);
    EXPECT_EQ(all[4 * i + 0], v[0]) << i;  // f64: bit for bit
    EXPECT_EQ(all[4 * i + 1], v[1]) << i;
    EXPECT_EQ(all[4 * i + 2], double(float(v[2]))) << i;
    if (i == 5) {
      EXPECT_TRUE(std::isnan(all[4 * i + 3]));
    } else {
      EXPECT_LE(std::abs(all[4 * i + 3] - v[3]), 0.005 + 1e-12) << i;
      EXPECT_EQ(all[4 * i + 3], std::round(v[3] / 0.01) * 0.01) << i;
    }
  }

  Summary s;
  ASSERT_TRUE(summarize(path, s, error)) << error;
  EXPECT_EQ(s.frames, std::uint64_t(kFrames));
  EXPECT_DOUBLE_EQ(s.t_last - s.t_first, (kFrames - 1) * 0.001);
  EXPECT_EQ(s.bytes, bytes);
  std::filesystem::remove(path);
}

TEST(Blog, AnI32ColumnKeepsEveryValueToItsResolution) {
  // Resolutions of the column table and an odd one; values of every size and sign, and what
  // has no count: NaN, infinities, values beyond +-(2^31 - 2) counts.
  const double resolutions[] = {1e-6, 1e-5, 1e-3, 1e-2, 0.25, 10};
  std::vector<double> xs = {0.0, -0.0, 1e-9, -1e-9, 0.5, -0.5, 0.1, 1.0 / 3, -2.0 / 3, 3.14159265,
                            -171.5, 1234.5678, 20.0, std::nan(""), HUGE_VAL, -HUGE_VAL};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 2000; ++k) xs.push_back(u(rng) * std::pow(10.0, k % 9 - 4));
  for (const double res : resolutions) {
    const Column c = column("x", "m", Type::kI32, res);
    for (const double x : xs) {
      const double y = stored(x, c);
      if (std::isnan(x)) {
        EXPECT_TRUE(std::isnan(y));
      } else if (std::abs(x / res) >= 2147483646.5) {
        EXPECT_EQ(y, x > 0 ? HUGE_VAL : -HUGE_VAL) << x << " at " << res;
      } else {
        EXPECT_LE(std::abs(y - x), 0.5 * res * (1 + 1e-9)) << x << " at " << res;
        EXPECT_EQ(stored(y, c), y) << x << " at " << res;  // stored again: unchanged
      }
    }
    EXPECT_EQ(stored(2147483645.0 * res, c), 2147483645.0 * res);
    EXPECT_EQ(stored(2147483648.0 * res, c), HUGE_VAL);
    EXPECT_EQ(stored(-2147483648.0 * res, c), -HUGE_VAL);
  }
  // Through a file: the same values back.
  const std::string path = tempFile("resolution.blog");
  Header h = header(1000);
  h.columns = {column("t", "s", Type::kF64)};
  for (const double res : resolutions) h.columns.push_back(column("x", "m", Type::kI32, res));
  Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, h, error)) << error;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    std::vector<double> v = {double(i)};
    for (std::size_t c = 1; c < h.columns.size(); ++c) v.push_back(xs[i]);
    w.append(v.data());
  }
  w.close();
  Reader r;
  const auto all = readAll(path, r, error);
  ASSERT_TRUE(error.empty()) << error;
  const std::size_t n = h.columns.size();
  ASSERT_EQ(all.size(), n * xs.size());
  for (std::size_t i = 0; i < xs.size(); ++i)
    for (std::size_t c = 1; c < n; ++c) {
      const double want = stored(xs[i], h.columns[c]), got = all[i * n + c];
      if (std::isnan(want))
        EXPECT_TRUE(std::isnan(got));
      else
        EXPECT_EQ(got, want) << xs[i] << " at " << h.columns[c].resolution;
    }
  std::filesystem::remove(path);
}

TEST(Blog, ValuesPrintAsTheyReadBack) {
  const std::vector<Column> columns = {
      column("t", "s", Type::kF64),           column("mode", "-", Type::kU8),
      column("f", "-", Type::kF32),           column("q", "rad", Type::kI32, 1e-5),
      column("tau", "N*m", Type::kI32, 0.01), column("big", "m", Type::kI32, 10),
      column("odd", "m", Type::kI32, 0.25)};
  const TextFormat text(columns);
  auto cell = [&](std::size_t c, double x) {
    std::string s;
    text.append(s, c, x);
    return s;
  };
  EXPECT_EQ(cell(0, 0.1), "0.1");
  EXPECT_EQ(cell(0, 12.345678912345), "12.3456789");  // 9 digits, as the TSV always printed
  EXPECT_EQ(cell(1, 3.0), "3");
  EXPECT_EQ(cell(1, std::nan("")), "0");  // a flag keeps no NaN
  EXPECT_EQ(cell(2, double(0.1f)), "0.1");
  EXPECT_EQ(cell(3, 0.00123), "0.00123");
  EXPECT_EQ(cell(3, -0.000004), "0");  // no "-0": the count is printed, not the product
  EXPECT_EQ(cell(3, 0.000004), "0");
  EXPECT_EQ(cell(3, 1.5), "1.5");
  EXPECT_EQ(cell(3, -3.14159265), "-3.14159");
  EXPECT_EQ(cell(3, 12), "12");
  EXPECT_EQ(cell(4, 40.004999), "40");
  EXPECT_EQ(cell(4, -0.07), "-0.07");
  EXPECT_EQ(cell(5, 1234), "1230");
  EXPECT_EQ(cell(6, 1.3), "1.25");
  EXPECT_EQ(cell(3, std::nan("")), "NaN");
  EXPECT_EQ(cell(3, 1e300), "inf");
  EXPECT_EQ(cell(3, -HUGE_VAL), "-inf");
  // The text of a value and of what a .blog gives back for it are the same.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-50, 50);
  for (int k = 0; k < 10000; ++k) {
    const double x = u(rng) * std::pow(10.0, -(k % 6));
    for (std::size_t c = 0; c < columns.size(); ++c)
      ASSERT_EQ(cell(c, x), cell(c, stored(x, columns[c]))) << x << " " << columns[c].name;
  }
}

TEST(Blog, ATruncatedFileReadsUpToItsLastCompleteBlock) {
  const std::string path = tempFile("whole.blog"), cut = tempFile("cut.blog");
  Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, header(100), error)) << error;
  for (int i = 0; i < 1000; ++i) w.append(frameValues(i).data());
  w.close();
  const std::string whole = slurp(path);

  // Cut at every 97th byte past the header: the frames read are the complete blocks before it.
  std::size_t header_end = 0;
  {
    Writer e;
    ASSERT_TRUE(e.open(cut, header(100), error));
    header_end = e.close();
  }
  for (std::size_t size = header_end; size < whole.size(); size += 97) {
    {
      std::ofstream out(cut, std::ios::binary | std::ios::trunc);
      out.write(whole.data(), static_cast<std::streamsize>(size));
    }
    Reader r;
    const auto all = readAll(cut, r, error);
    ASSERT_TRUE(error.empty()) << error;
    EXPECT_EQ(all.size() % 400, 0u) << size;  // whole blocks only
    EXPECT_LT(all.size(), 4000u) << size;
    for (std::size_t i = 0; i < all.size() / 4; ++i)
      ASSERT_EQ(all[4 * i], frameValues(int(i))[0]) << size;
    if (r.truncated()) {
      EXPECT_FALSE(r.truncation().empty());
    }
  }
  {  // 10 bytes short: the last block is lost, the nine before it read
    std::ofstream out(cut, std::ios::binary | std::ios::trunc);
    out.write(whole.data(), static_cast<std::streamsize>(whole.size() - 10));
  }
  {
    Reader r;
    const auto all = readAll(cut, r, error);
    EXPECT_EQ(all.size(), 4u * 900);
    EXPECT_TRUE(r.truncated());
    EXPECT_NE(r.truncation().find("ends inside a block"), std::string::npos) << r.truncation();
  }
  // Cut inside the header: a clear error, no crash.
  for (std::size_t size : {std::size_t(0), std::size_t(5), std::size_t(30), header_end - 1}) {
    {
      std::ofstream out(cut, std::ios::binary | std::ios::trunc);
      out.write(whole.data(), static_cast<std::streamsize>(size));
    }
    Reader r;
    error.clear();
    EXPECT_FALSE(r.open(cut, error)) << size;
    EXPECT_FALSE(error.empty());
  }
  std::filesystem::remove(path);
  std::filesystem::remove(cut);
}

TEST(Blog, ANewerFormatVersionIsAClearError) {
  const std::string path = tempFile("future.blog");
  Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, header(100), error));
  w.append(frameValues(0).data());
  w.close();
  std::string bytes = slurp(path);
  bytes[8] = static_cast<char>(kFormatVersion + 1);  // the u32 version, little-endian
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
  }
  Reader r;
  EXPECT_FALSE(r.open(path, error));
  EXPECT_NE(error.find("format version " + std::to_string(kFormatVersion + 1)), std::string::npos)
      << error;
  EXPECT_NE(error.find("up to " + std::to_string(kFormatVersion)), std::string::npos) << error;
  std::filesystem::remove(path);
}

TEST(Blog, AFormat1FileStillReads) {
  // Format 1: "column NAME UNIT TYPE" lines, no i32; its blocks are as format 2's. The header
  // written by hand before blocks of the current writer.
  const std::string path = tempFile("format1.blog");
  Header h = header(100);
  h.columns.pop_back();  // format 1 had no i32 columns
  Writer w;
  std::string error;
  ASSERT_TRUE(w.open(path, h, error)) << error;
  for (int i = 0; i < 250; ++i) w.append(frameValues(i).data());
  w.close();
  const std::string bytes = slurp(path);
  const std::uint32_t text_size = static_cast<unsigned char>(bytes[12]) |
                                  static_cast<unsigned char>(bytes[13]) << 8;
  const std::string blocks = bytes.substr(16 + text_size + 4);
  const std::string text =
      "format 1\nprofile sim-flat\nrobot humanoid\nstart_unix_ns 1764020882123456789\n"
      "start_utc 2025-11-24T21:48:02.123Z\nframes_per_block 100\ncolumns 3\n"
      "column t s f64\ncolumn mode - u8\ncolumn q_knee rad f32\n";
  auto u32 = [](std::uint32_t v) {
    std::string b(4, '\0');
    for (int i = 0; i < 4; ++i) b[i] = static_cast<char>(v >> (8 * i));
    return b;
  };
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes.substr(0, 8) << u32(1) << u32(static_cast<std::uint32_t>(text.size())) << text
        << u32(crc32(text.data(), text.size())) << blocks;
  }
  Reader r;
  const auto all = readAll(path, r, error);
  ASSERT_TRUE(error.empty()) << error;
  EXPECT_EQ(r.header().version, 1u);
  ASSERT_EQ(r.header().columns.size(), 3u);
  EXPECT_EQ(r.header().columns[2].type, Type::kF32);
  ASSERT_EQ(all.size(), 3u * 250);
  for (int i = 0; i < 250; ++i) {
    EXPECT_EQ(all[3 * i], frameValues(i)[0]);
    EXPECT_EQ(all[3 * i + 2], double(float(frameValues(i)[2])));
  }
  std::filesystem::remove(path);
}

TEST(Blog, NotABlogAndADamagedBlockAreSaidSo) {
  const std::string path = tempFile("damaged.blog");
  {
    std::ofstream out(path);
    out << "# ballast telemetry 1\n# t\n0\n";
  }
  Reader text;
  std::string error;
  EXPECT_FALSE(text.open(path, error));
  EXPECT_NE(error.find("not a ballast binary log"), std::string::npos) << error;

  Writer w;
  ASSERT_TRUE(w.open(path, header(100), error));
  for (int i = 0; i < 300; ++i) w.append(frameValues(i).data());
  w.close();
  std::string bytes = slurp(path);
  bytes[bytes.size() - 10] ^= 0x40;  // inside the last block
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
  }
  Reader r;
  error.clear();
  const auto all = readAll(path, r, error);
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_EQ(all.size(), 4u * 200);
  EXPECT_TRUE(r.truncated());
  EXPECT_NE(r.truncation().find("CRC"), std::string::npos) << r.truncation();
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ballast::blog
