// What a library's validateSettings() returns: which field of the settings it was given is wrong
// (a pointer into that object: a member, or an element of an array member) and what is wrong, in
// plain words. The library knows its fields, not where they come from; the caller (the profile
// layer) names the key that fills the field.
#pragma once

#include <string>

namespace ballast::model {

struct SettingsProblem {
  const void* field = nullptr;
  std::string message;  ///< empty: the settings are fine

  explicit operator bool() const { return !message.empty(); }
};

}  // namespace ballast::model
