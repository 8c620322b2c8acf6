// Settings declared as a table, Redis config.c-style: one row per key, and everything about the
// key comes from its row. Shared by ballastd's profile (daemon/profile/schema.cpp) and the
// backend plugins' own sections (plugins/*/..._settings.cpp), so both read and report alike.
//
// A row holds the key's name ("section.key"), type, default (YAML text, read by the same code as
// a profile, so it obeys the bounds too), bounds, unit (choices for a choice), one line of doc,
// documentation group, restart flag, and the field of the settings struct S it fills: a binder
// made from a member-pointer chain,
//
//     number("gait.period", "0.8", 0.2, 2, "s", "gait cycle")
//         .into<&Settings::control, &ControlSettings::locomotion, &LocomotionSettings::walkGait,
//               &gait::Gait::period>()
//
// checked at compile time (a number fills a floating-point field, a choice a string, an enum by
// index, or a bool; a list an std::vector, an std::array or an Eigen vector; ...), or with a
// conversion function for the few fields that need one. A Schema<S> is a list of rows, rules
// across rows (min < max) and aliases (a derived field reported at the key it comes from).
//
// From a Schema: reading a value (read(): type, bounds, length, choices; messages say what is
// wrong, the caller says where), the settings' defaults, the row that fills a given field of an
// S (so problems found later name the key of the field they concern), the rules, and the
// documentation (a text reference, man page entries, a YAML profile of every default).
// parseSection() reads a plugin's section, given as YAML text with its origin "file:line", into
// an S whose base Locations records where each key was written; its errors read
//     file:line:column: key: what is wrong
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace ballast::schema {

enum class Type : unsigned char {
  kBool,
  kInteger,  ///< decimal, or hexadecimal with 0x (CAN ids)
  kNumber,   ///< unit "rad" also takes "<x>deg"
  kString,
  kChoice,  ///< one of the '|'-separated choices in `unit`
  kPath,    ///< a file; the daemon resolves a relative one against the file that sets it
  kNumbers,
  kIntegers,
  kStrings,
  kPaths,
  kNumberMap,  ///< name -> number (joint -> angle, joint group -> gain)
  kGroupMap,   ///< name -> list of names (joint groups)
  kCustom,     ///< read by the row's own function (a plugin's per-motor entries)
  kFrame,      ///< a URDF link, or {link: NAME, offset: [x, y, z], rpy: [r, p, y]} (FrameRef)
  kFrames,     ///< a list of kFrame
};

/// "number", "list of numbers", ...: for messages and the man page.
const char* typeName(Type type);

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

/// What a row declares about its key, whatever settings it fills.
struct Key {
  const char* name = "";
  Type type = Type::kNumber;
  const char* defaultYaml = "";  ///< the default, as YAML text
  double min = -kUnbounded, max = kUnbounded;  ///< of every number in the value
  const char* unit = "";   ///< numbers: the unit; choices: "a|b|c"; frames: "rpy" if oriented
  const char* doc = "";    ///< one line
  const char* group = "";  ///< documentation heading; "": the key's section
  int length = 0;          ///< lists: exact number of elements (0: any)
  bool restart = false;    ///< cannot change on a running daemon

  bool isMap() const { return type == Type::kNumberMap || type == Type::kGroupMap; }
  bool isNumeric() const;
  /// The name up to its first dot ("" for a top-level key).
  std::string section() const;
  /// "[0.1, 30] s", "one of a|b" or "" (for messages and documentation).
  std::string bounds() const;
  /// One word for references: "number", "vec3", "strings", "map", ...
  std::string shortType() const;
};

/// A frame on the robot given by a URDF link, or by a link and a pose in it: the profile's way to
/// name a contact point, an IMU or a lidar without editing a vendor's URDF.
struct FrameRef {
  std::string link;
  std::array<double, 3> offset{};  ///< m, the frame's origin in the link's frame
  std::array<double, 3> rpy{};     ///< rad, its orientation: fixed-axis roll, pitch, yaw (URDF's)

  /// Offset or rotation given: the frame is not the link's own.
  bool placed() const;
  /// The frame's name in the controller's model: the link's, or "<role>@<link>" for a placed
  /// frame (role: left_toe, imu, ...), which no URDF link is named.
  std::string frameName(const std::string& role) const;
  bool operator==(const FrameRef& o) const {
    return link == o.link && offset == o.offset && rpy == o.rpy;
  }
  bool operator!=(const FrameRef& o) const { return !(*this == o); }
};

using NamedNumbers = std::map<std::string, double>;
using NamedLists = std::map<std::string, std::vector<std::string>>;

/// A value read for a key: the member its type uses is set.
struct Value {
  bool flag = false;
  long long integer = 0;
  double number = 0.0;
  std::string text;
  int choice = -1;  ///< index into the choices
  std::vector<double> numbers;
  std::vector<long long> integers;
  std::vector<std::string> strings;
  NamedNumbers numberMap;
  NamedLists groupMap;
  std::vector<FrameRef> frames;  ///< kFrame: one
};

/// What is wrong with a value and where: the node at fault (an element, an entry) and its key
/// ("gravity[2]", "joint_kp.legs").
struct Problem {
  YAML::Mark mark;
  std::string key;
  std::string what;
  YAML::Mark first = YAML::Mark::null_mark();  ///< "given twice": where it was given first
};

/// Reads `node` as a value of `key` into `out`. False, with `problem`, when it is not one.
bool read(const Key& key, const YAML::Node& node, Value& out, Problem& problem);
/// Reads one entry of a map key (`entry` its name) into out.numberMap or out.groupMap.
bool readEntry(const Key& key, const std::string& entry, const YAML::Node& node, Value& out,
               Problem& problem);

/// 'text', "a list of 2", "a map", "nothing": a value as messages show it.
std::string describe(const YAML::Node& node);
/// The candidate closest to `name` when it is a typo (at most 3 edits away), else "".
std::string closest(const std::string& name, const std::vector<std::string>& candidates);

struct SettingsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Where each key of a section was written (a plugin's settings struct derives from it).
struct Locations {
  /// "file:line:column" of each key given (entries of maps and custom keys as "key.entry").
  std::map<std::string, std::string> location;
  std::string origin;  ///< the section's "file:line"

  /// "file:line:column: key: " for a message about key (its location, else the section's).
  std::string where(const std::string& key) const;
};

/// Locations in a YAML text that starts at line `first` of `file` ("file:line" origins).
class Cursor {
 public:
  /// origin "file:line" (or a bare name); `out` records where keys were written (may be null).
  Cursor(const std::string& origin, Locations* out);

  std::string at(const YAML::Mark& mark) const;
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& what) const;
  /// "file:line:column: key: what" for a problem read() reported.
  std::string message(const Problem& problem) const;
  /// A number within [min, max], an integer, a string: else fail() naming `key`.
  double number(const YAML::Node& node, double min, double max, const std::string& key) const;
  long long integer(const YAML::Node& node, double min, double max, const std::string& key) const;
  std::string text(const YAML::Node& node, const std::string& key) const;
  /// Notes where `key` was written (for Locations::where).
  void record(const std::string& key, const YAML::Mark& mark) const;
  /// A map node's keys must be among `allowed` (dotted under `key`), with a suggestion if not.
  void checkKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
                 const std::string& key) const;

 private:
  std::string file_;
  int line_ = 1;
  bool hasLine_ = false;
  Locations* out_;
};

// ---- rows

template <class S>
struct Row : Key {
  void (*store)(S&, const Value&) = nullptr;
  /// The field the row fills in a given S, and its size (a problem about any part of it, an
  /// array's element, is the row's).
  const void* (*field)(const S&) = nullptr;
  std::size_t size = 0;
  /// kCustom: reads its node into S itself, failing through the cursor.
  void (*custom)(S&, const YAML::Node&, const Cursor&) = nullptr;
};

/// A rule across rows: "" when it holds, else what is wrong, reported at `key`.
template <class S>
struct Rule {
  const char* key;
  std::string (*check)(const S&);
};

/// A field no row fills but one derives from a key (the control period from the control rate):
/// problems about it are reported at that key.
template <class S>
struct Alias {
  const char* key;
  const void* (*field)(const S&);
  std::size_t size;
};

/// A row, a rule or an alias: the items of a table, in documentation order.
template <class S>
struct Item {
  Item(Row<S> r) : row(std::move(r)), kind(kRow) {}
  Item(Rule<S> r) : rule(r), kind(kRule) {}
  Item(Alias<S> a) : alias(a), kind(kAlias) {}
  Row<S> row;
  Rule<S> rule{nullptr, nullptr};
  Alias<S> alias{nullptr, nullptr, 0};
  enum Kind { kRow, kRule, kAlias } kind;
};

namespace detail {

template <class M>
struct Member;
template <class C, class T>
struct Member<T C::*> {
  using Class = C;
};

template <auto... M>
struct Chain;
template <auto First, auto... Rest>
struct Chain<First, Rest...> {
  using Root = typename Member<decltype(First)>::Class;
};
template <auto... M>
using RootOf = typename Chain<M...>::Root;

template <auto... M, class R>
auto& follow(R& root) {
  return (root .* ... .* M);
}

template <auto... M>
using FieldOf =
    std::remove_reference_t<decltype(follow<M...>(std::declval<RootOf<M...>&>()))>;

template <class T>
struct IsVector : std::false_type {};
template <class T, class A>
struct IsVector<std::vector<T, A>> : std::true_type {};

template <class F, class E, class = void>
struct Indexable : std::false_type {};
template <class F, class E>
struct Indexable<F, E,
                 std::void_t<decltype(std::declval<F&>()[0] = std::declval<E>()),
                             decltype(std::declval<F&>().size())>> : std::true_type {};

/// Whether a key of type T may fill a field of type F.
template <Type T, class F>
constexpr bool fits() {
  if constexpr (T == Type::kBool) return std::is_same_v<F, bool>;
  if constexpr (T == Type::kInteger) return std::is_integral_v<F> && !std::is_same_v<F, bool>;
  if constexpr (T == Type::kNumber) return std::is_floating_point_v<F>;
  if constexpr (T == Type::kString || T == Type::kPath) return std::is_same_v<F, std::string>;
  if constexpr (T == Type::kChoice)
    return std::is_same_v<F, std::string> || std::is_enum_v<F> || std::is_same_v<F, bool>;
  if constexpr (T == Type::kNumbers)
    return std::is_same_v<F, std::vector<double>> ||
           (!IsVector<F>::value && Indexable<F, double>::value);
  if constexpr (T == Type::kIntegers)
    return IsVector<F>::value && std::is_integral_v<typename F::value_type>;
  if constexpr (T == Type::kStrings || T == Type::kPaths)
    return std::is_same_v<F, std::vector<std::string>> ||
           (!IsVector<F>::value && Indexable<F, std::string>::value);
  if constexpr (T == Type::kNumberMap) return std::is_same_v<F, NamedNumbers>;
  if constexpr (T == Type::kGroupMap) return std::is_same_v<F, NamedLists>;
  if constexpr (T == Type::kFrame) return std::is_same_v<F, FrameRef>;
  if constexpr (T == Type::kFrames)
    return std::is_same_v<F, std::vector<FrameRef>> ||
           (!IsVector<F>::value && Indexable<F, FrameRef>::value);
  return false;
}

/// Stores a value read for a key of type T into a field of type F (fits<T, F>()).
template <Type T, class F>
void assign(F& f, const Value& v) {
  if constexpr (T == Type::kBool) {
    f = v.flag;
  } else if constexpr (T == Type::kInteger) {
    f = static_cast<F>(v.integer);
  } else if constexpr (T == Type::kNumber) {
    f = static_cast<F>(v.number);
  } else if constexpr (T == Type::kString || T == Type::kPath) {
    f = v.text;
  } else if constexpr (T == Type::kChoice) {
    if constexpr (std::is_same_v<F, std::string>)
      f = v.text;
    else if constexpr (std::is_same_v<F, bool>)
      f = v.choice != 0;
    else
      f = static_cast<F>(v.choice);
  } else if constexpr (T == Type::kNumbers || T == Type::kStrings || T == Type::kPaths) {
    const auto& from = [&]() -> const auto& {
      if constexpr (T == Type::kNumbers) return v.numbers;
      else return v.strings;
    }();
    if constexpr (IsVector<F>::value) {
      f = from;
    } else {  // fixed size: the elements given, the rest value-initialised (a vec2 in a Vec3d)
      using E = std::decay_t<decltype(f[0])>;
      for (std::size_t i = 0; i < static_cast<std::size_t>(f.size()); ++i)
        f[i] = i < from.size() ? from[i] : E{};
    }
  } else if constexpr (T == Type::kIntegers) {
    f.assign(v.integers.begin(), v.integers.end());
  } else if constexpr (T == Type::kNumberMap) {
    f = v.numberMap;
  } else if constexpr (T == Type::kGroupMap) {
    f = v.groupMap;
  } else if constexpr (T == Type::kFrame) {
    f = v.frames.empty() ? FrameRef{} : v.frames[0];
  } else if constexpr (T == Type::kFrames) {
    if constexpr (IsVector<F>::value) {
      f = v.frames;
    } else {
      for (std::size_t i = 0; i < static_cast<std::size_t>(f.size()); ++i)
        f[i] = i < v.frames.size() ? v.frames[i] : FrameRef{};
    }
  }
}

template <auto... M>
const void* address(const RootOf<M...>& s) {
  return &follow<M...>(const_cast<RootOf<M...>&>(s));
}

}  // namespace detail

/// A key being declared: finished by into<fields...>() (or custom<S>() for kCustom).
template <Type T>
struct Decl {
  Key key;

  Decl needsRestart() const { return with([](Key& k) { k.restart = true; }); }
  Decl ofLength(int n) const { return with([n](Key& k) { k.length = n; }); }
  Decl inGroup(const char* g) const { return with([g](Key& k) { k.group = g; }); }

  /// The row filling the field at the end of the member-pointer chain M.
  template <auto... M>
  Row<detail::RootOf<M...>> into() const {
    using F = detail::FieldOf<M...>;
    static_assert(detail::fits<T, F>(), "the field's type does not fit the key's type");
    return into<M...>(&detail::assign<T, F>);
  }
  /// The same with a conversion of the value into the field (a list into a struct, say).
  template <auto... M>
  Row<detail::RootOf<M...>> into(void (*convert)(detail::FieldOf<M...>&, const Value&)) const {
    using S = detail::RootOf<M...>;
    Row<S> row;
    static_cast<Key&>(row) = key;
    row.field = &detail::address<M...>;
    row.size = sizeof(detail::FieldOf<M...>);
    // A captureless lambda per instantiation holds `convert` through a static: one per chain.
    static void (*const stored)(detail::FieldOf<M...>&, const Value&) = convert;
    row.store = [](S& s, const Value& v) { stored(detail::follow<M...>(s), v); };
    return row;
  }
  /// kCustom: a row that reads its node itself (and records its own locations).
  template <class S>
  Row<S> custom(void (*read)(S&, const YAML::Node&, const Cursor&)) const {
    Row<S> row;
    static_cast<Key&>(row) = key;
    row.custom = read;
    return row;
  }

 private:
  template <class Edit>
  Decl with(Edit edit) const {
    Decl d = *this;
    edit(d.key);
    return d;
  }
};

// The declarations, one per type; a row keeps to a line or two.
inline Decl<Type::kBool> flag(const char* n, const char* def, const char* doc) {
  return {{n, Type::kBool, def, -kUnbounded, kUnbounded, "", doc}};
}
inline Decl<Type::kInteger> integer(const char* n, const char* def, double lo, double hi,
                                    const char* unit, const char* doc) {
  return {{n, Type::kInteger, def, lo, hi, unit, doc}};
}
inline Decl<Type::kNumber> number(const char* n, const char* def, double lo, double hi,
                                  const char* unit, const char* doc) {
  return {{n, Type::kNumber, def, lo, hi, unit, doc}};
}
inline Decl<Type::kString> text(const char* n, const char* def, const char* doc) {
  return {{n, Type::kString, def, -kUnbounded, kUnbounded, "", doc}};
}
inline Decl<Type::kPath> path(const char* n, const char* def, const char* doc) {
  return {{n, Type::kPath, def, -kUnbounded, kUnbounded, "", doc}};
}
inline Decl<Type::kChoice> choice(const char* n, const char* def, const char* choices,
                                  const char* doc) {
  return {{n, Type::kChoice, def, -kUnbounded, kUnbounded, choices, doc}};
}
inline Decl<Type::kNumbers> numbers(const char* n, const char* def, double lo, double hi,
                                    const char* unit, const char* doc) {
  return {{n, Type::kNumbers, def, lo, hi, unit, doc}};
}
inline Decl<Type::kIntegers> integers(const char* n, const char* def, double lo, double hi,
                                      const char* doc) {
  return {{n, Type::kIntegers, def, lo, hi, "", doc}};
}
inline Decl<Type::kStrings> strings(const char* n, const char* def, const char* doc) {
  return {{n, Type::kStrings, def, -kUnbounded, kUnbounded, "", doc}};
}
inline Decl<Type::kPaths> paths(const char* n, const char* def, const char* doc) {
  return {{n, Type::kPaths, def, -kUnbounded, kUnbounded, "", doc}};
}
inline Decl<Type::kNumberMap> numberMap(const char* n, const char* def, double lo, double hi,
                                        const char* unit, const char* doc) {
  return {{n, Type::kNumberMap, def, lo, hi, unit, doc}};
}
inline Decl<Type::kGroupMap> groupMap(const char* n, const char* def, const char* doc) {
  return {{n, Type::kGroupMap, def, -kUnbounded, kUnbounded, "", doc}};
}
/// A frame: a link name or {link, offset} (and rpy when `rotation`: an IMU, a lidar; a contact
/// point is a point).
inline Decl<Type::kFrame> frame(const char* n, const char* def, bool rotation, const char* doc) {
  return {{n, Type::kFrame, def, -kUnbounded, kUnbounded, rotation ? "rpy" : "", doc}};
}
inline Decl<Type::kFrames> frames(const char* n, const char* def, bool rotation, const char* doc) {
  return {{n, Type::kFrames, def, -kUnbounded, kUnbounded, rotation ? "rpy" : "", doc}};
}
inline Decl<Type::kCustom> custom(const char* n, const char* def, const char* doc) {
  return {{n, Type::kCustom, def, -kUnbounded, kUnbounded, "", doc}};
}

/// An alias: problems about the field at the end of M are reported at `key`.
template <auto... M>
Alias<detail::RootOf<M...>> alias(const char* key) {
  return {key, &detail::address<M...>, sizeof(detail::FieldOf<M...>)};
}

// ---- documentation of a list of keys (any settings type)

/// Entries for a man page: per section (or group) a .SS heading, per key a .TP paragraph with
/// its type, bounds, default and restart flag. `section`: the section the keys live in, put
/// before their names and headings (a backend plugin's "backend.simbody").
std::string manEntries(const std::vector<const Key*>& keys, const std::string& section = "");
/// Every key with its doc, bounds and default, as a commented YAML file.
std::string yamlDefaults(const std::vector<const Key*>& keys);
/// Per group, one line per key: name, type, default, bounds, doc (a plugin header's listing).
std::string textReference(const std::vector<const Key*>& keys);
/// A backend plugin's section for BackendEntry::section_doc: format "man" (manEntries under
/// "backend.NAME"), "yaml" (yamlDefaults under backend: NAME:, every line commented out, to be
/// appended to a profile of defaults), else null. The text stays valid until the next call.
const char* backendSectionDoc(const std::vector<const Key*>& keys, const char* name,
                              const char* format);
/// Text for troff: backslashes and dashes escaped, a leading dot or quote protected.
std::string troff(const std::string& text);

// ---- the table

template <class S>
class Schema {
 public:
  /// `unknownHint` ends the message for an unknown key ("; ballast-profile(5) lists every key").
  explicit Schema(std::vector<Item<S>> items, std::string unknownHint = "")
      : hint_(std::move(unknownHint)) {
    for (Item<S>& item : items) {
      if (item.kind == Item<S>::kRow) rows_.push_back(std::move(item.row));
      if (item.kind == Item<S>::kRule) rules_.push_back(item.rule);
      if (item.kind == Item<S>::kAlias) aliases_.push_back(item.alias);
    }
    for (const Row<S>& r : rows_) keys_.push_back(&r);
    for (const Rule<S>& r : rules_)
      if (!find(r.key)) throw std::logic_error(std::string("rule at unknown key ") + r.key);
  }

  const std::vector<Row<S>>& rows() const { return rows_; }
  const std::vector<Rule<S>>& rules() const { return rules_; }
  /// The rows as plain keys (documentation, Profile).
  const std::vector<const Key*>& keys() const { return keys_; }
  const std::string& unknownHint() const { return hint_; }

  const Row<S>* find(const std::string& name) const {
    for (const Row<S>& r : rows_)
      if (name == r.name) return &r;
    return nullptr;
  }
  /// True if some key starts with name + ".".
  bool isGroup(const std::string& name) const {
    const std::string prefix = name + ".";
    for (const Row<S>& r : rows_)
      if (std::string(r.name).compare(0, prefix.size(), prefix) == 0) return true;
    return false;
  }
  std::string closestKey(const std::string& name) const {
    std::vector<std::string> names;
    for (const Row<S>& r : rows_) names.push_back(r.name);
    return closest(name, names);
  }

  /// The key whose field holds `field` (an address inside `s`, a row's field or part of it, or
  /// an alias's); nullptr if none. Allocates nothing.
  const char* keyOf(const S& s, const void* field) const {
    const char* p = static_cast<const char*>(field);
    for (const Row<S>& r : rows_)
      if (r.field && within(p, r.field(s), r.size)) return r.name;
    for (const Alias<S>& a : aliases_)
      if (within(p, a.field(s), a.size)) return a.key;
    return nullptr;
  }
  /// The key of the field M... (the same in every S).
  template <auto... M>
  const char* keyOf() const {
    return keyOf(probe(), &detail::follow<M...>(const_cast<S&>(probe())));
  }
  /// The key of `field` inside `part`, a copy of the sub-object at M... of an S (a loop's
  /// settings, a server's configuration). Allocates nothing.
  template <auto... M, class Part>
  const char* keyWithin(const Part& part, const void* field) const {
    static_assert(std::is_same_v<Part, detail::FieldOf<M...>>, "part is not the field at M");
    const std::ptrdiff_t offset =
        static_cast<const char*>(field) - reinterpret_cast<const char*>(&part);
    if (offset < 0 || offset >= static_cast<std::ptrdiff_t>(sizeof(Part))) return nullptr;
    const char* base =
        reinterpret_cast<const char*>(&detail::follow<M...>(const_cast<S&>(probe())));
    return keyOf(probe(), base + offset);
  }

  /// Fills every row's field with its default. Throws std::logic_error naming a bad default.
  void applyDefaults(S& s) const {
    for (const Row<S>& r : rows_) {
      if (r.custom) {
        r.custom(s, YAML::Load(r.defaultYaml), Cursor("<built-in default>", nullptr));
        continue;
      }
      Value v;
      Problem p;
      if (!read(r, YAML::Load(*r.defaultYaml ? r.defaultYaml : "\"\""), v, p))
        throw std::logic_error(std::string("default of ") + r.name + ": " + p.what);
      r.store(s, v);
    }
  }
  /// Settings with every default (the schema applied to an empty profile).
  S defaults() const {
    S s{};
    applyDefaults(s);
    return s;
  }
  /// The rules that do not hold: (key, what is wrong), in table order.
  std::vector<std::pair<const char*, std::string>> broken(const S& s) const {
    std::vector<std::pair<const char*, std::string>> out;
    for (const Rule<S>& r : rules_)
      if (std::string what = r.check(s); !what.empty()) out.emplace_back(r.key, std::move(what));
    return out;
  }

 private:
  static bool within(const char* p, const void* begin, std::size_t size) {
    const char* b = static_cast<const char*>(begin);
    return p >= b && p < b + size;
  }
  /// An S to take field addresses in (made once, on first use).
  static const S& probe() {
    static const std::unique_ptr<const S> s = std::make_unique<const S>();
    return *s;
  }

  std::vector<Row<S>> rows_;
  std::vector<Rule<S>> rules_;
  std::vector<Alias<S>> aliases_;
  std::vector<const Key*> keys_;
  std::string hint_;
};

// ---- a plugin's section

namespace detail {
void walkSection(const std::vector<const Key*>& keys, const YAML::Node& map,
                 const std::string& prefix, const Cursor& cursor, Locations& out,
                 const std::string& hint,
                 const std::function<void(const Key&, const YAML::Node&)>& take);
}

/// Reads a section (YAML text starting at `origin`, "file:line") into settings with the
/// schema's defaults under it, then checks the rules. `what` names the section in messages
/// ("the simbody backend section"). Throws SettingsError "file:line:column: key: what is wrong"
/// at the first problem. S derives from Locations.
template <class S>
S parseSection(const Schema<S>& schema, const std::string& yaml, const std::string& origin,
               const std::string& what) {
  S s{};
  schema.applyDefaults(s);
  s.location.clear();
  s.origin = origin;
  const Cursor cursor(origin, &s);
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw SettingsError(cursor.at(e.mark) + ": " + e.msg);
  }
  if (root.IsNull()) return s;
  if (!root.IsMap()) throw SettingsError(cursor.at(root.Mark()) + ": " + what + " must be a map of keys");
  detail::walkSection(schema.keys(), root, "", cursor, s, schema.unknownHint(),
                      [&](const Key& key, const YAML::Node& node) {
                        const Row<S>& row = *schema.find(key.name);
                        if (row.custom) {
                          row.custom(s, node, cursor);
                          return;
                        }
                        Value v;
                        Problem p;
                        if (!read(row, node, v, p)) throw SettingsError(cursor.message(p));
                        row.store(s, v);
                        if (row.isMap() && node.IsMap())
                          for (const auto& e : node)
                            cursor.record(std::string(row.name) + "." + e.first.Scalar(),
                                          e.first.Mark());
                      });
  for (const auto& [key, problem] : schema.broken(s)) throw SettingsError(s.where(key) + problem);
  return s;
}

}  // namespace ballast::schema
