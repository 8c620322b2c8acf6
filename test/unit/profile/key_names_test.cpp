// Each profile key is typed once, in its row of the schema's table (daemon/profile/schema.cpp).
// Code that needs a setting reads the field the schema fills; a message names a key through the
// field it concerns (profile::keyOf, ControlSettings::key_of). This test fails listing every
// other place in daemon/ a key name appears, comments aside.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "profile/schema.hpp"
#include "profile/settings.hpp"

namespace ballast::profile {
namespace {

namespace fs = std::filesystem;

/// The file's text with its comments blanked (newlines kept, so lines still count).
std::string withoutComments(const std::string& text) {
  std::string out = text;
  enum { kCode, kLine, kBlock, kString, kChar, kRaw } state = kCode;
  std::string rawEnd;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i], next = i + 1 < text.size() ? text[i + 1] : '\0';
    switch (state) {
      case kCode:
        if (c == '/' && next == '/') {
          state = kLine;
          out[i] = ' ';
        } else if (c == '/' && next == '*') {
          state = kBlock;
          out[i] = ' ';
        } else if (c == 'R' && next == '"' && (i == 0 || !std::isalnum(text[i - 1]))) {
          const std::size_t open = text.find('(', i);
          rawEnd = ")" + text.substr(i + 2, open - i - 2) + "\"";
          state = kRaw;
          i = open;
        } else if (c == '"') {
          state = kString;
        } else if (c == '\'') {
          state = kChar;
        }
        break;
      case kLine:
        if (c == '\n') state = kCode;
        else out[i] = ' ';
        break;
      case kBlock:
        if (c == '*' && next == '/') {
          out[i] = out[i + 1] = ' ';
          ++i;
          state = kCode;
        } else if (c != '\n') {
          out[i] = ' ';
        }
        break;
      case kString:
      case kChar:
        if (c == '\\') ++i;
        else if (c == (state == kString ? '"' : '\'')) state = kCode;
        break;
      case kRaw:
        if (text.compare(i, rawEnd.size(), rawEnd) == 0) {
          i += rawEnd.size() - 1;
          state = kCode;
        }
        break;
    }
  }
  return out;
}

bool namePart(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

TEST(KeyNames, NoKeyIsTypedOutsideTheTable) {
  // The section keys: "section.key" (top-level keys are plain words, like JSON field names).
  std::vector<std::string> keys;
  for (const auto& row : schema())
    if (std::string(row.name).find('.') != std::string::npos) keys.push_back(row.name);
  ASSERT_GT(keys.size(), 100u);

  const fs::path daemon = fs::path(BALLAST_SOURCE_DIR) / "daemon";
  const fs::path table = daemon / "profile" / "schema.cpp";
  std::vector<std::string> hits;
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(daemon)) {
    const fs::path& path = entry.path();
    if (path.extension() != ".cpp" && path.extension() != ".hpp") continue;
    if (path == table) continue;
    ++files;
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    const std::string code = withoutComments(text.str());
    for (const std::string& key : keys)
      for (std::size_t at = code.find(key); at != std::string::npos; at = code.find(key, at + 1)) {
        const char before = at > 0 ? code[at - 1] : ' ';
        const char after = at + key.size() < code.size() ? code[at + key.size()] : ' ';
        if (namePart(before) || before == '.' || namePart(after)) continue;
        const auto line = std::count(code.begin(), code.begin() + static_cast<long>(at), '\n') + 1;
        hits.push_back(fs::relative(path, BALLAST_SOURCE_DIR).string() + ":" +
                       std::to_string(line) + ": " + key);
      }
  }
  EXPECT_GT(files, 50u);
  std::string list;
  for (const auto& h : hits) list += "\n  " + h;
  EXPECT_TRUE(hits.empty()) << "profile keys typed outside daemon/profile/schema.cpp:" << list;
}

TEST(KeyNames, CommentsAreSkippedAndStringsAreNot) {
  EXPECT_EQ(withoutComments("a // b\nc"), "a     \nc");
  EXPECT_EQ(withoutComments("x /* y */ z"), "x         z");
  EXPECT_EQ(withoutComments("s = \"// not a comment\";"), "s = \"// not a comment\";");
  EXPECT_EQ(withoutComments("r = R\"(// raw)\"; // c"), "r = R\"(// raw)\";     ");
}

}  // namespace
}  // namespace ballast::profile
