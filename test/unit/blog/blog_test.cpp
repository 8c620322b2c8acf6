// The binary telemetry log: what goes in comes out (exactly for f64 and u8 columns, rounded to
// f32 for f32 columns), a file cut anywhere reads up to its last complete block, a newer format
// version or a damaged block is said so.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "blog/blog.hpp"

namespace ballast::blog {
namespace {

std::string tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("ballast-blog-" + std::to_string(getpid()) + "-" + name);
}

Header header(std::uint32_t per_block) {
  Header h;
  h.profile = "sim-flat";
  h.robot = "humanoid";
  h.start_unix_ns = 1764020882123456789;
  h.frames_per_block = per_block;
  h.columns = {{"t", "s", Type::kF64}, {"mode", "-", Type::kU8}, {"q_knee", "rad", Type::kF32},
               {"tau_knee", "N*m", Type::kF32}};
  return h;
}

std::vector<double> frameValues(int i) {
  const double t = i * 0.001;
  return {t, double(i / 700 % 4), 0.3 * std::sin(6 * t) + 1e-4 * std::cos(977.0 * i),
          i == 5 ? std::nan("") : 40 * std::cos(6 * t)};
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
  ASSERT_EQ(r.header().columns.size(), 4u);
  EXPECT_EQ(r.header().columns[3].name, "tau_knee");
  EXPECT_EQ(r.header().columns[3].unit, "N*m");
  EXPECT_EQ(r.header().columns[2].type, Type::kF32);
  ASSERT_EQ(all.size(), 4u * kFrames);
  for (int i = 0; i < kFrames; ++i) {
    const auto v = frameValues(i);
    EXPECT_EQ(all[4 * i + 0], v[0]) << i;  // f64: bit for bit
    EXPECT_EQ(all[4 * i + 1], v[1]) << i;
    EXPECT_EQ(all[4 * i + 2], double(float(v[2]))) << i;
    if (i == 5)
      EXPECT_TRUE(std::isnan(all[4 * i + 3]));
    else
      EXPECT_EQ(all[4 * i + 3], double(float(v[3]))) << i;
  }

  Summary s;
  ASSERT_TRUE(summarize(path, s, error)) << error;
  EXPECT_EQ(s.frames, std::uint64_t(kFrames));
  EXPECT_DOUBLE_EQ(s.t_last - s.t_first, (kFrames - 1) * 0.001);
  EXPECT_EQ(s.bytes, bytes);
  std::filesystem::remove(path);
}

TEST(Blog, TsvPrintsF32ValuesInTheirShortestForm) {
  std::string line;
  appendTsv(line, double(0.1f), Type::kF32);
  appendTsv(line, 0.1, Type::kF64);
  appendTsv(line, std::nan(""), Type::kF32);
  appendTsv(line, 3.0, Type::kU8);
  EXPECT_EQ(line, "0.1\t0.1\tNaN\t3\t");
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
  EXPECT_NE(error.find("format version 2"), std::string::npos) << error;
  EXPECT_NE(error.find("up to 1"), std::string::npos) << error;
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
