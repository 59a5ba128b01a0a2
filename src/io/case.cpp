#include "tetcontact/io/case.hpp"
#include "tetcontact/io/expression.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

#include "tetcontact/diagnostics/expect.hpp"
#include "tetcontact/io/files.hpp"

namespace tc {
namespace {

namespace fs = std::filesystem;

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string join(const std::string& path, const std::string& key) {
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

 private:
  std::string file_;
  std::set<std::string> overridden_;
};

// --set path.to.key=value: navigate (creating maps where keys are missing) and assign.
std::string apply_override(YAML::Node root, const std::string& file, const std::string& text) {
  const auto eq = text.find('=');
  auto bad = [&](const std::string& msg) -> CaseError {
    return CaseError(file + ": --set " + text + ": " + msg);
  };
  if (eq == std::string::npos || eq == 0) throw bad("expected path.to.key=value");
  const std::string path = text.substr(0, eq), value = text.substr(eq + 1);
  std::vector<std::string> segs;
  std::stringstream ss(path);
  for (std::string seg; std::getline(ss, seg, '.');) {
    if (seg.empty()) throw bad("empty key in path '" + path + "'");
    segs.push_back(seg);
  }
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw bad("cannot parse value '" + value + "' as YAML: " + e.msg);
  }
  if (!parsed || parsed.IsNull()) throw bad("empty value");

  YAML::Node cur = root;
  std::string walked;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const std::string& seg = segs[i];
    const bool last = i + 1 == segs.size();
    YAML::Node next;
    if (cur.IsSequence()) {
      long idx = -1;
      auto [p, ec] = std::from_chars(seg.data(), seg.data() + seg.size(), idx);
      if (ec != std::errc() || p != seg.data() + seg.size() || idx < 0 ||
          static_cast<std::size_t>(idx) >= cur.size())
        throw bad("'" + walked + "' is a list of " + std::to_string(cur.size()) + " entries; '" +
                  seg + "' is not an index into it");
      next.reset(cur[static_cast<std::size_t>(idx)]);
      if (last) {
        cur[static_cast<std::size_t>(idx)] = parsed;
        return path;
      }
    } else if (cur.IsMap() || cur.IsNull() || !cur.IsDefined()) {
      if (last) {
        cur[seg] = parsed;
        return path;
      }
      if (!cur[seg]) cur[seg] = YAML::Node(YAML::NodeType::Map);
      next.reset(cur[seg]);
    } else {
      throw bad("'" + walked + "' is a value, not a mapping or list");
    }
    walked = join(walked, seg);
    cur.reset(next);
  }
  return path;
}

Region parse_region(const Reader& r, const YAML::Node& n, const std::string& path,
                    const std::vector<std::string>& extra_keys = {}) {
  std::vector<std::string> allowed{"min", "max"};
  allowed.insert(allowed.end(), extra_keys.begin(), extra_keys.end());
  r.keys(n, path, allowed);
  Region reg;
  reg.min = r.vec3(r.require(n, path, "min"), join(path, "min"));
  reg.max = r.vec3(r.require(n, path, "max"), join(path, "max"));
  for (int i = 0; i < 3; ++i)
    if (reg.min[i] > reg.max[i]) r.fail(n, path, "min must not exceed max in any coordinate");
  return reg;
}

int parse_split(const Reader& r, const YAML::Node& n, const std::string& path) {
  if (!n[std::string("split")]) return 6;
  const std::string p = join(path, "split");
  const long s = r.integer(n["split"], p);
  if (s != 5 && s != 6 && s != 12)
    r.fail(n["split"], p, "hex split must be 5, 6 or 12, got " + std::to_string(s));
  return static_cast<int>(s);
}

MeshSpec parse_mesh(const Reader& r, const YAML::Node& n, const std::string& path,
                    const fs::path& case_dir) {
  r.keys(n, path, {"box", "plate", "cylinder", "sphere", "file"});
  if (n.size() != 1)
    r.fail(n, path, "give exactly one mesh source: box, plate, cylinder, sphere or file");
  const std::string kind = n.begin()->first.Scalar();
  const YAML::Node g = n.begin()->second;
  const std::string gp = join(path, kind);
  MeshSpec m;
  auto cells3 = [&](const YAML::Node& c, const std::string& p) {
    if (!c.IsSequence() || c.size() != 3) r.fail(c, p, "expected three cell counts [nx, ny, nz]");
    std::array<int, 3> out;
    for (int i = 0; i < 3; ++i) out[i] = r.count(c[i], join(p, std::to_string(i)), 1, 4096);
    return out;
  };
  auto size3 = [&](const YAML::Node& s, const std::string& p) {
    const Vec3 v = r.vec3(s, p);
    if (!(v.minCoeff() > 0.0)) r.fail(s, p, "sizes must be positive (m)");
    return v;
  };
  if (kind == "box") {
    m.kind = MeshSpec::Kind::box;
    r.keys(g, gp, {"size", "cells", "split"});
    m.size = size3(r.require(g, gp, "size"), join(gp, "size"));
    m.cells = cells3(r.require(g, gp, "cells"), join(gp, "cells"));
    m.split = parse_split(r, g, gp);
  } else if (kind == "plate") {
    m.kind = MeshSpec::Kind::plate;
    r.keys(g, gp, {"size", "cells_through_thickness", "split"});
    m.size = size3(r.require(g, gp, "size"), join(gp, "size"));
    m.cells_through_thickness = r.count(r.require(g, gp, "cells_through_thickness"),
                                        join(gp, "cells_through_thickness"), 1, 4096);
    m.split = parse_split(r, g, gp);
  } else if (kind == "cylinder" || kind == "sphere") {
    const bool cyl = kind == "cylinder";
    m.kind = cyl ? MeshSpec::Kind::cylinder : MeshSpec::Kind::sphere;
    if (cyl)
      r.keys(g, gp, {"radius", "height", "cells_across", "cells_axial", "split"});
    else
      r.keys(g, gp,
             {"radius", "cells_across", "split", "refine_toward", "refine_factor", "cell_size",
              "refine_size", "growth"});
    m.radius = r.positive(r.require(g, gp, "radius"), join(gp, "radius"), "m");
    if (!cyl && g["cell_size"]) {
      // Unstructured (Delaunay refinement): sizes instead of a cell count.
      for (const char* k : {"cells_across", "split", "refine_factor"})
        if (g[k])
          r.fail(g[k], join(gp, k),
                 "belongs to the lattice sphere (cells_across); a sphere with cell_size is "
                 "meshed by Delaunay refinement and is graded by refine_size and growth");
      m.cell_size = r.positive(g["cell_size"], join(gp, "cell_size"), "m");
      if (m.cell_size > m.radius)
        r.fail(g["cell_size"], join(gp, "cell_size"), "must not exceed the radius");
      if (g["refine_toward"] || g["refine_size"] || g["growth"]) {
        const YAML::Node t = r.require(g, gp, "refine_toward");
        m.refine_toward = r.vec3(t, join(gp, "refine_toward"));
        if (m.refine_toward.norm() == 0.0)
          r.fail(t, join(gp, "refine_toward"), "must be a non-zero direction, e.g. [1, 0, 0]");
        const YAML::Node z = r.require(g, gp, "refine_size");
        m.refine_size = r.positive(z, join(gp, "refine_size"), "m");
        if (m.refine_size > m.cell_size)
          r.fail(z, join(gp, "refine_size"), "must not exceed cell_size");
        if (m.radius / m.refine_size > 1e4)
          r.fail(z, join(gp, "refine_size"), "must be at least radius / 10^4");
        if (g["growth"]) {
          m.growth = r.number(g["growth"], join(gp, "growth"));
          if (!(m.growth > 0.0 && m.growth <= 1.0))
            r.fail(g["growth"], join(gp, "growth"), "must be in (0, 1]");
        }
      }
      return m;
    }
    for (const char* k : {"refine_size", "growth"})
      if (g[k])
        r.fail(g[k], join(gp, k), "belongs to a sphere with cell_size (Delaunay refinement)");
    m.cells_across = r.count(r.require(g, gp, "cells_across"), join(gp, "cells_across"), 1, 4096);
    if (cyl) {
      m.height = r.positive(r.require(g, gp, "height"), join(gp, "height"), "m");
      m.cells_axial = r.count(r.require(g, gp, "cells_axial"), join(gp, "cells_axial"), 1, 4096);
    }
    m.split = parse_split(r, g, gp);
    if (!cyl && (g["refine_toward"] || g["refine_factor"])) {
      const YAML::Node t = r.require(g, gp, "refine_toward");
      m.refine_toward = r.vec3(t, join(gp, "refine_toward"));
      const Vec3 a = m.refine_toward.cwiseAbs();
      if (!(a.sum() == 1.0 && a.maxCoeff() == 1.0))
        r.fail(t, join(gp, "refine_toward"), "must be one of ±x, ±y, ±z, e.g. [1, 0, 0]");
      const YAML::Node f = r.require(g, gp, "refine_factor");
      m.refine_factor = r.number(f, join(gp, "refine_factor"));
      if (!(m.refine_factor > 0.0 && m.refine_factor <= 1.0))
        r.fail(f, join(gp, "refine_factor"), "must be in (0, 1]");
    }
    if (m.split != 6)
      r.fail(g["split"], join(gp, "split"),
             "a " + kind +
                 " is offered with split 6 only (5 and 12 put slivers in the "
                 "wedge-shaped cells under its curved surface)");
  } else {
    m.kind = MeshSpec::Kind::file;
    std::string rel;
    if (g.IsScalar()) {
      rel = r.string(g, gp);
    } else {
      r.keys(g, gp, {"path", "physical"});
      rel = r.string(r.require(g, gp, "path"), join(gp, "path"));
      if (g["physical"]) m.physical = r.string(g["physical"], join(gp, "physical"));
    }
    const fs::path p =
        (fs::path(rel).is_absolute() ? fs::path(rel) : case_dir / rel).lexically_normal();
    if (!fs::is_regular_file(p)) r.fail(g, gp, "mesh file not found: " + p.string());
    m.file = p.string();
  }
  return m;
}

std::vector<TransformOp> parse_transform(const Reader& r, const YAML::Node& n,
                                         const std::string& path) {
  if (!n.IsSequence())
    r.fail(n, path, "expected a list of operations, e.g. [{scale: 0.001}, {translate: [0,0,0]}]");
  std::vector<TransformOp> ops;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string p = join(path, std::to_string(i));
    const YAML::Node op = n[i];
    r.keys(op, p, {"translate", "rotate", "scale"});
    if (op.size() != 1) r.fail(op, p, "one operation per list entry");
    const std::string kind = op.begin()->first.Scalar();
    const YAML::Node v = op.begin()->second;
    const std::string vp = join(p, kind);
    TransformOp t;
    if (kind == "translate") {
      t.kind = TransformOp::Kind::translate;
      t.vector = r.vec3(v, vp);
    } else if (kind == "scale") {
      t.kind = TransformOp::Kind::scale;
      t.value = r.positive(v, vp, "dimensionless factor");
    } else {
      t.kind = TransformOp::Kind::rotate;
      r.keys(v, vp, {"axis", "degrees"});
      t.vector = r.vec3(r.require(v, vp, "axis"), join(vp, "axis"));
      if (t.vector.norm() == 0.0) r.fail(v["axis"], join(vp, "axis"), "axis must be non-zero");
      t.value = r.number(r.require(v, vp, "degrees"), join(vp, "degrees"));
    }
    ops.push_back(t);
  }
  return ops;
}

// The Steinberg–Guinan block: Y0, Ymax, beta, n, initial_strain, A (1/Pa), B (1/K),
// reference_temperature, melt_temperature (T_m0), gamma0, a. Γ0 defaults to the Mie–Grüneisen
// EOS's (checked in parse_material, after the EOS).
void read_steinberg_guinan(const Reader& r, const YAML::Node& sn, const std::string& sp,
                           SteinbergGuinan& sg) {
  r.map(sn, sp);
  r.keys(sn, sp,
         {"Y0", "Ymax", "beta", "n", "initial_strain", "A", "B", "reference_temperature",
          "melt_temperature", "gamma0", "a", "source"});
  sg.y0 = r.positive(r.require(sn, sp, "Y0"), join(sp, "Y0"), "Pa");
  if (sn["Ymax"]) {
    sg.ymax = r.positive(sn["Ymax"], join(sp, "Ymax"), "Pa");
    if (sg.ymax < sg.y0) r.fail(sn["Ymax"], join(sp, "Ymax"), "Ymax must not be below Y0");
  }
  if (sn["beta"]) sg.beta = r.non_negative(sn["beta"], join(sp, "beta"));
  if (sn["n"]) sg.n = r.positive(sn["n"], join(sp, "n"), "dimensionless");
  if (sn["initial_strain"])
    sg.initial_strain = r.non_negative(sn["initial_strain"], join(sp, "initial_strain"));
  if (sn["A"]) sg.a_pressure = r.non_negative(sn["A"], join(sp, "A"));
  if (sn["B"]) sg.b_temperature = r.non_negative(sn["B"], join(sp, "B"));
  if (sn["reference_temperature"])
    sg.reference_temperature =
        r.positive(sn["reference_temperature"], join(sp, "reference_temperature"), "K");
  if (sn["melt_temperature"]) {
    sg.melt_temperature = r.positive(sn["melt_temperature"], join(sp, "melt_temperature"), "K");
    if (!(sg.melt_temperature > sg.reference_temperature))
      r.fail(sn["melt_temperature"], join(sp, "melt_temperature"),
             "the melt temperature must be above the reference temperature");
  }
  sg.gamma0 = -1.0;  // unset: the EOS's
  if (sn["gamma0"]) sg.gamma0 = r.non_negative(sn["gamma0"], join(sp, "gamma0"));
  if (sn["a"]) sg.a = r.non_negative(sn["a"], join(sp, "a"));
}

// The strength law (`strength: bilinear | johnson_cook | steinberg_guinan`, the constants of
// each) and the temperature's keys. A library entry may carry the constants of several laws
// while its law stays bilinear: the case picks the law.
void read_strength(const Reader& r, const YAML::Node& m, const std::string& p, Material& mat) {
  if (const YAML::Node sn = m["steinberg_guinan"])
    read_steinberg_guinan(r, sn, join(p, "steinberg_guinan"), mat.steinberg_guinan);
  if (const YAML::Node jn = m["johnson_cook"]) {
    const std::string jp = join(p, "johnson_cook");
    r.map(jn, jp);
    r.keys(jn, jp,
           {"A", "B", "n", "C", "reference_strain_rate", "m", "room_temperature",
            "melt_temperature", "source"});
    JohnsonCook& jc = mat.johnson_cook;
    jc.a = r.positive(r.require(jn, jp, "A"), join(jp, "A"), "Pa");
    if (jn["B"]) jc.b = r.non_negative(jn["B"], join(jp, "B"));
    if (jn["n"]) jc.n = r.positive(jn["n"], join(jp, "n"), "dimensionless");
    if (jn["C"]) jc.c = r.non_negative(jn["C"], join(jp, "C"));
    if (jn["reference_strain_rate"])
      jc.reference_rate =
          r.positive(jn["reference_strain_rate"], join(jp, "reference_strain_rate"), "1/s");
    if (jn["m"]) jc.m = r.positive(jn["m"], join(jp, "m"), "dimensionless");
    if (jn["room_temperature"])
      jc.room_temperature = r.positive(jn["room_temperature"], join(jp, "room_temperature"), "K");
    if (jn["melt_temperature"]) {
      jc.melt_temperature = r.positive(jn["melt_temperature"], join(jp, "melt_temperature"), "K");
      if (!(jc.melt_temperature > jc.room_temperature))
        r.fail(jn["melt_temperature"], join(jp, "melt_temperature"),
               "the melt temperature must be above the room temperature");
    }
  }
  if (const YAML::Node sn = m["strength"]) {
    const std::string law = r.string(sn, join(p, "strength"));
    if (law == "bilinear") {
      mat.strength = StrengthModel::bilinear;
    } else if (law == "johnson_cook") {
      if (!m["johnson_cook"])
        r.fail(sn, join(p, "strength"), "johnson_cook needs the material's johnson_cook constants");
      mat.strength = StrengthModel::johnson_cook;
    } else if (law == "steinberg_guinan") {
      if (!m["steinberg_guinan"])
        r.fail(sn, join(p, "strength"),
               "steinberg_guinan needs the material's steinberg_guinan constants");
      mat.strength = StrengthModel::steinberg_guinan;
    } else {
      r.fail(sn, join(p, "strength"),
             "expected bilinear, johnson_cook or steinberg_guinan, got '" + law + "'");
    }
  }
  if (m["specific_heat"])
    mat.specific_heat = r.positive(m["specific_heat"], join(p, "specific_heat"), "J/(kg K)");
  if (const YAML::Node t = m["taylor_quinney"]) {
    mat.taylor_quinney = r.number(t, join(p, "taylor_quinney"));
    if (!(mat.taylor_quinney >= 0.0 && mat.taylor_quinney <= 1.0))
      r.fail(t, join(p, "taylor_quinney"), "the Taylor-Quinney factor must be in [0, 1]");
  }
  if (m["initial_temperature"])
    mat.initial_temperature =
        r.positive(m["initial_temperature"], join(p, "initial_temperature"), "K");
}

// Johnson–Cook's failure constants (`johnson_cook_failure`, a library entry may carry them) and
// the switch `ductile_failure`. The temperatures default to the strength law's.
void read_ductile_failure(const Reader& r, const YAML::Node& m, const std::string& p,
                          Material& mat) {
  JohnsonCookFailure& f = mat.johnson_cook_failure;
  if (const YAML::Node fn = m["johnson_cook_failure"]) {
    const std::string fp = join(p, "johnson_cook_failure");
    r.map(fn, fp);
    r.keys(fn, fp,
           {"D1", "D2", "D3", "D4", "D5", "reference_strain_rate", "room_temperature",
            "melt_temperature", "min_strain", "source"});
    f.d1 = r.number(r.require(fn, fp, "D1"), join(fp, "D1"));
    for (const auto& [key, value] :
         {std::pair{"D2", &f.d2}, {"D3", &f.d3}, {"D4", &f.d4}, {"D5", &f.d5}})
      if (fn[key]) *value = r.number(fn[key], join(fp, key));
    if (fn["reference_strain_rate"])
      f.reference_rate =
          r.positive(fn["reference_strain_rate"], join(fp, "reference_strain_rate"), "1/s");
    if (fn["room_temperature"])
      f.room_temperature = r.positive(fn["room_temperature"], join(fp, "room_temperature"), "K");
    if (fn["melt_temperature"])
      f.melt_temperature = r.positive(fn["melt_temperature"], join(fp, "melt_temperature"), "K");
    if (fn["min_strain"])
      f.min_strain = r.positive(fn["min_strain"], join(fp, "min_strain"), "dimensionless");
  }
  const bool jc = mat.strength == StrengthModel::johnson_cook;
  if (f.room_temperature == 0.0)
    f.room_temperature = jc ? mat.johnson_cook.room_temperature
                         : mat.strength == StrengthModel::steinberg_guinan
                             ? mat.steinberg_guinan.reference_temperature
                             : 293.0;
  if (f.melt_temperature == 0.0)
    f.melt_temperature =
        jc ? mat.johnson_cook.melt_temperature : mat.steinberg_guinan.melt_temperature;
  if (const YAML::Node dn = m["ductile_failure"]) {
    mat.ductile_failure = r.boolean(dn, join(p, "ductile_failure"));
    if (mat.ductile_failure && !m["johnson_cook_failure"])
      r.fail(dn, join(p, "ductile_failure"),
             "ductile failure needs the material's johnson_cook_failure constants (D1 ... D5)");
  }
  if (mat.ductile_failure && f.d5 != 0.0 && !(f.melt_temperature > f.room_temperature))
    r.fail(m["johnson_cook_failure"], join(p, "johnson_cook_failure"),
           "D5 needs a melt temperature above the room temperature: give melt_temperature");
}

// One material's keys: density; elasticity as (youngs_modulus, poisson_ratio) or
// (shear_modulus [, bulk_modulus]); optional strength; optional EOS.
Material parse_material(const Reader& r, const YAML::Node& m, const std::string& p) {
  r.keys(m, p,
         {"from",
          "density",
          "youngs_modulus",
          "poisson_ratio",
          "shear_modulus",
          "bulk_modulus",
          "yield_stress",
          "hardening_modulus",
          "eos",
          "spall_strength",
          "loosening_limit",
          "strength",
          "johnson_cook",
          "steinberg_guinan",
          "specific_heat",
          "taylor_quinney",
          "initial_temperature",
          "erosion_plastic_strain",
          "ductile_failure",
          "johnson_cook_failure"});
  Material mat;
  mat.density = r.positive(r.require(m, p, "density"), join(p, "density"), "kg/m^3");
  const bool by_young = m["youngs_modulus"] || m["poisson_ratio"];
  const bool by_shear = m["shear_modulus"] || m["bulk_modulus"];
  if (by_young && by_shear)
    r.fail(m, p,
           "give either youngs_modulus and poisson_ratio, or shear_modulus (and bulk_modulus)");
  if (by_young) {
    const double e = r.positive(r.require(m, p, "youngs_modulus"), join(p, "youngs_modulus"), "Pa");
    const YAML::Node nu = r.require(m, p, "poisson_ratio");
    const double v = r.number(nu, join(p, "poisson_ratio"));
    if (!(v > -1.0 && v < 0.5))
      r.fail(nu, join(p, "poisson_ratio"),
             "Poisson's ratio must be in (-1, 0.5), got " + nu.Scalar());
    set_elastic_constants(mat, e, v);
  } else if (by_shear) {
    mat.shear_modulus =
        r.positive(r.require(m, p, "shear_modulus"), join(p, "shear_modulus"), "Pa");
    if (m["bulk_modulus"])
      mat.bulk_modulus = r.positive(m["bulk_modulus"], join(p, "bulk_modulus"), "Pa");
  } else {
    r.fail(m, p, "missing elastic constants: youngs_modulus and poisson_ratio, or shear_modulus");
  }
  if (m["yield_stress"])
    mat.yield_stress = r.non_negative(m["yield_stress"], join(p, "yield_stress"));
  if (m["hardening_modulus"]) {
    mat.hardening_modulus = r.non_negative(m["hardening_modulus"], join(p, "hardening_modulus"));
    if (mat.yield_stress == 0.0)
      r.fail(m["hardening_modulus"], join(p, "hardening_modulus"),
             "hardening needs a yield_stress > 0");
  }
  read_strength(r, m, p, mat);
  if (const YAML::Node e = m["eos"]) {
    const std::string ep = join(p, "eos");
    r.map(e, ep);
    const std::string type = r.string(r.require(e, ep, "type"), join(ep, "type"));
    if (type == "linear") {
      r.keys(e, ep, {"type"});
    } else if (type == "mie_gruneisen") {
      r.keys(e, ep, {"type", "c0", "s", "gamma0"});
      mat.eos = EosKind::mie_gruneisen;
      mat.c0 = r.positive(r.require(e, ep, "c0"), join(ep, "c0"), "m/s");
      mat.s = r.non_negative(r.require(e, ep, "s"), join(ep, "s"));
      mat.gamma0 = r.non_negative(r.require(e, ep, "gamma0"), join(ep, "gamma0"));
      mat.bulk_modulus = mat.density * mat.c0 * mat.c0;  // K0 = ρ0 c0²
    } else {
      r.fail(e["type"], join(ep, "type"),
             "EOS type must be linear or mie_gruneisen, got '" + type + "'");
    }
  }
  if (mat.bulk_modulus <= 0.0)
    r.fail(m, p,
           "no bulk modulus: give bulk_modulus, youngs_modulus and poisson_ratio, or a "
           "mie_gruneisen eos");
  if (SteinbergGuinan& sg = mat.steinberg_guinan; sg.gamma0 < 0.0) {
    if (sg.melt_temperature > 0.0 && mat.eos != EosKind::mie_gruneisen)
      r.fail(m["steinberg_guinan"], join(p, "steinberg_guinan"),
             "the melt law needs gamma0: give steinberg_guinan.gamma0 or a mie_gruneisen eos");
    sg.gamma0 = mat.gamma0;
  }
  if (m["spall_strength"])
    mat.spall_strength = r.non_negative(m["spall_strength"], join(p, "spall_strength"));
  if (m["erosion_plastic_strain"])
    mat.erosion_plastic_strain =
        r.non_negative(m["erosion_plastic_strain"], join(p, "erosion_plastic_strain"));
  read_ductile_failure(r, m, p, mat);
  if (const YAML::Node l = m["loosening_limit"]) {
    mat.loosening_limit = r.number(l, join(p, "loosening_limit"));
    if (!(mat.loosening_limit > 0.0 && mat.loosening_limit < 1.0))
      r.fail(l, join(p, "loosening_limit"),
             "the loosening limit chi* = 1 - V0/V must be in (0, 1), got " + l.Scalar());
  }
  return mat;
}

// A YAML file, or a CaseError naming FILE:LINE:COL of a syntax error.
YAML::Node load_yaml(const std::string& path, const char* what) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    std::ostringstream os;
    os << path << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
       << ": YAML syntax error: " << e.msg;
    throw CaseError(os.str());
  } catch (const YAML::Exception& e) {
    throw CaseError(path + ": cannot read " + what + ": " + e.msg);
  }
}

}  // namespace

std::string default_material_library() {
  return data_dir() + "/materials.yaml";
}

std::vector<Material> load_material_library(const std::string& path) {
  if (!fs::is_regular_file(path)) throw CaseError(path + ": material library not found");
  const YAML::Node root = load_yaml(path, "material library");
  const Reader r(path, {});
  r.map(root, "");
  std::vector<Material> out;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const YAML::Node entry = it->second;
    if (entry.IsMap() && entry["from"])
      r.fail(entry["from"], it->first.Scalar() + ".from", "a library entry cannot use from");
    Material m = parse_material(r, entry, it->first.Scalar());
    m.name = it->first.Scalar();
    out.push_back(m);
  }
  return out;
}

const std::vector<std::string>& known_output_fields() {
  static const std::vector<std::string> f = {
      "displacement", "velocity",  "stress",         "pressure",
      "body",         "von_mises", "plastic_strain", "internal_energy",
      "viscosity",    "damage",    "temperature",    "ductile_damage"};
  return f;
}

const Material& Case::material(const std::string& n) const {
  for (const Material& m : materials)
    if (m.name == n) return m;
  throw CaseError(file + ": unknown material '" + n + "'");
}

namespace {

// The case's solver section: CFL, step limit, viscosity, average nodal pressure.
void read_solver(const Reader& r, const YAML::Node& root, Case& c) {
  if (const YAML::Node s = root["solver"]) {
    r.keys(s, "solver",
           {"cfl", "max_steps", "threads", "viscosity", "average_nodal_pressure",
            "anp_stabilization"});
    if (s["cfl"]) {
      c.cfl = r.number(s["cfl"], "solver.cfl");
      if (!(c.cfl > 0.0 && c.cfl <= 1.0))
        r.fail(s["cfl"], "solver.cfl", "CFL factor must be in (0, 1], got " + s["cfl"].Scalar());
    }
    if (s["max_steps"]) {
      c.max_steps = r.integer(s["max_steps"], "solver.max_steps");
      if (c.max_steps < 1) r.fail(s["max_steps"], "solver.max_steps", "must be at least 1");
    }
    if (const YAML::Node t = s["threads"]) {
      if (!(t.IsScalar() && t.Scalar() == "auto")) {
        const long n = r.integer(t, "solver.threads");
        if (n < 1 || n > 4096)
          r.fail(t, "solver.threads", "expected auto or an integer in [1, 4096]");
        c.threads = static_cast<int>(n);
      }
    }
    if (const YAML::Node q = s["viscosity"]) {
      r.keys(q, "solver.viscosity", {"linear", "quadratic"});
      if (q["linear"]) c.viscosity_linear = r.non_negative(q["linear"], "solver.viscosity.linear");
      if (q["quadratic"])
        c.viscosity_quadratic = r.non_negative(q["quadratic"], "solver.viscosity.quadratic");
    }
    if (const YAML::Node a = s["average_nodal_pressure"]) {
      const std::string v = a.IsScalar() ? a.Scalar() : "";
      if (v == "auto")
        c.average_nodal_pressure = AnpMode::automatic;
      else if (v == "true")
        c.average_nodal_pressure = AnpMode::on;
      else if (v == "false")
        c.average_nodal_pressure = AnpMode::off;
      else
        r.fail(a, "solver.average_nodal_pressure", "expected auto, true or false");
    }
    if (const YAML::Node a = s["anp_stabilization"]) {
      c.anp_stabilization = r.number(a, "solver.anp_stabilization");
      if (!(c.anp_stabilization >= 0.0 && c.anp_stabilization <= 1.0))
        r.fail(a, "solver.anp_stabilization", "must be in [0, 1], got " + a.Scalar());
    }
  }
}

// The case's materials, each from the library (`from`) with the case's keys over it.
void read_materials(const Reader& r, const YAML::Node& root, Case& c, const fs::path& case_dir) {
  // Materials (a library entry named by `from`, with the case's keys over it).
  const YAML::Node mats = r.require(root, "", "materials");
  r.map(mats, "materials");
  if (mats.size() == 0) r.fail(mats, "materials", "define at least one material");
  std::string library_path;
  if (root["material_library"]) {
    const std::string rel = r.string(root["material_library"], "material_library");
    library_path =
        (fs::path(rel).is_absolute() ? fs::path(rel) : case_dir / rel).lexically_normal().string();
    if (!fs::is_regular_file(library_path))
      r.fail(root["material_library"], "material_library", "file not found: " + library_path);
  }
  YAML::Node library;
  bool library_loaded = false;
  for (auto it = mats.begin(); it != mats.end(); ++it) {
    const std::string name = it->first.Scalar();
    const std::string p = join("materials", name);
    YAML::Node m = it->second;
    if (m.IsMap() && m["from"]) {
      const std::string from = r.string(m["from"], join(p, "from"));
      if (!library_loaded) {
        if (library_path.empty()) {  // the shipped library, found only when a case needs it
          try {
            library_path = default_material_library();
          } catch (const std::runtime_error& e) {
            r.fail(m["from"], join(p, "from"), e.what());
          }
        }
        load_material_library(library_path);  // validates it, naming its own lines
        library = YAML::LoadFile(library_path);
        c.material_library = library_path;
        library_loaded = true;
      }
      const YAML::Node& lib = library;  // const: a lookup must not add the key
      if (!lib[from]) {
        std::string names;
        for (auto e = library.begin(); e != library.end(); ++e)
          names += (names.empty() ? "" : ", ") + e->first.Scalar();
        r.fail(m["from"], join(p, "from"),
               "no material '" + from + "' in " + library_path + " (it has: " + names + ")");
      }
      YAML::Node merged = YAML::Clone(lib[from]);
      for (auto kv = m.begin(); kv != m.end(); ++kv)
        if (kv->first.Scalar() != "from") merged[kv->first.Scalar()] = kv->second;
      // The case's own yield_stress or hardening_modulus are the bilinear law's constants: they
      // select it over the entry's law unless the case names a law itself.
      if ((m["yield_stress"] || m["hardening_modulus"]) && !m["strength"])
        merged["strength"] = "bilinear";
      m = merged;
    }
    Material mat = parse_material(r, m, p);
    mat.name = name;
    for (const Material& other : c.materials)
      if (other.name == name) r.fail(it->first, p, "duplicate material name");
    c.materials.push_back(mat);
  }
}

// The case's bodies: name, material, mesh, transform, velocities.
void read_bodies(const Reader& r, const YAML::Node& root, Case& c, const fs::path& case_dir) {
  // Bodies.
  const YAML::Node bodies = r.require(root, "", "bodies");
  if (!bodies.IsSequence() || bodies.size() == 0)
    r.fail(bodies, "bodies", "expected a non-empty list of bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string p = join("bodies", std::to_string(i));
    const YAML::Node b = bodies[i];
    r.keys(b, p,
           {"name", "material", "mesh", "transform", "velocity", "angular_velocity",
            "velocity_regions"});
    BodySpec body;
    body.name = r.string(r.require(b, p, "name"), join(p, "name"));
    for (const BodySpec& other : c.bodies)
      if (other.name == body.name) r.fail(b["name"], join(p, "name"), "duplicate body name");
    const YAML::Node mat = r.require(b, p, "material");
    body.material = r.string(mat, join(p, "material"));
    if (std::none_of(c.materials.begin(), c.materials.end(),
                     [&](const Material& m) { return m.name == body.material; }))
      r.fail(mat, join(p, "material"), "no material named '" + body.material + "' in materials");
    body.mesh = parse_mesh(r, r.require(b, p, "mesh"), join(p, "mesh"), case_dir);
    if (b["transform"]) body.transform = parse_transform(r, b["transform"], join(p, "transform"));
    if (b["velocity"]) body.velocity = r.vec3(b["velocity"], join(p, "velocity"));
    if (b["angular_velocity"])
      body.angular_velocity = r.vec3(b["angular_velocity"], join(p, "angular_velocity"));
    if (const YAML::Node vr = b["velocity_regions"]) {
      const std::string vp = join(p, "velocity_regions");
      if (!vr.IsSequence()) r.fail(vr, vp, "expected a list of {min, max, velocity}");
      for (std::size_t k = 0; k < vr.size(); ++k) {
        const std::string kp = join(vp, std::to_string(k));
        VelocityRegion reg;
        reg.region = parse_region(r, vr[k], kp, {"velocity"});
        reg.velocity = r.vec3(r.require(vr[k], kp, "velocity"), join(kp, "velocity"));
        body.velocity_regions.push_back(reg);
      }
    }
    c.bodies.push_back(std::move(body));
  }
}

// The case's boundary conditions: fixed or prescribed velocity components on a body's region.
void read_boundary_conditions(const Reader& r, const YAML::Node& root, Case& c) {
  // Boundary conditions.
  if (const YAML::Node bcs = root["boundary_conditions"]) {
    r.each(bcs, "boundary_conditions", "boundary conditions",
           [&](const YAML::Node& n, const std::string& p) {
             r.keys(n, p, {"body", "region", "type", "velocity", "components"});
             BoundarySpec bc;
             bc.key = p;
             const YAML::Node body = r.require(n, p, "body");
             bc.body = r.string(body, join(p, "body"));
             if (std::none_of(c.bodies.begin(), c.bodies.end(),
                              [&](const BodySpec& b) { return b.name == bc.body; }))
               r.fail(body, join(p, "body"), "no body named '" + bc.body + "'");
             if (n["region"]) bc.region = parse_region(r, n["region"], join(p, "region"));
             const YAML::Node type = r.require(n, p, "type");
             const std::string t = r.string(type, join(p, "type"));
             if (t != "fixed" && t != "velocity")
               r.fail(type, join(p, "type"), "type must be 'fixed' or 'velocity', got '" + t + "'");
             bc.fixed = t == "fixed";
             if (bc.fixed && n["velocity"])
               r.fail(n["velocity"], join(p, "velocity"), "a fixed condition takes no velocity");
             if (!bc.fixed) bc.velocity = r.vec3(r.require(n, p, "velocity"), join(p, "velocity"));
             if (const YAML::Node comp = n["components"]) {
               const std::string cp = join(p, "components");
               if (!comp.IsSequence() || comp.size() == 0)
                 r.fail(comp, cp, "expected a list of components, e.g. [x, z]");
               bc.components = {false, false, false};
               for (std::size_t k = 0; k < comp.size(); ++k) {
                 const std::string s = r.string(comp[k], join(cp, std::to_string(k)));
                 if (s != "x" && s != "y" && s != "z")
                   r.fail(comp[k], join(cp, std::to_string(k)), "component must be x, y or z");
                 bc.components[s[0] - 'x'] = true;
               }
             }
             c.boundary_conditions.push_back(bc);
           });
  }
}

// The case's rigid walls.
void read_walls(const Reader& r, const YAML::Node& root, Case& c) {
  // Rigid walls.
  if (const YAML::Node walls = root["walls"]) {
    r.each(walls, "walls", "walls", [&](const YAML::Node& n, const std::string& p) {
      r.keys(n, p, {"name", "point", "normal", "friction"});
      RigidWall w;
      w.name = n["name"] ? r.string(n["name"], join(p, "name"))
                         : "wall-" + std::to_string(c.walls.size());
      w.point = r.vec3(r.require(n, p, "point"), join(p, "point"));
      w.normal = r.vec3(r.require(n, p, "normal"), join(p, "normal"));
      if (w.normal.norm() == 0.0) r.fail(n["normal"], join(p, "normal"), "normal must be non-zero");
      w.normal.normalize();
      if (n["friction"]) w.friction = r.non_negative(n["friction"], join(p, "friction"));
      c.walls.push_back(w);
    });
  }
}

// The case's reference values and measures.
void read_references(const Reader& r, const YAML::Node& root, Case& c) {
  // A body the case has, by name.
  const auto body_name = [&](const YAML::Node& node, const std::string& path) {
    const std::string name = r.string(node, path);
    if (std::none_of(c.bodies.begin(), c.bodies.end(),
                     [&](const BodySpec& s) { return s.name == name; }))
      r.fail(node, path, "no body named '" + name + "'");
    return name;
  };
  // Reference values.
  if (const YAML::Node refs = root["reference"]) {
    r.each(refs, "reference", "reference values", [&](const YAML::Node& n, const std::string& p) {
      r.keys(n, p,
             {"name", "measure", "body", "axis", "component", "region", "area", "plane",
              "debris_of", "within", "time", "value", "tolerance", "source", "kind"});
      ReferenceSpec ref;
      ref.name = r.string(r.require(n, p, "name"), join(p, "name"));
      if (n["kind"]) {
        ref.kind = r.string(n["kind"], join(p, "kind"));
        if (ref.kind != "physical" && ref.kind != "regression")
          r.fail(n["kind"], join(p, "kind"), "kind must be physical or regression");
      }
      const YAML::Node m = r.require(n, p, "measure");
      const std::string measure = r.string(m, join(p, "measure"));
      using M = ReferenceSpec::Measure;
      if (measure == "length")
        ref.measure = M::length;
      else if (measure == "radius")
        ref.measure = M::radius;
      else if (measure == "mean_stress")
        ref.measure = M::mean_stress;
      else if (measure == "mean_pressure")
        ref.measure = M::mean_pressure;
      else if (measure == "velocity")
        ref.measure = M::velocity;
      else if (measure == "contact_duration")
        ref.measure = M::contact_duration;
      else if (measure == "contact_max_force")
        ref.measure = M::contact_max_force;
      else if (measure == "contact_mean_pressure")
        ref.measure = M::contact_mean_pressure;
      else if (measure == "hole_diameter")
        ref.measure = M::hole_diameter;
      else if (measure == "mass_through")
        ref.measure = M::mass_through;
      else if (measure == "momentum_through")
        ref.measure = M::momentum_through;
      else if (measure == "perforated")
        ref.measure = M::perforated;
      else if (measure == "debris_speed")
        ref.measure = M::debris_speed;
      else if (measure == "debris_cone_angle")
        ref.measure = M::debris_cone_angle;
      else if (measure == "debris_particle_mass")
        ref.measure = M::debris_particle_mass;
      else if (measure == "largest_fragment")
        ref.measure = M::largest_fragment;
      else
        r.fail(m, join(p, "measure"),
               "measure must be length, radius, mean_stress, mean_pressure, velocity, "
               "contact_duration, contact_max_force, contact_mean_pressure, hole_diameter, "
               "mass_through, momentum_through, perforated, debris_speed, debris_cone_angle, "
               "debris_particle_mass or largest_fragment");
      const bool debris = ref.measure >= M::mass_through;
      for (const char* k : {"plane", "debris_of", "within"})
        if (!debris && n[k])
          r.fail(n[k], join(p, k),
                 "only the debris measures (perforated, mass_through, ...) take it");
      if (ref.measure == M::contact_duration || ref.measure == M::contact_max_force) {
        // whole-run figures: nothing more to say
      } else if (debris) {
        ref.body = body_name(r.require(n, p, "body"), join(p, "body"));
        const std::string pp = join(p, "plane");
        const YAML::Node pl = r.require(n, p, "plane");
        r.map(pl, pp);
        r.keys(pl, pp, {"point", "normal"});
        ref.plane_point = r.vec3(r.require(pl, pp, "point"), join(pp, "point"));
        const Vec3 normal = r.vec3(r.require(pl, pp, "normal"), join(pp, "normal"));
        if (normal.norm() == 0.0) r.fail(pl["normal"], join(pp, "normal"), "must be non-zero");
        ref.plane_normal = normal.normalized();
        if (n["within"]) ref.within = r.positive(n["within"], join(p, "within"), "m");
        if (const YAML::Node of = n["debris_of"])
          r.each(of, join(p, "debris_of"), "body names",
                 [&](const YAML::Node& e, const std::string& ep) {
                   ref.debris_of.push_back(body_name(e, ep));
                 });
      } else if (ref.measure == M::contact_mean_pressure) {
        ref.area = r.positive(r.require(n, p, "area"), join(p, "area"), "m^2");
      } else if (ref.measure == M::length || ref.measure == M::radius ||
                 ref.measure == M::velocity || ref.measure == M::hole_diameter) {
        ref.body = body_name(r.require(n, p, "body"), join(p, "body"));
        const YAML::Node a = r.require(n, p, "axis");
        const std::string axis = r.string(a, join(p, "axis"));
        if (axis != "x" && axis != "y" && axis != "z")
          r.fail(a, join(p, "axis"), "axis must be x, y or z");
        ref.axis = axis[0] - 'x';
        if (ref.measure == M::hole_diameter) {
          const Region reg = parse_region(r, r.require(n, p, "region"), join(p, "region"));
          ref.region_min = reg.min;
          ref.region_max = reg.max;
        }
      } else {
        const Region reg = parse_region(r, r.require(n, p, "region"), join(p, "region"));
        ref.region_min = reg.min;
        ref.region_max = reg.max;
        if (ref.measure == M::mean_stress) {
          const YAML::Node cmp = r.require(n, p, "component");
          static const std::vector<std::string> names{"xx", "yy", "zz", "xy", "yz", "xz"};
          const std::string cs = r.string(cmp, join(p, "component"));
          const auto it = std::find(names.begin(), names.end(), cs);
          if (it == names.end())
            r.fail(cmp, join(p, "component"), "component must be xx, yy, zz, xy, yz or xz");
          ref.component = static_cast<int>(it - names.begin());
        }
      }
      // Without value and tolerance a measure is reported, not judged.
      if (n["value"] || n["tolerance"]) {
        ref.value = r.number(r.require(n, p, "value"), join(p, "value"));
        if (ref.value == 0.0)
          r.fail(n["value"], join(p, "value"),
                 "a reference value must be non-zero (errors are relative)");
        ref.tolerance = r.positive(r.require(n, p, "tolerance"), join(p, "tolerance"), "relative");
      } else {
        ref.value = ref.tolerance = std::numeric_limits<double>::quiet_NaN();
      }
      if (n["source"]) ref.source = r.string(n["source"], join(p, "source"));
      if (const YAML::Node t = n["time"]) {
        if (ref.measure == M::contact_duration || ref.measure == M::contact_max_force ||
            ref.measure == M::contact_mean_pressure || ref.measure == M::velocity)
          r.fail(t, join(p, "time"), "this measure is of the whole run: it has no time");
        ref.time = r.positive(t, join(p, "time"), "s");
        if (ref.time > c.end_time) r.fail(t, join(p, "time"), "after the case's end_time");
      }
      c.references.push_back(ref);
    });
  }
}

// The case's output: frame interval, fields, history.
void read_output(const Reader& r, const YAML::Node& root, Case& c) {
  // Output.
  c.output.interval = c.end_time / 20.0;
  c.output.fields = {"displacement", "velocity", "stress", "pressure", "body"};
  if (const YAML::Node o = root["output"]) {
    r.keys(o, "output", {"interval", "fields", "history_every", "format"});
    if (const YAML::Node f = o["format"]) {
      const std::string v = f.IsScalar() ? f.Scalar() : "";
      if (v == "ascii")
        c.output.format = VtuFormat::ascii;
      else if (v == "binary")
        c.output.format = VtuFormat::binary;
      else if (v == "compressed")
        c.output.format = VtuFormat::compressed;
      else
        r.fail(f, "output.format", "expected ascii, binary or compressed");
    }
    if (o["interval"]) c.output.interval = r.positive(o["interval"], "output.interval", "s");
    if (o["history_every"]) {
      c.output.history_every = r.integer(o["history_every"], "output.history_every");
      if (c.output.history_every < 1)
        r.fail(o["history_every"], "output.history_every", "must be at least 1");
    }
    if (const YAML::Node f = o["fields"]) {
      if (!f.IsSequence()) r.fail(f, "output.fields", "expected a list of field names");
      c.output.fields.clear();
      for (std::size_t k = 0; k < f.size(); ++k) {
        const std::string fp = join("output.fields", std::to_string(k));
        const std::string name = r.string(f[k], fp);
        const auto& known = known_output_fields();
        if (std::find(known.begin(), known.end(), name) == known.end()) {
          std::string list;
          for (const auto& k2 : known) list += (list.empty() ? "" : ", ") + k2;
          r.fail(f[k], fp, "unknown field '" + name + "'; known fields: " + list);
        }
        c.output.fields.push_back(name);
      }
    }
  }
}

// The case's contact between bodies.
void read_contact(const Reader& r, const YAML::Node& root, Case& c) {
  // Contact between bodies.
  if (const YAML::Node s = root["contact"]) {
    r.keys(s, "contact",
           {"enabled", "broadphase", "margin", "passes", "order", "normal", "friction", "pairs",
            "binding_lists", "edge_edge", "initial_overlap", "verify", "separation"});
    c.contact = s["enabled"] ? r.boolean(s["enabled"], "contact.enabled") : true;
    ContactSettings& cs = c.contact_settings;
    if (const YAML::Node o = s["initial_overlap"]) {
      const std::string v = r.string(o, "contact.initial_overlap");
      if (v != "error" && v != "allow")
        r.fail(o, "contact.initial_overlap", "initial_overlap must be error or allow");
      c.allow_initial_overlap = v == "allow";
    }
    if (s["edge_edge"]) cs.edge_edge = r.boolean(s["edge_edge"], "contact.edge_edge");
    if (s["verify"]) cs.verify = r.boolean(s["verify"], "contact.verify");
    if (s["binding_lists"])
      cs.binding_lists = r.boolean(s["binding_lists"], "contact.binding_lists");
    if (s["broadphase"]) {
      cs.broadphase = r.string(s["broadphase"], "contact.broadphase");
      const auto& names = broadphase_names();
      if (std::find(names.begin(), names.end(), cs.broadphase) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        r.fail(s["broadphase"], "contact.broadphase",
               "unknown broadphase '" + cs.broadphase + "'; known: " + list);
      }
    }
    if (s["margin"]) cs.margin = r.non_negative(s["margin"], "contact.margin");
    if (s["separation"]) cs.separation = r.non_negative(s["separation"], "contact.separation");
    if (s["passes"]) cs.passes = r.count(s["passes"], "contact.passes", 1, 1000);
    if (const YAML::Node o = s["order"]) {
      const std::string v = r.string(o, "contact.order");
      if (v == "lighter_first")
        cs.order = ContactSettings::Order::lighter_first;
      else if (v == "input")
        cs.order = ContactSettings::Order::input;
      else
        r.fail(o, "contact.order", "order must be lighter_first or input");
    }
    if (const YAML::Node n = s["normal"]) {
      const std::string v = r.string(n, "contact.normal");
      if (v == "face")
        cs.normal = ContactSettings::Normal::face;
      else if (v == "node")
        cs.normal = ContactSettings::Normal::node;
      else
        r.fail(n, "contact.normal", "normal must be face or node");
    }
    const auto friction = [&](const YAML::Node& f, const std::string& p, FrictionMode& mode,
                              double& k) {
      const YAML::Node m = r.require(f, p, "mode");
      const std::string v = r.string(m, join(p, "mode"));
      if (v == "slip")
        mode = FrictionMode::slip;
      else if (v == "stick")
        mode = FrictionMode::stick;
      else if (v == "coulomb")
        mode = FrictionMode::coulomb;
      else
        r.fail(m, join(p, "mode"), "friction mode must be slip, stick or coulomb");
      if (f["coefficient"]) k = r.non_negative(f["coefficient"], join(p, "coefficient"));
      if (mode == FrictionMode::coulomb && !f["coefficient"])
        r.fail(f, p, "coulomb friction needs a coefficient");
    };
    if (const YAML::Node f = s["friction"]) {
      r.keys(f, "contact.friction", {"mode", "coefficient"});
      friction(f, "contact.friction", cs.mode, cs.coefficient);
    }
    if (const YAML::Node pairs = s["pairs"]) {
      if (!pairs.IsSequence()) r.fail(pairs, "contact.pairs", "expected a list of body pairs");
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::string p = join("contact.pairs", std::to_string(i));
        r.keys(pairs[i], p, {"bodies", "mode", "coefficient"});
        const YAML::Node b = r.require(pairs[i], p, "bodies");
        if (!b.IsSequence() || b.size() != 2)
          r.fail(b, join(p, "bodies"), "expected two body names");
        std::array<std::string, 2> names;
        for (int k = 0; k < 2; ++k) {
          names[k] = r.string(b[k], join(join(p, "bodies"), std::to_string(k)));
          if (std::none_of(c.bodies.begin(), c.bodies.end(),
                           [&](const BodySpec& body) { return body.name == names[k]; }))
            r.fail(b[k], join(join(p, "bodies"), std::to_string(k)),
                   "no body named '" + names[k] + "'");
        }
        PairFriction pf;
        friction(pairs[i], p, pf.mode, pf.coefficient);
        cs.pairs.push_back(pf);
        c.contact_pair_bodies.push_back(names);
      }
    }
  }
}

// The case's fracture and particles.
void read_fracture(const Reader& r, const YAML::Node& root, Case& c) {
  // Fracture (seed 000): spall damage and loosening, and destroyed boundary cells turned into
  // particles (on unless `particles: false`: then they stay in the mesh without stress).
  if (const YAML::Node s = root["fracture"]) {
    r.keys(s, "fracture", {"enabled", "particles", "erosion_step_ratio"});
    c.fracture = s["enabled"] ? r.boolean(s["enabled"], "fracture.enabled") : true;
    c.particles = s["particles"] ? r.boolean(s["particles"], "fracture.particles") : true;
    if (const YAML::Node e = s["erosion_step_ratio"]) {
      c.erosion_step_ratio = r.number(e, "fracture.erosion_step_ratio");
      if (!(c.erosion_step_ratio >= 0.0 && c.erosion_step_ratio < 1.0))
        r.fail(e, "fracture.erosion_step_ratio", "must be in [0, 1) (0: no erosion)");
      if (c.erosion_step_ratio > 0.0 && s["particles"] && !c.particles)
        r.fail(e, "fracture.erosion_step_ratio",
               "erosion turns cells into particles: needs "
               "fracture.particles true");
    }
  }
}

// The bounds the run must hold (`expect`).
void read_expect(const Reader& r, const YAML::Node& root, Case& c) {
  // Bounds the run must hold (the stability cases state theirs).
  if (const YAML::Node e = root["expect"]) {
    const std::vector<std::string>& known = expect_figure_names();
    r.keys(e, "expect", known);
    for (const std::string& k : known)
      if (e[k]) {
        const double v = r.number(e[k], "expect." + k);
        if (!(v >= 0.0)) r.fail(e[k], "expect." + k, "a bound must be >= 0");
        c.expect.emplace_back(k, v);
      }
  }
}

}  // namespace

// The case's `parameters:` (issue 18), each a number or an expression over the ones before it,
// and every scalar of the case that starts with '=' replaced by its expression's value (printed
// to round-trip), before anything else reads the case.
std::vector<std::pair<std::string, double>> substitute_parameters(const Reader& r,
                                                                  YAML::Node root) {
  std::vector<std::pair<std::string, double>> out;
  std::map<std::string, double> names;
  const auto value = [&](const YAML::Node& n, const std::string& path) {
    const std::string s = n.Scalar();
    try {
      return evaluate_expression(s.substr(1), names);
    } catch (const ExpressionError& e) {
      r.fail(n, path, "expression '" + s + "': " + e.what());
    }
  };
  const auto is_expression = [](const YAML::Node& n) {
    return n.IsScalar() && !n.Scalar().empty() && n.Scalar()[0] == '=';
  };
  if (const YAML::Node p = root["parameters"]) {
    r.map(p, "parameters");
    for (auto it = p.begin(); it != p.end(); ++it) {
      const std::string name = it->first.Scalar(), path = join("parameters", name);
      const bool identifier =
          !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
          std::all_of(name.begin(), name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
          });
      if (!identifier || name == "pi" || name == "deg")
        r.fail(it->first, path, "a parameter's name must be an identifier other than pi and deg");
      const double v =
          is_expression(it->second) ? value(it->second, path) : r.number(it->second, path);
      names[name] = v;
      out.emplace_back(name, v);
    }
  }
  const std::function<void(YAML::Node, const std::string&)> walk = [&](YAML::Node n,
                                                                       const std::string& path) {
    if (n.IsMap()) {
      for (auto it = n.begin(); it != n.end(); ++it)
        if (it->first.Scalar() != "parameters" || !path.empty())
          walk(it->second, join(path, it->first.Scalar()));
    } else if (n.IsSequence()) {
      for (std::size_t i = 0; i < n.size(); ++i) walk(n[i], join(path, std::to_string(i)));
    } else if (is_expression(n)) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", value(n, path));
      n = std::string(buf);
    }
  };
  walk(root, "");
  return out;
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  if (!fs::exists(path)) throw CaseError(path + ": case file not found");
  if (!fs::is_regular_file(path)) throw CaseError(path + ": not a regular file");
  YAML::Node root = load_yaml(path, "case file");
  if (!root || root.IsNull()) throw CaseError(path + ": empty case file");
  std::set<std::string> overridden;
  for (const std::string& o : overrides) overridden.insert(apply_override(root, path, o));

  const Reader r(path, overridden);
  const fs::path case_dir = fs::absolute(path).parent_path();
  Case c;
  c.file = path;
  r.keys(root, "",
         {"name", "description", "parameters", "end_time", "solver", "material_library",
          "materials", "bodies", "boundary_conditions", "walls", "output", "reference", "contact",
          "fracture", "expect", "diagnostics"});
  c.parameters = substitute_parameters(r, root);
  c.name = root["name"] ? r.string(root["name"], "name") : fs::path(path).stem().string();
  if (root["description"]) c.description = r.string(root["description"], "description");
  c.end_time = r.positive(r.require(root, "", "end_time"), "end_time", "s");

  read_solver(r, root, c);
  read_materials(r, root, c, case_dir);
  read_bodies(r, root, c, case_dir);
  read_boundary_conditions(r, root, c);
  read_walls(r, root, c);
  read_references(r, root, c);
  read_output(r, root, c);
  read_contact(r, root, c);
  if (const YAML::Node d = root["diagnostics"]) {
    r.keys(d, "diagnostics", {"every_step"});
    if (d["every_step"])
      c.output.penetration_every_step = r.boolean(d["every_step"], "diagnostics.every_step");
  }
  read_fracture(r, root, c);
  read_expect(r, root, c);
  if (c.fracture &&
      std::find(c.output.fields.begin(), c.output.fields.end(), "damage") == c.output.fields.end())
    c.output.fields.push_back("damage");  // what fracture adds is always shown
  return c;
}

}  // namespace tc
