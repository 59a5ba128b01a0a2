// The case file's reader, shared by the parsers of its sections (case_*.cpp), private to io/:
// the validation kit (Reader: every message names the file, line, column and key, or the
// --set that gave the key), overrides, and one function per section of the case file.
#pragma once

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tetcontact/io/case.hpp"
#include "tetcontact/model/names.hpp"

namespace tc::case_file {

namespace fs = std::filesystem;

std::size_t edit_distance(const std::string& a, const std::string& b);

inline std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// Validation context: the file, and which key paths came from --set.
class Reader {
 public:
  Reader(std::string file, std::set<std::string> overridden)
      : file_(std::move(file)), overridden_(std::move(overridden)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& path,
                         const std::string& msg) const {
    std::ostringstream os;
    for (const std::string& o : overridden_)
      if (path == o || path.rfind(o + ".", 0) == 0) {
        os << file_ << ": --set " << o << ": key '" << path << "': " << msg;
        throw CaseError(os.str());
      }
    const YAML::Mark mark = node.Mark();
    os << file_;
    if (mark.line >= 0) os << ":" << mark.line + 1 << ":" << mark.column + 1;
    os << ": key '" << (path.empty() ? "(top level)" : path) << "': " << msg;
    throw CaseError(os.str());
  }

  void map(const YAML::Node& node, const std::string& path) const {
    if (!node.IsMap()) fail(node, path, "expected a mapping (key: value pairs)");
  }

  // Unknown and duplicate keys.
  void keys(const YAML::Node& node, const std::string& path,
            const std::vector<std::string>& allowed) const {
    map(node, path);
    std::set<std::string> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string key = it->first.Scalar();
      if (!seen.insert(key).second) fail(it->first, join(path, key), "duplicate key");
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string best;
        std::size_t best_d = 3;
        for (const std::string& a : allowed)
          if (std::size_t d = edit_distance(key, a); d < best_d) best_d = d, best = a;
        std::string msg = "unknown key";
        if (!best.empty()) msg += " (did you mean '" + best + "'?)";
        msg += "; allowed here: ";
        for (std::size_t i = 0; i < allowed.size(); ++i) msg += (i ? ", " : "") + allowed[i];
        fail(it->first, join(path, key), msg);
      }
    }
  }

  YAML::Node require(const YAML::Node& node, const std::string& path,
                     const std::string& key) const {
    map(node, path);
    const YAML::Node child = node[key];
    if (!child) fail(node, join(path, key), "missing required key");
    return child;
  }

  // A scalar read whole by std::from_chars as T, or a message naming `what`.
  template <class T>
  T scalar(const YAML::Node& node, const std::string& path, const char* what) const {
    if (!node.IsScalar()) fail(node, path, std::string("expected ") + what);
    const std::string& s = node.Scalar();
    T v{};
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || s.empty())
      fail(node, path, std::string("expected ") + what + ", got '" + s + "'");
    return v;
  }

  double number(const YAML::Node& node, const std::string& path) const {
    const double v = scalar<double>(node, path, "a number");
    if (!std::isfinite(v)) fail(node, path, "must be finite, got '" + node.Scalar() + "'");
    return v;
  }

  long integer(const YAML::Node& node, const std::string& path) const {
    return scalar<long>(node, path, "an integer");
  }

  std::string string(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) fail(node, path, "expected a string");
    return node.Scalar();
  }

  bool boolean(const YAML::Node& node, const std::string& path) const {
    const std::string s = node.IsScalar() ? node.Scalar() : "";
    if (s == "true") return true;
    if (s == "false") return false;
    fail(node, path, "expected true or false");
  }

  Vec3 vec3(const YAML::Node& node, const std::string& path) const {
    if (!node.IsSequence() || node.size() != 3)
      fail(node, path, "expected a list of three numbers [x, y, z]");
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = number(node[i], join(path, std::to_string(i)));
    return v;
  }

  // Calls f(entry, "path.i") for each entry of a list.
  template <class F>
  void each(const YAML::Node& list, const std::string& path, const char* what, F&& f) const {
    if (!list.IsSequence()) fail(list, path, std::string("expected a list of ") + what);
    for (std::size_t i = 0; i < list.size(); ++i) f(list[i], join(path, std::to_string(i)));
  }

  double positive(const YAML::Node& node, const std::string& path, const char* unit) const {
    const double v = number(node, path);
    if (!(v > 0.0))
      fail(node, path, "must be positive (" + std::string(unit) + "), got " + node.Scalar());
    return v;
  }

  double non_negative(const YAML::Node& node, const std::string& path) const {
    const double v = number(node, path);
    if (v < 0.0) fail(node, path, "must not be negative, got " + node.Scalar());
    return v;
  }

  int count(const YAML::Node& node, const std::string& path, long lo, long hi) const {
    const long v = integer(node, path);
    if (v < lo || v > hi)
      fail(node, path,
           "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
               std::to_string(v));
    return static_cast<int>(v);
  }

  // A name of `table` (the enum's one name table), or a message listing them.
  template <class E, std::size_t N>
  E choice(const YAML::Node& node, const std::string& path, const NameTable<E, N>& table,
           const std::string& what) const {
    const std::string s = node.IsScalar() ? node.Scalar() : "";
    if (const std::optional<E> v = value_of(table, s)) return *v;
    fail(node, path, what + " must be " + name_list(table) + ", got '" + s + "'");
  }

 private:
  std::string file_;
  std::set<std::string> overridden_;
};

// --set path.to.key=value: navigate (creating maps where keys are missing) and assign; returns
// the key's path.
std::string apply_override(YAML::Node root, const std::string& file, const std::string& text);

// A YAML file, or a CaseError naming FILE:LINE:COL of a syntax error.
YAML::Node load_yaml(const std::string& path, const char* what);

// A region {min, max} (and `extra_keys`).
Region parse_region(const Reader& r, const YAML::Node& n, const std::string& path,
                    const std::vector<std::string>& extra_keys = {});

// One material's keys (a library entry, or a case's material over its entry; `at`: the case's
// own entry, where errors about the material as a whole are reported).
Material parse_material(const Reader& r, const YAML::Node& m, const std::string& p,
                        const YAML::Node* at = nullptr);

// Parameters and expressions (case.cpp): a '='-scalar's value over `names`; the parameters'
// values in file order.
bool is_expression(const YAML::Node& n);
double expression_value(const Reader& r, const YAML::Node& n, const std::string& path,
                        const std::map<std::string, double>& names);
std::vector<std::pair<std::string, double>> parameter_values(const Reader& r,
                                                             const YAML::Node& root);

// The sections, in the order load_case reads them (case.cpp).
std::vector<std::pair<std::string, double>> substitute_parameters(const Reader& r, YAML::Node root);
void read_solver(const Reader& r, const YAML::Node& root, Case& c);  // case_solver
void read_materials(const Reader& r, const YAML::Node& root, Case& c,
                    const fs::path& case_dir);  // case_materials
void read_bodies(const Reader& r, const YAML::Node& root, Case& c,
                 const fs::path& case_dir);                                       // case_bodies
void read_boundary_conditions(const Reader& r, const YAML::Node& root, Case& c);  // case_bodies
void read_walls(const Reader& r, const YAML::Node& root, Case& c);                // case_bodies
void read_symmetry(const Reader& r, const YAML::Node& root, Case& c);             // case_bodies
void read_references(const Reader& r, const YAML::Node& root, Case& c);           // case_references
void read_output(const Reader& r, const YAML::Node& root, Case& c);               // case_solver
void read_gauges(const Reader& r, const YAML::Node& root, Case& c);               // case_solver
void read_contact(const Reader& r, const YAML::Node& root, Case& c);              // case_contact
void read_fracture(const Reader& r, const YAML::Node& root, Case& c);             // case_contact
void read_expect(const Reader& r, const YAML::Node& root, Case& c);               // case_references
void read_campaign(const Reader& r, const YAML::Node& root, Case& c);             // case_campaign
void read_shield_equation(const Reader& r, const YAML::Node& root, Case& c);      // case_shield
// `as_written`: the file before its overrides, for the cells the file itself gives.
void read_mesh_study(const Reader& r, const YAML::Node& root, const YAML::Node& as_written,
                     Case& c);  // case_shield

}  // namespace tc::case_file
