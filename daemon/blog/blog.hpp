// The binary telemetry log (.blog): what `ballast record start FILE.blog` writes, what
// `ballast log` converts. ballast(1) documents the format; this is its one implementation.
//
//   file   = header block*
//   header = magic "\x89BLOG\r\n\x1a" (8 bytes), u32 format version, u32 text length,
//            text, u32 CRC-32 of the text
//   text   = lines "key value": format, profile, robot, start_unix_ns, start_utc,
//            frames_per_block, "limb NAME JOINT..." (format 2: the robot's limbs, each the
//            joints from its root out, for per-limb plots), columns N, then N lines "column NAME UNIT TYPE RESOLUTION DOC" in
//            frame order: TYPE f64, u8, i32 or f32; RESOLUTION the step of an i32 column (in
//            UNIT), "-" for the others; DOC the rest of the line (format 1: "column NAME UNIT
//            TYPE", no i32)
//   block  = u32 "BLK1", u32 frames, u32 raw size, u32 compressed size,
//            u32 CRC-32 of the compressed bytes, the compressed bytes (zstd)
// All integers little-endian. Each block stands alone (its first frame is not a delta), so a
// file cut short (power cut, SIGKILL) reads up to its last complete block.
//
// A column's type says how much of a value is kept. f64 and u8 keep it exactly (the time, the
// operator's commands; the mode and contact flags). i32 keeps it to a stated resolution: the
// nearest multiple of RESOLUTION, as a signed count (NaN, and beyond +-(2^31 - 2) counts -inf
// and +inf, have counts of their own, so they read back as what they were). f32 (format 1's
// physical columns) keeps 24 bits of mantissa. Why fixed point for physical quantities: a
// float's low mantissa bits hold sensor noise, and so do its sign and exponent near zero (a
// joint velocity jittering about 0), so they cost the file most of their 4 bytes (3.3 on a
// MuJoCo walk's joint velocities and torques) for digits nobody reads; a resolution per column,
// chosen below what the robot's sensors and motor protocol resolve (the column table,
// control/telemetry_columns.cpp), drops exactly those.
//
// Inside a block, column after column: each frame's value in the column's type, taken as a
// little-endian integer of its width, minus the previous frame's (0 before the block's first
// frame, modulo the width) and zigzagged (d >= 0 -> 2d, d < 0 -> -2d-1), the column's bytes split
// into planes (every frame's byte 0, then every byte 1, ...), then zstd over the whole block.
// Why: telemetry changes little from one millisecond to the next, so the difference of two
// neighbouring values is small and its high bytes are zero; the planes put those zeros next to
// each other, where zstd takes them for almost nothing. On a recorded MuJoCo walk (170 columns,
// format 1's floats) the difference beat the XOR of Gorilla-style encoders by 11 % (375 against
// 419 bytes per frame), a second difference was worse on the noisy columns, zstd above level 3
// gained little (4 % at level 19) for 20x the time.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace ballast::blog {

/// 2: i32 columns with a resolution, and a doc per column. Format 1 files read as ever.
inline constexpr std::uint32_t kFormatVersion = 2;

enum class Type : std::uint8_t { kF64, kF32, kU8, kI32 };
const char* typeName(Type t);
int typeSize(Type t);

struct Column {
  std::string name, unit;
  Type type = Type::kF64;
  double resolution = 0.0;  ///< kI32: values are kept as the nearest multiple of it (in unit)
  std::string doc;          ///< what the column holds, one line
};

/// x as a column of this description keeps it: what reading it back gives (exact for f64 and
/// NaN, rounded to the resolution for i32, to a float for f32, to an integer 0..255 for u8).
double stored(double x, const Column& c);

/// How each column prints as text (the TSV recording, `ballast log --to tsv|csv`): f64 with 9
/// significant digits, u8 as an integer, f32 in its shortest form as a float (0.1f prints 0.1),
/// i32 as the decimal its resolution allows (0.00123 at 1e-05, trailing zeros dropped), NaN as
/// "NaN" and a saturated i32 as "inf" or "-inf". A value prints as it reads back from a .blog,
/// so the TSV the daemon writes and the TSV converted from a .blog of the same frames are the
/// same text.
class TextFormat {
 public:
  explicit TextFormat(const std::vector<Column>& columns);
  /// Appends value x of column c (no separator).
  void append(std::string& line, std::size_t c, double x) const;

 private:
  struct Cell {
    Type type;
    double resolution;
    int decimals;  // i32 whose resolution is 10^-decimals; INT_MIN for another resolution
  };
  std::vector<Cell> cells_;
};

/// Named lists of the recording's joints (the robot's limbs, for plots).
struct Group {
  std::string name;
  std::vector<std::string> members;
};

struct Header {
  std::uint32_t version = kFormatVersion;
  std::string profile, robot;
  std::vector<Group> limbs;  ///< "limb NAME JOINT..." lines: joint chains out to each leaf
  std::int64_t start_unix_ns = 0;
  std::uint32_t frames_per_block = 1000;
  std::vector<Column> columns;
};

/// Writes a .blog. Everything it needs is allocated in open(); append() allocates nothing (it
/// runs on the telemetry writer thread, which shares the machine with the 1 kHz loop).
class Writer {
 public:
  ~Writer();
  /// Creates (truncating) path and writes the header; false with a message.
  bool open(const std::string& path, const Header& header, std::string& error);
  /// One frame: header.columns.size() values, converted to each column's type.
  void append(const double* values);
  /// Writes the last (partial) block and closes. Returns the bytes in the file.
  std::uint64_t close();
  bool isOpen() const { return file_ != nullptr; }
  std::uint64_t frames() const { return frames_; }
  std::uint64_t bytes() const { return bytes_; }

 private:
  void flushBlock();
  std::FILE* file_ = nullptr;
  std::vector<Column> columns_;
  std::vector<std::size_t> offset_;  // each column's first byte in raw_
  std::uint32_t per_block_ = 0, in_block_ = 0;
  std::size_t raw_size_ = 0;          // a full block's raw bytes
  std::vector<unsigned char> values_;  // this block's values, column after column (not XORed)
  std::vector<unsigned char> raw_, packed_;
  void* cctx_ = nullptr;
  std::uint64_t frames_ = 0, bytes_ = 0;
};

/// Whether path starts with a .blog's magic bytes (a text recording does not).
bool isBinaryLog(const std::string& path);

/// Reads a .blog block by block.
class Reader {
 public:
  ~Reader();
  /// Opens path and reads its header; false with a message (not a .blog, a newer format, a
  /// damaged header).
  bool open(const std::string& path, std::string& error);
  const Header& header() const { return header_; }
  /// The next block's frames into values (frames × columns, frame after frame); false at the
  /// end of the file. truncated() tells whether the end was a damaged or incomplete block.
  bool nextBlock(std::vector<double>& values, std::size_t& frames);
  bool truncated() const { return truncated_; }
  const std::string& truncation() const { return truncation_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  Header header_;
  std::vector<unsigned char> raw_, packed_;
  bool truncated_ = false;
  std::string truncation_;
};


/// What --info prints: the header, frames, duration (from the t column) and size.
struct Summary {
  Header header;
  std::uint64_t frames = 0, bytes = 0;
  double t_first = 0, t_last = 0;
  bool truncated = false;
  std::string truncation;
};
bool summarize(const std::string& path, Summary& summary, std::string& error);

/// What `ballast log FILE --to ...` writes: which format, which columns, which frames.
struct Slice {
  enum class Format { kTsv, kCsv };
  /// kTsv: the TSV recording (ballast(1), as the writer writes FILE.tsv: "# ballast telemetry
  /// 1", "# " and the names, then tab-separated values, NaN where none). kCsv: RFC 4180, one
  /// line of names, then comma-separated values, an empty field where none (what spreadsheets
  /// and pandas take for missing).
  Format format = Format::kTsv;
  /// Shell patterns (fnmatch(3)) naming the columns to keep, in file order, t always first;
  /// empty: every column.
  std::vector<std::string> columns;
  double from = -1.0 / 0.0, to = 1.0 / 0.0;  ///< the frames with from <= t <= to (s)
};

/// The columns the patterns select (indices in file order; t first when the file has it); false
/// with a message naming the first pattern that matches no column.
bool selectColumns(const std::vector<Column>& columns, const std::vector<std::string>& patterns,
                   std::vector<std::size_t>& selected, std::string& error);

/// What convert did: converted; or refused the file (unreadable, not a recording, a newer
/// format) or the slice (a pattern that matches no column); or could not write the text.
enum class Converted { kOk, kBadRecording, kNoSuchColumn, kCannotWrite };

/// Converts a .blog to text on out, as slice says; anything but kOk comes with a message. A
/// truncated file converts up to its last complete block and sets *truncation (if given) to why
/// it ended early. *frames (if given): the frames written.
Converted convert(const std::string& path, std::FILE* out, const Slice& slice, std::string& error,
                  std::string* truncation = nullptr, std::uint64_t* frames = nullptr);

/// The text recording's header (ballastd(8), TELEMETRY): "# ballast telemetry 1", "# " and the
/// tab-separated column names, then "# limb NAME JOINT..." per limb (what a .blog's header
/// says of them), each line ending in '\n'. Readers skip lines starting with '#' after the
/// names.
std::string textHeader(const std::vector<std::string>& names, const std::vector<Group>& limbs);
/// A "# limb NAME JOINT..." line of a text header, read back into limb; false for other lines.
bool parseTextLimb(const std::string& line, Group& limb);

/// CRC-32 (IEEE 802.3, as zlib's crc32).
std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0);

/// "2026-11-24T21:48:02.123Z" for a Unix time in ns.
std::string utcTime(std::int64_t unix_ns);

}  // namespace ballast::blog
