#include "profile/profile.hpp"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace ballast::profile {

namespace fs = std::filesystem;

ProfileError::ProfileError(std::vector<std::string> p)
    : std::runtime_error([&] {
        std::string all;
        for (const auto& line : p) all += (all.empty() ? "" : "\n") + line;
        return all;
      }()),
      problems(std::move(p)) {}

std::string Origin::str() const {
  if (file.empty()) return "default";
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

Origin originOf(const YAML::Node& node, const std::string& file) {
  const YAML::Mark m = node.Mark();
  return Origin{file, m.line + 1, m.column + 1};
}

std::string quote(const YAML::Node& node) { return schema::describe(node); }

/// A value of key k ("" if fine, else what is wrong; mark and key of the part at fault).
bool check(const Key& k, const YAML::Node& node, schema::Problem& problem) {
  schema::Value v;
  return schema::read(k, node, v, problem);
}

/// The value of a key, read (the loader checked it).
schema::Value valueOf(const Key& k, const YAML::Node& node) {
  schema::Value v;
  schema::Problem problem;
  if (!schema::read(k, node, v, problem))
    throw std::logic_error(std::string("profile value of ") + k.name + ": " + problem.what);
  return v;
}

/// The name of a backend's own section: "backend.<name>".
std::string backendSectionName(const std::string& backend) {
  return Key{backendKey()}.section() + "." + backend;
}

std::string resolvePath(const std::string& value, const std::string& file) {
  if (value.empty() || value[0] == '/' || file.empty()) return value;
  return (fs::path(file).parent_path() / value).lexically_normal().string();
}

YAML::Node scalarNode(const std::string& s) {
  return YAML::Node(s);
}

}  // namespace

std::vector<std::string> defaultProfileDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("BALLAST_PROFILE_PATH")) {
    std::stringstream in(env);
    for (std::string d; std::getline(in, d, ':');)
      if (!d.empty()) dirs.push_back(d);
  }
  dirs.push_back(BALLAST_SOURCE_PROFILE_DIR);
  dirs.push_back(BALLAST_INSTALL_PROFILE_DIR);
  return dirs;
}

std::string resolveProfile(const std::string& name, const std::vector<std::string>& dirs) {
  if (name.find('/') != std::string::npos) return name;
  const std::string file =
      name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0 ? name : name + ".yaml";
  std::string searched;
  for (const auto& d : dirs) {
    const std::string candidate = d + "/" + file;
    if (access(candidate.c_str(), R_OK) == 0) return candidate;
    searched += (searched.empty() ? "" : ", ") + d;
  }
  throw ProfileError({"profile '" + name + "': no " + file + " in " + searched +
                      " (give a path, or set BALLAST_PROFILE_PATH)"});
}

/// Reads files into a Profile: bases first, each file overlaid on what came before.
class Loader {
 public:
  Loader(Profile& p, std::vector<std::string> dirs) : p_(p), dirs_(std::move(dirs)) {}

  void file(const std::string& path, bool top) {
    const std::string canonical = fs::weakly_canonical(path).string();
    for (const auto& s : stack_)
      if (s == canonical) {
        std::string chain;
        for (const auto& c : stack_) chain += c + " -> ";
        problems_.push_back(path + ": extends: cycle: " + chain + canonical);
        return;
      }
    std::ifstream in(path);
    if (!in) {
      problems_.push_back(path + ": cannot read it: " + std::strerror(errno));
      return;
    }
    std::vector<std::string>& lines = lines_[path];
    std::string content;
    for (std::string line; std::getline(in, line);) {
      lines.push_back(line);
      content += line + "\n";
    }
    YAML::Node root;
    try {
      root = YAML::Load(content);
    } catch (const YAML::ParserException& e) {
      problems_.push_back(path + ":" + std::to_string(e.mark.line + 1) + ":" +
                          std::to_string(e.mark.column + 1) + ": YAML syntax: " + e.msg);
      return;
    }
    p_.files_.push_back(path);
    if (root.IsNull()) return;  // an empty file is an empty profile
    if (!root.IsMap()) {
      problem(root, path, "", "a profile is a YAML map of sections, got " + quote(root));
      return;
    }
    stack_.push_back(canonical);
    if (const YAML::Node base = root[extendsKey()]) {
      schema::Problem bad;
      const std::string name = base.IsScalar() ? base.Scalar() : "";
      if (!check(*findKey(extendsKey()), base, bad)) {
        problem(bad.mark, path, extendsKey(), bad.what);
      } else if (!name.empty()) {
        std::vector<std::string> dirs{fs::path(path).parent_path().string()};
        dirs.insert(dirs.end(), dirs_.begin(), dirs_.end());
        try {
          const bool isPath = name.find('/') != std::string::npos ||
                              (name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0);
          const std::string basePath =
              isPath ? resolvePath(name, path) : resolveProfile(name, dirs);
          file(basePath, false);
        } catch (const ProfileError& e) {
          problem(base, path, extendsKey(), e.what());
        }
      }
    }
    stack_.pop_back();
    overlayMap(root, "", path, top);
  }

  void finish() {
    // Defaults under everything.
    for (const Key* k : table().keys()) {
      if (k->isMap()) {
        auto& entries = p_.maps_[k->name];
        const YAML::Node def = YAML::Load(k->defaultYaml);
        for (const auto& kv : def)
          entries.emplace(kv.first.Scalar(), Profile::Setting{kv.second, Origin{}});
        continue;
      }
      if (p_.leaves_.count(k->name)) continue;
      const YAML::Node def = *k->defaultYaml ? YAML::Load(k->defaultYaml) : YAML::Node(std::string());
      if (schema::Problem bad; !check(*k, def, bad))
        throw std::logic_error(std::string("schema default of ") + k->name + ": " + bad.what);
      p_.leaves_[k->name] = Profile::Setting{def, Origin{}};
    }
    const std::string backend = p_.leaves_.at(backendKey()).node.Scalar();
    for (const auto& [name, origin] : top_backend_sections_)
      if (name != backendSectionName(backend))
        problems_.push_back(origin.str() + ": " + name +
                            ": unknown key: the backend's own section is named after " +
                            backendKey() + " (" + backendSectionName(backend) + ")");
    if (problems_.empty() && p_.leaves_.at(urdfKey()).node.Scalar().empty())
      problems_.push_back(p_.path_ + ": " + urdfKey() + ": required: the robot model (URDF) to control");
    if (!problems_.empty()) throw ProfileError(problems_);
  }

 private:
  void problem(const YAML::Node& node, const std::string& file, const std::string& key,
               const std::string& what) {
    problem(node.Mark(), file, key, what);
  }
  void problem(const YAML::Mark& mark, const std::string& file, const std::string& key,
               const std::string& what) {
    const Origin at{file, mark.line + 1, mark.column + 1};
    problems_.push_back(at.str() + ": " + (key.empty() ? "" : key + ": ") + what);
  }

  /// A YAML map at `prefix` ("" for the root) in `file`.
  void overlayMap(const YAML::Node& map, const std::string& prefix, const std::string& file,
                  bool top) {
    std::map<std::string, YAML::Mark> seen;
    for (const auto& kv : map) {
      const YAML::Node& keyNode = kv.first;
      if (!keyNode.IsScalar()) {
        problem(keyNode, file, prefix, "keys must be names, got " + quote(keyNode));
        continue;
      }
      const std::string key = prefix.empty() ? keyNode.Scalar() : prefix + "." + keyNode.Scalar();
      if (const auto first = seen.find(keyNode.Scalar()); first != seen.end()) {
        problem(keyNode, file, key,
                "given twice (first at " + Origin{file, first->second.line + 1, first->second.column + 1}.str() + ")");
        continue;
      }
      seen.emplace(keyNode.Scalar(), keyNode.Mark());
      if (key == extendsKey()) continue;  // handled by file()
      overlayValue(keyNode, kv.second, key, file, top);
    }
  }

  void overlayValue(const YAML::Node& keyNode, const YAML::Node& value, const std::string& key,
                    const std::string& file, bool top) {
    if (const Key* k = findKey(key)) {
      if (k->isMap()) {
        if (value.IsNull()) return;
        if (!value.IsMap()) {
          schema::Problem bad;
          check(*k, value, bad);
          problem(bad.mark, file, bad.key, bad.what);
          return;
        }
        auto& entries = p_.maps_[key];
        std::map<std::string, YAML::Mark> seen;
        for (const auto& kv : value) {
          if (!kv.first.IsScalar()) {
            problem(kv.first, file, key, "keys must be names, got " + quote(kv.first));
            continue;
          }
          const std::string entry = kv.first.Scalar();
          if (const auto first = seen.find(entry); first != seen.end()) {
            problem(kv.first, file, key + "." + entry,
                    "given twice (first at " +
                        Origin{file, first->second.line + 1, first->second.column + 1}.str() + ")");
            continue;
          }
          seen.emplace(entry, kv.first.Mark());
          schema::Value v;
          if (schema::Problem bad; !schema::readEntry(*k, entry, kv.second, v, bad)) {
            problem(bad.mark, file, bad.key, bad.what);
            continue;
          }
          entries[entry] = Profile::Setting{kv.second, originOf(kv.first, file)};
        }
        return;
      }
      if (schema::Problem bad; !check(*k, value, bad)) {
        problem(bad.mark, file, bad.key, bad.what);
        return;
      }
      YAML::Node stored;  // a fresh node: assigning to one that aliases `value` rewrites the tree
      if (k->type == KeyType::kPath) {
        stored = scalarNode(resolvePath(value.IsNull() ? "" : value.Scalar(), file));
      } else if (k->type == KeyType::kPaths) {
        stored = YAML::Node(YAML::NodeType::Sequence);
        for (std::size_t i = 0; i < value.size(); ++i)
          stored.push_back(resolvePath(value[i].Scalar(), file));
      } else {
        stored = value;
      }
      p_.leaves_[key] = Profile::Setting{stored, originOf(value, file)};
      return;
    }
    if (isBackendSection(key)) {
      if (!value.IsMap() && !value.IsNull()) {
        problem(value, file, key, "the backend's own section must be a map, got " + quote(value));
        return;
      }
      const Origin o = originOf(keyNode, file);
      p_.section_origins_[key] = o;
      if (top)
        top_backend_sections_[key] = o;
      else
        top_backend_sections_.erase(key);
      if (value.IsMap()) {
        overlaySection(value, key, "", file);
        keepVerbatim(keyNode, value, key, file);
      }
      return;
    }
    if (isSection(key)) {
      if (value.IsNull()) return;
      if (!value.IsMap()) {
        problem(value, file, key, "is a section: expected a map of its keys, got " + quote(value));
        return;
      }
      overlayMap(value, key, file, top);
      return;
    }
    const std::string near = closestKey(key);
    problem(keyNode, file, key,
            "unknown key" + (near.empty() ? std::string() : " (did you mean " + near + "?)") +
                "; ballast-profile(5) lists every key");
  }

  /// A backend's own section: kept as leaves under dotted sub-paths; maps merge, the rest replaces.
  void overlaySection(const YAML::Node& map, const std::string& key, const std::string& sub,
                      const std::string& file) {
    auto& entries = p_.maps_[key];
    for (const auto& kv : map) {
      if (!kv.first.IsScalar()) {
        problem(kv.first, file, key, "keys must be names, got " + quote(kv.first));
        continue;
      }
      const std::string path = sub.empty() ? kv.first.Scalar() : sub + "." + kv.first.Scalar();
      // What this replaces: a value at the same path or a scalar above it; a scalar or list
      // also replaces a map below it (a map merges with one).
      const bool leaf = !kv.second.IsMap();
      for (auto e = entries.begin(); e != entries.end();) {
        const std::string& have = e->first;
        const bool below = leaf && have.rfind(path + ".", 0) == 0;
        const bool above = path.rfind(have + ".", 0) == 0;
        e = (have == path || below || above) ? entries.erase(e) : std::next(e);
      }
      if (kv.second.IsMap())
        overlaySection(kv.second, key, path, file);
      else
        entries[path] = Profile::Setting{kv.second, originOf(kv.first, file)};
    }
  }

  /// The section's own lines in its file (block style only): from the value's first line to
  /// the first later line indented no deeper than the key.
  void keepVerbatim(const YAML::Node& keyNode, const YAML::Node& value, const std::string& key,
                    const std::string& file) {
    p_.section_text_.erase(key);
    if (value.Style() == YAML::EmitterStyle::Flow) return;
    const std::vector<std::string>& lines = lines_[file];
    const int keyColumn = keyNode.Mark().column;
    const int first = value.Mark().line;
    if (first <= keyNode.Mark().line || first >= static_cast<int>(lines.size())) return;
    int end = first + 1;
    for (; end < static_cast<int>(lines.size()); ++end) {
      const std::string& l = lines[end];
      const auto c = l.find_first_not_of(' ');
      if (c == std::string::npos || l[c] == '#') continue;
      if (static_cast<int>(c) <= keyColumn) break;
    }
    std::string text;
    for (int i = first; i < end; ++i) text += lines[i] + "\n";
    p_.section_text_[key] = Profile::BackendSection{text, file + ":" + std::to_string(first + 1)};
  }

  Profile& p_;
  std::map<std::string, std::vector<std::string>> lines_;
  std::vector<std::string> dirs_;
  std::vector<std::string> stack_;
  std::vector<std::string> problems_;
  std::map<std::string, Origin> top_backend_sections_;
};

Profile Profile::load(const std::string& path, const std::vector<std::string>& search_dirs) {
  Profile p;
  p.path_ = fs::absolute(path).lexically_normal().string();
  p.name_ = fs::path(path).stem().string();
  Loader loader(p, search_dirs);
  loader.file(p.path_, true);
  loader.finish();
  return p;
}

// ---- typed access

const Profile::Setting& Profile::leaf(const std::string& key,
                                      std::initializer_list<KeyType> types) const {
  const Key* k = findKey(key);
  if (!k) throw std::logic_error("profile key '" + key + "' is not in the schema");
  bool ok = false;
  for (KeyType t : types) ok |= k->type == t;
  if (!ok)
    throw std::logic_error("profile key '" + key + "' is a " + schema::typeName(k->type) +
                           ", read with the wrong getter");
  return leaves_.at(key);
}

const std::map<std::string, Profile::Setting>& Profile::entries(const std::string& key,
                                                                KeyType type) const {
  const Key* k = findKey(key);
  if (!k || k->type != type)
    throw std::logic_error("profile key '" + key + "' is not a " + schema::typeName(type));
  static const std::map<std::string, Setting> kEmpty;
  const auto it = maps_.find(key);
  return it == maps_.end() ? kEmpty : it->second;
}

bool Profile::flag(const std::string& key) const {
  return leaf(key, {KeyType::kBool}).node.as<bool>();
}

long long Profile::integer(const std::string& key) const {
  return valueOf(*findKey(key), leaf(key, {KeyType::kInteger}).node).integer;
}

double Profile::number(const std::string& key) const {
  return valueOf(*findKey(key), leaf(key, {KeyType::kNumber}).node).number;
}

std::string Profile::text(const std::string& key) const {
  return leaf(key, {KeyType::kString, KeyType::kChoice, KeyType::kPath}).node.Scalar();
}

std::vector<double> Profile::numbers(const std::string& key) const {
  return valueOf(*findKey(key), leaf(key, {KeyType::kNumbers}).node).numbers;
}

std::vector<long long> Profile::integers(const std::string& key) const {
  return valueOf(*findKey(key), leaf(key, {KeyType::kIntegers}).node).integers;
}

std::vector<std::string> Profile::strings(const std::string& key) const {
  const YAML::Node& n = leaf(key, {KeyType::kStrings, KeyType::kPaths}).node;
  std::vector<std::string> out;
  for (std::size_t i = 0; i < n.size(); ++i) out.push_back(n[i].Scalar());
  return out;
}

std::map<std::string, double> Profile::numberMap(const std::string& key) const {
  std::map<std::string, double> out;
  for (const auto& [name, s] : entries(key, KeyType::kNumberMap)) {
    schema::Value v;
    schema::Problem bad;
    schema::readEntry(*findKey(key), name, s.node, v, bad);
    out[name] = v.numberMap[name];
  }
  return out;
}

std::map<std::string, std::vector<std::string>> Profile::groupMap(const std::string& key) const {
  std::map<std::string, std::vector<std::string>> out;
  for (const auto& [name, s] : entries(key, KeyType::kGroupMap)) {
    auto& list = out[name];
    for (std::size_t i = 0; i < s.node.size(); ++i) list.push_back(s.node[i].Scalar());
  }
  return out;
}

YAML::Node Profile::value(const std::string& key) const {
  const Key* k = findKey(key);
  if (!k) throw std::logic_error("profile key '" + key + "' is not in the schema");
  if (!k->isMap()) return leaves_.at(key).node;
  YAML::Node map(YAML::NodeType::Map);
  if (const auto it = maps_.find(key); it != maps_.end())
    for (const auto& [entry, s] : it->second) map[entry] = s.node;
  return map;
}

Origin Profile::origin(const std::string& key) const {
  if (const auto it = leaves_.find(key); it != leaves_.end()) return it->second.origin;
  if (const auto it = section_origins_.find(key); it != section_origins_.end()) return it->second;
  return Origin{};
}

Origin Profile::origin(const std::string& key, const std::string& entry) const {
  if (const auto m = maps_.find(key); m != maps_.end())
    if (const auto e = m->second.find(entry); e != m->second.end()) return e->second.origin;
  return Origin{};
}

std::string Profile::problem(const std::string& key, const std::string& message) const {
  const Origin o = origin(key);
  return (o.file.empty() ? path_ : o.str()) + ": " + key + ": " + message;
}

std::string Profile::problem(const std::string& key, const std::string& entry,
                             const std::string& message) const {
  const Origin o = origin(key, entry);
  return (o.file.empty() ? path_ : o.str()) + ": " + key + "." + entry + ": " + message;
}

std::string Profile::problemAtElement(const std::string& key, std::size_t index,
                                      const std::string& message) const {
  const std::string name = key + "[" + std::to_string(index) + "]";
  const auto it = leaves_.find(key);
  if (it == leaves_.end() || it->second.origin.file.empty() || !it->second.node.IsSequence() ||
      index >= it->second.node.size()) {  // a default: the key's own place
    const Origin o = origin(key);
    return (o.file.empty() ? path_ : o.str()) + ": " + name + ": " + message;
  }
  const YAML::Node element = it->second.node[index];
  return originOf(element, it->second.origin.file).str() + ": " + name + ": " + message;
}

namespace {
/// Rebuilds a YAML map from dotted sub-paths (those under prefix).
YAML::Node unflatten(const std::map<std::string, Profile::Setting>& entries,
                     const std::string& prefix = "") {
  YAML::Node node(YAML::NodeType::Map);
  std::set<std::string> done;
  for (const auto& [path, s] : entries) {
    if (!prefix.empty() && path.rfind(prefix + ".", 0) != 0) continue;
    const std::string rest = prefix.empty() ? path : path.substr(prefix.size() + 1);
    const auto dot = rest.find('.');
    const std::string first = rest.substr(0, dot);
    if (!done.insert(first).second) continue;
    if (dot == std::string::npos)
      node[first] = YAML::Clone(s.node);
    else
      node[first] = unflatten(entries, prefix.empty() ? first : prefix + "." + first);
  }
  return node;
}

std::string flow(const YAML::Node& n) {
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}
}  // namespace

Profile::BackendSection Profile::backendSection() const {
  const std::string key = backendSectionName(text(backendKey()));
  const auto it = maps_.find(key);
  if (it == maps_.end() || it->second.empty()) return {"{}", ""};
  // Verbatim if every key of the merged section comes from the file the text was taken from.
  if (const auto v = section_text_.find(key); v != section_text_.end()) {
    const std::string file = v->second.origin.substr(0, v->second.origin.rfind(':'));
    bool single = true;
    for (const auto& [sub, setting] : it->second) single &= setting.origin.file == file;
    if (single) return v->second;
  }
  YAML::Emitter e;
  e << unflatten(it->second);
  const Origin& o = section_origins_.at(key);
  return {std::string(e.c_str()) + "\n", o.file + ":" + std::to_string(o.line + 1)};
}

std::string Profile::locateBackendProblem(const std::string& message) const {
  const auto it = maps_.find(backendSectionName(text(backendKey())));
  if (it == maps_.end()) return message;
  // Messages read "file:line:column: key: what"; find the key after the location.
  std::size_t pos = 0;
  for (int colons = 0; colons < 3 && pos != std::string::npos; ++colons) {
    pos = message.find(':', pos);
    if (pos != std::string::npos) ++pos;
  }
  if (pos == std::string::npos) return message;
  const std::size_t keyStart = message.find_first_not_of(' ', pos);
  const std::size_t keyEnd = message.find(':', keyStart);
  if (keyStart == std::string::npos || keyEnd == std::string::npos) return message;
  const std::string key = message.substr(keyStart, keyEnd - keyStart);
  const auto e = it->second.find(key);
  if (e == it->second.end()) return message;
  return e->second.origin.str() + ": " + message.substr(keyStart);
}

std::string Profile::describe() const {
  std::ostringstream out;
  out << "# profile " << name_ << " (" << path_ << ")\n";
  std::string section;
  for (const Key& k : schema()) {
    const std::string name = k.name;
    const auto dot = name.find('.');
    const std::string sec = dot == std::string::npos ? "" : name.substr(0, dot);
    const std::string leafName = dot == std::string::npos ? name : name.substr(dot + 1);
    if (sec != section) {
      if (section == "backend") {
        const std::string b = backendSectionName(text(backendKey()));
        out << "  " << text(backendKey()) << ":  # " << origin(b).str() << "\n";
        YAML::Emitter e;
        if (const auto it = maps_.find(b); it != maps_.end()) e << unflatten(it->second);
        std::istringstream yaml(e.c_str());
        for (std::string line; std::getline(yaml, line);) out << "    " << line << "\n";
      }
      section = sec;
      if (!sec.empty()) out << sec << ":\n";
    }
    const std::string indent = sec.empty() ? "" : "  ";
    if (k.isMap()) {
      const auto& e = maps_.at(name);
      out << indent << leafName << ":" << (e.empty() ? " {}" : "") << "\n";
      for (const auto& [entry, s] : e)
        out << indent << "  " << entry << ": " << flow(s.node) << "  # " << s.origin.str() << "\n";
      continue;
    }
    const Setting& s = leaves_.at(name);
    out << indent << leafName << ": " << flow(s.node) << "  # " << s.origin.str() << "\n";
  }
  return out.str();
}

std::vector<std::string> Profile::restartChanges(const Profile& a, const Profile& b) {
  std::vector<std::string> changed;
  for (const Key& k : schema()) {
    if (!k.restart) continue;
    std::string va, vb;
    if (k.isMap()) {
      for (const auto& [e, s] : a.maps_.at(k.name)) va += e + "=" + flow(s.node) + ";";
      for (const auto& [e, s] : b.maps_.at(k.name)) vb += e + "=" + flow(s.node) + ";";
    } else {
      va = flow(a.leaves_.at(k.name).node);
      vb = flow(b.leaves_.at(k.name).node);
    }
    if (va != vb) changed.push_back(std::string(k.name) + " (" + va + " -> " + vb + ")");
  }
  auto section = [](const Profile& p) {
    const auto it = p.maps_.find(backendSectionName(p.text(backendKey())));
    std::string all;
    if (it != p.maps_.end())
      for (const auto& [sub, s] : it->second) all += sub + "=" + flow(s.node) + ";";
    return all;
  };
  if (a.text(backendKey()) == b.text(backendKey()) && section(a) != section(b))
    changed.push_back(backendSectionName(a.text(backendKey())));
  return changed;
}

}  // namespace ballast::profile
