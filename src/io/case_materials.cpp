// The case file's `materials:` and the material library (data/materials.yaml): density,
// elasticity, strength law, temperature, EOS, failure.
#include "case_reader.hpp"

#include <algorithm>

#include "tetcontact/io/files.hpp"

namespace tc {
namespace case_file {

namespace {

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

// Tillotson's block: A, B (Pa), a, b, E0, E_iv, E_cv (J/kg), alpha, beta; every one required
// (no constant of the law has a default that would hold for another material).
void read_tillotson(const Reader& r, const YAML::Node& tn, const std::string& tp, Tillotson& t) {
  r.map(tn, tp);
  r.keys(tn, tp, {"A", "B", "a", "b", "E0", "E_iv", "E_cv", "alpha", "beta", "source"});
  t.big_a = r.positive(r.require(tn, tp, "A"), join(tp, "A"), "Pa");
  t.big_b = r.non_negative(r.require(tn, tp, "B"), join(tp, "B"));
  t.a = r.non_negative(r.require(tn, tp, "a"), join(tp, "a"));
  t.b = r.non_negative(r.require(tn, tp, "b"), join(tp, "b"));
  t.e0 = r.positive(r.require(tn, tp, "E0"), join(tp, "E0"), "J/kg");
  t.e_iv = r.positive(r.require(tn, tp, "E_iv"), join(tp, "E_iv"), "J/kg");
  t.e_cv = r.positive(r.require(tn, tp, "E_cv"), join(tp, "E_cv"), "J/kg");
  if (!(t.e_cv > t.e_iv))
    r.fail(tn["E_cv"], join(tp, "E_cv"),
           "the energy of complete vaporisation E_cv must be above E_iv, the incipient one");
  t.alpha = r.non_negative(r.require(tn, tp, "alpha"), join(tp, "alpha"));
  t.beta = r.non_negative(r.require(tn, tp, "beta"), join(tp, "beta"));
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
    mat.strength = r.choice(sn, join(p, "strength"), k_strength_names, "strength");
    const std::string law(name_of(k_strength_names, mat.strength));
    if (mat.strength != StrengthModel::bilinear && !m[law])
      r.fail(sn, join(p, "strength"), law + " needs the material's " + law + " constants");
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
  if (const YAML::Node fn = m["ductile_failure_at_floor"])
    mat.ductile_failure_at_floor = r.boolean(fn, join(p, "ductile_failure_at_floor"));
  if (mat.ductile_failure && f.d5 != 0.0 && !(f.melt_temperature > f.room_temperature))
    r.fail(m["johnson_cook_failure"], join(p, "johnson_cook_failure"),
           "D5 needs a melt temperature above the room temperature: give melt_temperature");
}

// A material's keys over the library entry it names (`from`): the entry's keys, each of `over`'s
// (but `from`) in its place. Its own yield_stress or hardening_modulus are the bilinear law's
// constants: they select it over the entry's law unless it names a law itself.
YAML::Node merged_over(const YAML::Node& entry, const YAML::Node& over) {
  YAML::Node merged = YAML::Clone(entry);
  for (auto kv = over.begin(); kv != over.end(); ++kv)
    if (kv->first.Scalar() != "from") merged[kv->first.Scalar()] = kv->second;
  if ((over["yield_stress"] || over["hardening_modulus"]) && !over["strength"])
    merged["strength"] = "bilinear";
  return merged;
}

// A library entry as its material reads it: its own keys over the entry it derives from, when it
// names one (`from`, one level: that entry does not derive from another).
YAML::Node library_entry(const Reader& r, const YAML::Node& library, const std::string& name) {
  const YAML::Node& lib = library;  // const: a lookup must not add the key
  const YAML::Node entry = lib[name];
  if (!(entry.IsMap() && entry["from"])) return entry;
  const std::string p = join(name, "from");
  const std::string base = r.string(entry["from"], p);
  if (base == name) r.fail(entry["from"], p, "an entry cannot derive from itself");
  const YAML::Node b = lib[base];
  if (!b) r.fail(entry["from"], p, "no library entry '" + base + "' to derive from");
  r.map(b, base);
  if (b["from"])
    r.fail(entry["from"], p,
           "'" + base + "' derives from another entry itself: name the one it derives from");
  // A clone: the entry's own nodes keep the library's lines, which a case's error must not cite.
  return merged_over(b, YAML::Clone(entry));
}

}  // namespace

// One material's keys: density; elasticity as (youngs_modulus, poisson_ratio) or
// (shear_modulus [, bulk_modulus]); optional strength; optional EOS.
Material parse_material(const Reader& r, const YAML::Node& m, const std::string& p,
                        const YAML::Node* at) {
  // What is wrong with the material as a whole (or a key it lacks) is said at `at`, the case's
  // own entry, when `m` is a library entry merged with the case's keys (a merged map has no
  // line of the case file).
  const YAML::Node& here = at ? *at : m;
  const auto require = [&](const char* key) -> YAML::Node {
    if (const YAML::Node v = m[key]) return v;
    r.fail(here, join(p, key), "missing required key");
  };
  r.keys(m, p,
         {"from",
          "density",
          "youngs_modulus",
          "poisson_ratio",
          "shear_modulus",
          "bulk_modulus",
          "yield_stress",
          "hardening_modulus",
          "initial_plastic_strain",
          "eos",
          "tillotson",
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
          "ductile_failure_at_floor",
          "johnson_cook_failure"});
  Material mat;
  mat.density = r.positive(require("density"), join(p, "density"), "kg/m^3");
  const bool by_young = m["youngs_modulus"] || m["poisson_ratio"];
  const bool by_shear = m["shear_modulus"] || m["bulk_modulus"];
  if (by_young && by_shear)
    r.fail(here, p,
           "give either youngs_modulus and poisson_ratio, or shear_modulus (and bulk_modulus)");
  if (by_young) {
    const double e = r.positive(require("youngs_modulus"), join(p, "youngs_modulus"), "Pa");
    const YAML::Node nu = require("poisson_ratio");
    const double v = r.number(nu, join(p, "poisson_ratio"));
    if (!(v > -1.0 && v < 0.5))
      r.fail(nu, join(p, "poisson_ratio"),
             "Poisson's ratio must be in (-1, 0.5), got " + nu.Scalar());
    set_elastic_constants(mat, e, v);
  } else if (by_shear) {
    mat.shear_modulus = r.positive(require("shear_modulus"), join(p, "shear_modulus"), "Pa");
    if (m["bulk_modulus"])
      mat.bulk_modulus = r.positive(m["bulk_modulus"], join(p, "bulk_modulus"), "Pa");
  } else {
    r.fail(here, p,
           "missing elastic constants: youngs_modulus and poisson_ratio, or shear_modulus");
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
  if (m["initial_plastic_strain"])
    mat.initial_plastic_strain =
        r.non_negative(m["initial_plastic_strain"], join(p, "initial_plastic_strain"));
  if (const YAML::Node tn = m["tillotson"])
    read_tillotson(r, tn, join(p, "tillotson"), mat.tillotson);
  if (const YAML::Node e = m["eos"]) {
    const std::string ep = join(p, "eos");
    r.map(e, ep);
    mat.eos = r.choice(r.require(e, ep, "type"), join(ep, "type"), k_eos_names, "EOS type");
    if (mat.eos == EosKind::linear) {
      r.keys(e, ep, {"type"});
    } else if (mat.eos == EosKind::tillotson) {
      r.keys(e, ep, {"type"});
      if (!m["tillotson"])
        r.fail(e["type"], join(ep, "type"), "tillotson needs the material's tillotson constants");
      mat.bulk_modulus = mat.tillotson.big_a;  // K0 = A
    } else {
      r.keys(e, ep, {"type", "c0", "s", "gamma0"});
      mat.c0 = r.positive(r.require(e, ep, "c0"), join(ep, "c0"), "m/s");
      mat.s = r.non_negative(r.require(e, ep, "s"), join(ep, "s"));
      mat.gamma0 = r.non_negative(r.require(e, ep, "gamma0"), join(ep, "gamma0"));
      mat.bulk_modulus = mat.density * mat.c0 * mat.c0;  // K0 = ρ0 c0²
    }
  }
  if (mat.bulk_modulus <= 0.0)
    r.fail(here, p,
           "no bulk modulus: give bulk_modulus, youngs_modulus and poisson_ratio, or a "
           "mie_gruneisen or tillotson eos");
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
      // The library was validated above, each entry with what it derives from. m is rebound:
      // the case's own entry stays as written.
      const Reader lr(library_path, {});
      m.reset(merged_over(library_entry(lr, library, from), m));
    }
    Material mat = parse_material(r, m, p, &it->second);
    mat.name = name;
    for (const Material& other : c.materials)
      if (other.name == name) r.fail(it->first, p, "duplicate material name");
    c.materials.push_back(mat);
  }
}

}  // namespace case_file

using namespace case_file;

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
    const YAML::Node read = library_entry(r, root, it->first.Scalar());
    Material m = parse_material(r, read, it->first.Scalar(), &entry);
    m.name = it->first.Scalar();
    out.push_back(m);
  }
  return out;
}

const Material& Case::material(const std::string& n) const {
  for (const Material& m : materials)
    if (m.name == n) return m;
  throw CaseError(file + ": unknown material '" + n + "'");
}

}  // namespace tc
