// The profile schema: every key a profile may hold, declared once, Redis config.c-style, in the
// table in schema.cpp: its type, default, bounds, unit, doc, restart flag and the field of
// Settings (settings.hpp) it fills; the rules across keys sit beside the rows they relate.
// Loading, validation, the settings' values and defaults, `ballastd --dump-schema` and the
// ballast-profile(5) man page all read this one table (the engine: plugins/common/
// settings_schema.hpp, which the backends' own sections use too).
//
// Keys are "section.name". Numbers with unit "rad" also accept "<x>deg". Lists may have a fixed
// length. Maps (name -> number, name -> list of names) merge entry by entry across `extends`.
// A key marked restart cannot change under a running daemon: `ballast profile use` and SIGHUP
// refuse a profile that changes it.
//
// To add a key: one row in the table (and its field in the settings struct it fills), then
// regenerate the man page (`build/bin/ballastd --dump-schema=man > man/ballast-profile.5`; a
// test compares them).
#pragma once

#include <string>
#include <vector>

#include "common/settings_schema.hpp"  // plugins/common

namespace ballast::profile {

struct Settings;
using Key = schema::Key;
using KeyType = schema::Type;

/// The table.
const schema::Schema<Settings>& table();
/// Its rows, in documentation order.
const std::vector<schema::Row<Settings>>& schema();
/// The key of that name, nullptr if none. "backend.<name>" (the backend's own section) is not
/// in the table under that name: see isBackendSection.
const Key* findKey(const std::string& name);
/// True for "backend.X" where X is not a declared backend key: a backend's own section.
bool isBackendSection(const std::string& name);
/// True if some key starts with name + "." (name is a section).
bool isSection(const std::string& name);
/// The declared key closest to name (for "did you mean ...?"), "" if none is close.
std::string closestKey(const std::string& name);

/// The keys the loader reads itself: the base profile, the backend (its own section is named
/// after the backend), the robot model (required).
const char* extendsKey();
const char* backendKey();
const char* urdfKey();

/// A backend plugin's own section, documented by the plugin (BackendEntry::section_doc).
struct BackendSectionDoc {
  std::string name;  ///< "simbody": the section is backend.simbody
  std::string text;  ///< man page entries, or commented YAML
};

/// ballast-profile(5), generated from the table (troff), with the backends' sections given.
std::string schemaManPage(const std::vector<BackendSectionDoc>& backends = {});
/// Every key with its default and doc, as a commented YAML profile; the backends' sections
/// after it, commented out.
std::string schemaYaml(const std::vector<BackendSectionDoc>& backends = {});

}  // namespace ballast::profile
