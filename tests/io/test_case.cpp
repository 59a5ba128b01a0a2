// Case files: every error class gives one message with file, line and key path.
#include <gtest/gtest.h>

#include <tuple>

#include <cstdlib>
#include <filesystem>
#include <limits>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"

using namespace tc;

namespace {

const char* k_valid = R"(name: tiny
end_time: 1.0e-6
solver:
  cfl: 0.5
materials:
  al:
    density: 2700
    youngs_modulus: 70.0e9
    poisson_ratio: 0.3
bodies:
  - name: block
    material: al
    mesh:
      box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2], split: 6}
    velocity: [0, 0, -10]
boundary_conditions:
  - body: block
    region: {min: [-1, -1, -0.005], max: [1, 1, -0.005]}
    type: fixed
output:
  interval: 1.0e-7
  fields: [velocity, stress]
)";

struct ErrorCase {
  const char* name;
  std::string text;  // whole file
  std::vector<std::string> overrides;
  std::string expect_location;  // ":LINE:" or "--set ..."
  std::string expect_key;       // key path in the message
  std::string expect_what;      // what is wrong
};

// Each case must be refused with a message naming the file, the location, the key and what
// is wrong.
void expect_errors(const std::vector<ErrorCase>& cases, const std::string& scratch) {
  test::TempDir dir(scratch);
  const std::string path = dir / "bad.yaml";
  for (const ErrorCase& c : cases) {
    test::write_text(path, c.text);
    try {
      load_case(path, c.overrides);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const CaseError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path, 0), 0u) << c.name << ": " << msg;
      EXPECT_NE(msg.find(c.expect_location), std::string::npos) << c.name << ": " << msg;
      if (!c.expect_key.empty()) {
        EXPECT_NE(msg.find("key '" + c.expect_key + "'"), std::string::npos)
            << c.name << ": " << msg;
      }
      EXPECT_NE(msg.find(c.expect_what), std::string::npos) << c.name << ": " << msg;
    }
  }
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return pos == std::string::npos ? s : s.replace(pos, from.size(), to);
}

}  // namespace

TEST(CaseFile, ValidFileLoadsWithDefaults) {
  test::TempDir dir("case-valid");
  test::write_text(dir / "c.yaml", k_valid);
  const Case c = load_case(dir / "c.yaml");
  EXPECT_EQ(c.name, "tiny");
  EXPECT_DOUBLE_EQ(c.end_time, 1e-6);
  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_EQ(c.bodies[0].mesh.kind, MeshSpec::Kind::box);
  EXPECT_EQ(c.bodies[0].mesh.cells, (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(c.bodies[0].velocity, Vec3(0, 0, -10));
  ASSERT_EQ(c.boundary_conditions.size(), 1u);
  EXPECT_TRUE(c.boundary_conditions[0].fixed);
  EXPECT_EQ(c.output.fields, (std::vector<std::string>{"velocity", "stress"}));
  EXPECT_EQ(c.output.history_every, 1);
  EXPECT_FALSE(c.contact);
}

TEST(CaseFile, SetOverridesAnyKey) {
  test::TempDir dir("case-set");
  test::write_text(dir / "c.yaml", k_valid);
  const Case c = load_case(dir / "c.yaml", {"solver.cfl=0.25", "bodies.0.velocity=[1, 2, 3]",
                                            "bodies.0.mesh.box.cells=[4,4,4]",
                                            "output.history_every=5", "name=renamed"});
  EXPECT_DOUBLE_EQ(c.cfl, 0.25);
  EXPECT_EQ(c.bodies[0].velocity, Vec3(1, 2, 3));
  EXPECT_EQ(c.bodies[0].mesh.cells[0], 4);
  EXPECT_EQ(c.output.history_every, 5);
  EXPECT_EQ(c.name, "renamed");
}

TEST(CaseFile, EveryErrorClassNamesFileLineAndKey) {
  const std::string v = k_valid;
  const std::vector<ErrorCase> cases = {
      {"yaml syntax", replace(v, "cfl: 0.5", "cfl: [0.5"), {}, ":", "", "YAML syntax error"},
      {"unknown top-level key",
       replace(v, "end_time:", "end_tme:"),
       {},
       ":2:",
       "end_tme",
       "unknown key (did you mean 'end_time'?)"},
      {"unknown nested key",
       replace(v, "    density: 2700", "    densty: 2700"),
       {},
       ":7:",
       "materials.al.densty",
       "unknown key (did you mean 'density'?)"},
      {"missing key",
       replace(v, "    youngs_modulus: 70.0e9\n", ""),
       {},
       ":7:",
       "materials.al.youngs_modulus",
       "missing required key"},
      {"missing top-level key",
       replace(v, "end_time: 1.0e-6\n", ""),
       {},
       ":1:",
       "end_time",
       "missing required key"},
      {"wrong type (number)",
       replace(v, "density: 2700", "density: heavy"),
       {},
       ":7:",
       "materials.al.density",
       "expected a number, got 'heavy'"},
      {"wrong type (list)",
       replace(v, "velocity: [0, 0, -10]", "velocity: 10"),
       {},
       ":15:",
       "bodies.0.velocity",
       "expected a list of three numbers"},
      {"wrong type (map)",
       replace(v, "solver:\n  cfl: 0.5", "solver: fast"),
       {},
       ":3:",
       "solver",
       "expected a mapping"},
      {"negative density",
       replace(v, "density: 2700", "density: -2700"),
       {},
       ":7:",
       "materials.al.density",
       "must be positive"},
      {"cfl above one",
       replace(v, "cfl: 0.5", "cfl: 1.5"),
       {},
       ":4:",
       "solver.cfl",
       "CFL factor must be in (0, 1]"},
      {"cfl zero",
       replace(v, "cfl: 0.5", "cfl: 0"),
       {},
       ":4:",
       "solver.cfl",
       "CFL factor must be in (0, 1]"},
      {"poisson ratio",
       replace(v, "poisson_ratio: 0.3", "poisson_ratio: 0.5"),
       {},
       ":9:",
       "materials.al.poisson_ratio",
       "must be in (-1, 0.5)"},
      {"negative end time",
       replace(v, "end_time: 1.0e-6", "end_time: -1"),
       {},
       ":2:",
       "end_time",
       "must be positive"},
      {"not finite",
       replace(v, "end_time: 1.0e-6", "end_time: .inf"),
       {},
       ":2:",
       "end_time",
       "expected a number"},
      {"zero cells",
       replace(v, "cells: [2, 2, 2]", "cells: [2, 0, 2]"),
       {},
       ":14:",
       "bodies.0.mesh.box.cells.1",
       "must be in [1, 4096]"},
      {"bad split",
       replace(v, "split: 6", "split: 7"),
       {},
       ":14:",
       "bodies.0.mesh.box.split",
       "hex split must be 5, 6 or 12"},
      {"lattice key on a Delaunay sphere",
       replace(v, "box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2], split: 6}",
               "sphere: {radius: 0.005, cell_size: 0.001, cells_across: 8}"),
       {},
       ":14:",
       "bodies.0.mesh.sphere.cells_across",
       "belongs to the lattice sphere"},
      {"refinement without its point",
       replace(v, "box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2], split: 6}",
               "sphere: {radius: 0.005, cell_size: 0.001, refine_size: 1.0e-4}"),
       {},
       ":14:",
       "bodies.0.mesh.sphere.refine_toward",
       "missing required key"},
      {"refinement coarser than the bulk",
       replace(v, "box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2], split: 6}",
               "sphere: {radius: 0.005, cell_size: 0.001, refine_toward: [1, 0, 0], "
               "refine_size: 0.002}"),
       {},
       ":14:",
       "bodies.0.mesh.sphere.refine_size",
       "must not exceed cell_size"},
      {"unknown material",
       replace(v, "material: al", "material: steel"),
       {},
       ":12:",
       "bodies.0.material",
       "no material named 'steel'"},
      {"unknown bc body",
       replace(v, "  - body: block", "  - body: brick"),
       {},
       ":17:",
       "boundary_conditions.0.body",
       "no body named 'brick'"},
      {"bc type",
       replace(v, "type: fixed", "type: glued"),
       {},
       ":19:",
       "boundary_conditions.0.type",
       "must be 'fixed' or 'velocity'"},
      {"region min > max",
       replace(v, "min: [-1, -1, -0.005]", "min: [2, -1, -0.005]"),
       {},
       ":18:",
       "boundary_conditions.0.region",
       "min must not exceed max"},
      {"unknown field",
       replace(v, "fields: [velocity, stress]", "fields: [velocity, heat]"),
       {},
       ":22:",
       "output.fields.1",
       "unknown field 'heat'"},
      {"missing mesh file",
       replace(v, "box: {size: [0.01, 0.01, 0.01], cells: [2, 2, 2], split: 6}",
               "file: nowhere.msh"),
       {},
       ":14:",
       "bodies.0.mesh.file",
       "mesh file not found"},
      {"duplicate key",
       replace(v, "    density: 2700", "    density: 2700\n    density: 2800"),
       {},
       ":8:",
       "materials.al.density",
       "duplicate key"},
      {"loosening limit out of range",
       replace(v, "    density: 2700", "    density: 2700\n    loosening_limit: 1.5"),
       {},
       ":8:",
       "materials.al.loosening_limit",
       "must be in (0, 1)"},
      {"override wrong type",
       v,
       {"solver.cfl=fast"},
       "--set solver.cfl",
       "solver.cfl",
       "expected a number, got 'fast'"},
      {"override out of range",
       v,
       {"solver.cfl=2"},
       "--set solver.cfl",
       "solver.cfl",
       "CFL factor must be in (0, 1]"},
      {"override bad index",
       v,
       {"bodies.3.velocity=[0,0,0]"},
       "--set bodies.3",
       "",
       "is a list of 1 entries"},
      {"override syntax", v, {"solver.cfl"}, "--set solver.cfl", "", "expected path.to.key=value"},
      {"override unknown key",
       v,
       {"solver.cfll=0.3"},
       "--set solver.cfll",
       "solver.cfll",
       "unknown key (did you mean 'cfl'?)"},
  };
  expect_errors(cases, "case-errors");
}

TEST(CaseFile, MissingAndEmptyFiles) {
  test::TempDir dir("case-missing");
  EXPECT_THROW(load_case(dir / "none.yaml"), CaseError);
  test::write_text(dir / "empty.yaml", "");
  EXPECT_THROW(load_case(dir / "empty.yaml"), CaseError);
}

TEST(CaseFile, ShippedCasesAreValid) {
  for (const char* f : {"data/cases/elastic-vibration.yaml", "data/cases/two-blocks-msh.yaml"}) {
    EXPECT_NO_THROW(load_case(test::source_path(f))) << f;
  }
}

// The schema example in data/cases/README.md is a valid case: the manual stays true.
TEST(CaseFile, ReadmeExampleIsValid) {
  const std::string readme = test::read_text(test::source_path("data/cases/README.md"));
  const auto begin = readme.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const auto end = readme.find("```", begin + 8);
  std::string yaml = readme.substr(begin + 8, end - begin - 8);
  test::TempDir dir("case-readme");
  // The example's relative paths point from data/cases/ to data/.
  for (const std::string rel : {"../meshes/", "../materials.yaml"}) {
    const auto at = yaml.find(rel);
    ASSERT_NE(at, std::string::npos) << rel;
    yaml.replace(at, rel.size(), test::source_path("data/" + rel.substr(3)));
  }
  test::write_text(dir / "example.yaml", yaml);
  const Case c = load_case(dir / "example.yaml");
  EXPECT_EQ(c.name, "my-case");
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_EQ(c.bodies[0].transform.size(), 3u);
  EXPECT_TRUE(c.contact);
  EXPECT_EQ(c.contact_settings.pairs.size(), 1u);
  EXPECT_EQ(c.boundary_conditions.size(), 2u);
  EXPECT_EQ(c.output.fields.size(), 11u);  // the example's ten, and fracture's `damage`
  EXPECT_TRUE(c.fracture);
  EXPECT_EQ(c.materials.size(), 7u);
  EXPECT_EQ(c.walls.size(), 1u);
  ASSERT_EQ(c.references.size(), 4u);
  EXPECT_EQ(c.references[2].measure, ReferenceSpec::Measure::perforated);
  EXPECT_EQ(c.references[2].debris_of, std::vector<std::string>{"rod"});
  EXPECT_EQ(c.references[2].time, 1.0e-5);
  EXPECT_EQ(c.references[3].measure, ReferenceSpec::Measure::thickness_left);
  EXPECT_EQ(c.references[3].within, 0.005);
  EXPECT_EQ(c.material("target").yield_stress, 0.3e9);
  EXPECT_EQ(c.material("hot_rod").strength, StrengthModel::johnson_cook);
  EXPECT_EQ(c.material("hot_rod").johnson_cook.n, 0.31);
  EXPECT_EQ(c.material("shocked_metal").strength, StrengthModel::steinberg_guinan);
  EXPECT_EQ(c.material("shocked_metal").steinberg_guinan.ymax, 0.68e9);
  EXPECT_EQ(c.material("debris").eos, EosKind::tillotson);
  EXPECT_EQ(c.material("debris").tillotson.e_cv, 13.9e6);
  EXPECT_NO_THROW(build_model(c));
}

TEST(MaterialLibrary, ShippedLibraryIsValidAndComplete) {
  const auto lib = load_material_library(default_material_library());
  std::vector<std::string> names;
  for (const Material& m : lib) names.push_back(m.name);
  // The Whipple database's alloys too: every shot of it maps to an entry with failure constants.
  const std::vector<std::string> database{"al2017-t4", "al2024-t3", "al1100-o", "al7075-t6",
                                          "al2219-t87"};
  for (const char* want :
       {"al6061-t6", "al2024-t4", "amg6", "steel-4340", "ofhc-copper", "tungsten-alloy"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const std::string& want : database)
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const Material& m : lib) {
    EXPECT_GT(m.density, 0.0) << m.name;
    EXPECT_GT(m.shear_modulus, 0.0) << m.name;
    EXPECT_TRUE(m.plastic()) << m.name;
    EXPECT_EQ(m.eos, EosKind::mie_gruneisen) << m.name;
    // K0 = ρ0 c0² and a Poisson's ratio of a metal.
    EXPECT_NEAR(m.bulk_modulus, m.density * m.c0 * m.c0, 1e-6 * m.bulk_modulus) << m.name;
    EXPECT_GT(m.poisson_ratio(), 0.2) << m.name;
    EXPECT_LT(m.poisson_ratio(), 0.4) << m.name;
    const bool of_database = std::count(database.begin(), database.end(), m.name) > 0;
    if (m.name != "amg6" && !of_database) {  // the metals with Johnson–Cook constants
      EXPECT_GT(m.johnson_cook.a, 0.0) << m.name;
      EXPECT_GT(m.johnson_cook.melt_temperature, m.johnson_cook.room_temperature) << m.name;
    }
    if (m.name != "amg6") {
      EXPECT_GT(m.specific_heat, 0.0) << m.name;
    }
    if (of_database) {  // one failure model for all: Johnson–Cook's, with its melt
      EXPECT_NE(m.johnson_cook_failure.d2, 0.0) << m.name;
      EXPECT_GT(m.johnson_cook_failure.melt_temperature, m.johnson_cook_failure.room_temperature)
          << m.name;
    }
    // A failure set read in the law's order gives a metal's fracture strain in the tests it is
    // fitted on, shear (σ* = 0) and a smooth tension bar (σ* = 1/3), quasi-static at room
    // temperature: above 5 %, not at the floor.
    if (m.johnson_cook_failure.d2 != 0.0)
      for (const double triaxiality : {0.0, 1.0 / 3.0}) {
        const JohnsonCookFailure& f = m.johnson_cook_failure;
        EXPECT_GT(johnson_cook_failure_strain(f, triaxiality, 0.0, f.room_temperature), 0.05)
            << m.name << " at σ* = " << triaxiality;
      }
  }
}

TEST(MaterialLibrary, CaseTakesAnEntryAndOverridesKeys) {
  test::TempDir dir("case-library");
  std::string v = k_valid;
  v = replace(v, R"(  al:
    density: 2700
    youngs_modulus: 70.0e9
    poisson_ratio: 0.3)",
              R"(  al:
    from: ofhc-copper
    yield_stress: 400.0e6
    hardening_modulus: 100.0e6)");
  test::write_text(dir / "c.yaml", v);
  const Case c = load_case(dir / "c.yaml");
  const Material& m = c.material("al");
  EXPECT_EQ(m.density, 8930);             // from the library
  EXPECT_EQ(m.shear_modulus, 47.7e9);     // from the library
  EXPECT_EQ(m.yield_stress, 400e6);       // overridden
  EXPECT_EQ(m.hardening_modulus, 100e6);  // added
  EXPECT_EQ(m.eos, EosKind::mie_gruneisen);
  EXPECT_EQ(c.material_library, default_material_library());
  // An aluminium entry's Tillotson constants, chosen by the case's eos (its bulk modulus A).
  std::string til = replace(k_valid, R"(  al:
    density: 2700
    youngs_modulus: 70.0e9
    poisson_ratio: 0.3)",
                            R"(  al:
    from: al6061-t6
    eos: {type: tillotson})");
  test::write_text(dir / "t.yaml", til);
  const Material& t = load_case(dir / "t.yaml").material("al");
  EXPECT_EQ(t.eos, EosKind::tillotson);
  EXPECT_EQ(t.tillotson.big_a, 75.2e9);
  EXPECT_EQ(t.tillotson.e_cv, 13.9e6);
  EXPECT_EQ(t.bulk_modulus, 75.2e9);
  EXPECT_EQ(t.density, 2703);
  // The library's Johnson–Cook constants come along; the law stays bilinear until chosen.
  EXPECT_EQ(m.strength, StrengthModel::bilinear);
  EXPECT_EQ(m.johnson_cook.a, 90e6);
  EXPECT_EQ(m.johnson_cook.melt_temperature, 1356);
  EXPECT_EQ(m.specific_heat, 383);
  // So do its fracture constants [JC85]; ductile failure stays off until a case turns it on.
  EXPECT_FALSE(m.ductile_failure);
  EXPECT_TRUE(m.ductile_failure_at_floor);  // at the floor too, unless a case says not
  EXPECT_EQ(m.johnson_cook_failure.d2, 4.89);
  EXPECT_EQ(m.johnson_cook_failure.melt_temperature, 1356);
  test::write_text(
      dir / "floor.yaml",
      replace(v, "from: ofhc-copper", "from: ofhc-copper\n    ductile_failure_at_floor: false"));
  EXPECT_FALSE(load_case(dir / "floor.yaml").material("al").ductile_failure_at_floor);
  test::write_text(dir / "jc.yaml", replace(v, "from: ofhc-copper",
                                            "from: ofhc-copper\n    strength: johnson_cook"));
  const Case jc = load_case(dir / "jc.yaml");
  EXPECT_EQ(jc.material("al").strength, StrengthModel::johnson_cook);
  EXPECT_TRUE(jc.material("al").plastic());
  EXPECT_EQ(jc.material("al").start_temperature(), 293.0);
  // Steinberg–Guinan from the entry's block, Γ0 from its EOS unless given, T from T_ref.
  const std::string sg_text = replace(v, R"(    from: ofhc-copper
    yield_stress: 400.0e6
    hardening_modulus: 100.0e6)",
                                      "    from: ofhc-copper\n    strength: steinberg_guinan");
  test::write_text(dir / "sg.yaml", sg_text);
  const Material sg = load_case(dir / "sg.yaml").material("al");
  EXPECT_EQ(sg.strength, StrengthModel::steinberg_guinan);
  EXPECT_EQ(sg.steinberg_guinan.y0, 0.12e9);
  EXPECT_EQ(sg.steinberg_guinan.ymax, 0.64e9);
  EXPECT_EQ(sg.steinberg_guinan.a_pressure, 2.83e-11);
  EXPECT_EQ(sg.steinberg_guinan.gamma0, 2.02);
  EXPECT_EQ(sg.start_temperature(), 300.0);
  // A case's own yield_stress selects the bilinear law over the entry's (named) law.
  test::write_text(dir / "sg-yield.yaml",
                   replace(sg_text, "    strength: steinberg_guinan", "    yield_stress: 1.0e8"));
  EXPECT_EQ(load_case(dir / "sg-yield.yaml").material("al").strength, StrengthModel::bilinear);

  test::write_text(dir / "bad.yaml", replace(v, "from: ofhc-copper", "from: unobtainium"));
  try {
    load_case(dir / "bad.yaml");
    FAIL();
  } catch (const CaseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("key 'materials.al.from'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no material 'unobtainium'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ofhc-copper"), std::string::npos) << msg;
  }
}

// A library entry may derive from another (`from`, one level): its keys over the other's. Its
// material then starts from its cold work (`initial_plastic_strain`).
TEST(MaterialLibrary, AnEntryDerivesFromAnother) {
  test::TempDir dir("library-from");
  const std::string base = R"(base:
  strength: steinberg_guinan
  density: 8930
  shear_modulus: 47.7e9
  eos: {type: mie_gruneisen, c0: 3940, s: 1.489, gamma0: 2.02}
  steinberg_guinan: {Y0: 0.12e9, Ymax: 0.64e9, beta: 36, n: 0.45}
)";
  test::write_text(dir / "lib.yaml",
                   base + "worked:\n  from: base\n  initial_plastic_strain: 0.25\n");
  const auto lib = load_material_library(dir / "lib.yaml");
  ASSERT_EQ(lib.size(), 2u);
  EXPECT_EQ(lib[0].initial_plastic_strain, 0.0);
  EXPECT_EQ(lib[1].name, "worked");
  EXPECT_EQ(lib[1].initial_plastic_strain, 0.25);
  EXPECT_EQ(lib[1].density, 8930);  // the rest is the base's
  EXPECT_EQ(lib[1].strength, StrengthModel::steinberg_guinan);
  EXPECT_EQ(lib[1].steinberg_guinan.ymax, 0.64e9);

  // A case takes the derived entry, and its own keys go over both.
  std::string v = replace(k_valid, "materials:", "material_library: lib.yaml\nmaterials:");
  v = replace(v, R"(  al:
    density: 2700
    youngs_modulus: 70.0e9
    poisson_ratio: 0.3)",
              "  al:\n    from: worked\n    density: 9000");
  test::write_text(dir / "c.yaml", v);
  const Material m = load_case(dir / "c.yaml").material("al");
  EXPECT_EQ(m.initial_plastic_strain, 0.25);
  EXPECT_EQ(m.density, 9000);
  EXPECT_EQ(m.steinberg_guinan.y0, 0.12e9);

  const auto fails = [&](const std::string& text, const std::vector<std::string>& says) {
    test::write_text(dir / "bad.yaml", text);
    try {
      load_material_library(dir / "bad.yaml");
      FAIL() << text;
    } catch (const CaseError& e) {
      const std::string msg = e.what();
      for (const std::string& want : says) EXPECT_NE(msg.find(want), std::string::npos) << msg;
    }
  };
  fails(base + "worked:\n  from: nothing\n",
        {"bad.yaml", "worked.from", "no library entry 'nothing'"});
  fails(base + "worked:\n  from: base\nreworked:\n  from: worked\n",
        {"reworked.from", "'worked' derives from another entry"});
  fails(base + "worked:\n  from: base\n  initial_plastic_strain: -0.1\n",
        {"worked.initial_plastic_strain"});
  fails(base + "worked:\n  from: worked\n", {"worked.from", "cannot derive from itself"});
  fails("odd:\n  from: scalar\nscalar: 3\n", {"bad.yaml:3:", "key 'scalar'", "expected a mapping"});
  // Its own yield_stress selects the bilinear law over the base's, as a case's does.
  test::write_text(dir / "lib.yaml", base + "soft:\n  from: base\n  yield_stress: 0.1e9\n");
  EXPECT_EQ(load_material_library(dir / "lib.yaml")[1].strength, StrengthModel::bilinear);
}

TEST(CaseFile, MaterialAndWallErrors) {
  const std::string v = k_valid;
  const std::vector<ErrorCase> cases = {
      {"both elastic forms",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    shear_modulus: 1.0e9"),
       {},
       ":7:",
       "materials.al",
       "either youngs_modulus and poisson_ratio"},
      {"hardening without yield",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    hardening_modulus: 1.0e9"),
       {},
       ":10:",
       "materials.al.hardening_modulus",
       "needs a yield_stress"},
      {"bad eos",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    eos: {type: ideal_gas}"),
       {},
       ":10:",
       "materials.al.eos.type",
       "mie_gruneisen or tillotson"},
      {"tillotson without constants",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    eos: {type: tillotson}"),
       {},
       ":10:",
       "materials.al.eos.type",
       "tillotson needs the material's tillotson constants"},
      {"tillotson vaporisation energies",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    eos: {type: tillotson}\n    tillotson: {A: 75.2e9, B: "
               "65.0e9, a: 0.5, b: 1.63, E0: 5.0e6, E_iv: 3.0e6, E_cv: 2.0e6, alpha: 5, beta: 5}"),
       {},
       ":11:",
       "materials.al.tillotson.E_cv",
       "must be above E_iv"},
      {"tillotson missing E0",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    tillotson: {A: 75.2e9, B: 65.0e9, a: 0.5, b: 1.63, "
               "E_iv: 3.0e6, E_cv: 13.9e6, alpha: 5, beta: 5}"),
       {},
       ":10:",
       "materials.al.tillotson.E0",
       "missing required key"},
      {"mg missing s",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    eos: {type: mie_gruneisen, c0: 5000, gamma0: 2}"),
       {},
       ":10:",
       "materials.al.eos.s",
       "missing required key"},
      {"zero wall normal",
       v + "walls:\n  - {point: [0, 0, 0], normal: [0, 0, 0]}\n",
       {},
       ":24:",
       "walls.0.normal",
       "non-zero"},
      {"negative friction",
       v + "walls:\n  - {point: [0, 0, 0], normal: [0, 0, 1], friction: -0.1}\n",
       {},
       ":24:",
       "walls.0.friction",
       "must not be negative"},
      {"anp value",
       v,
       {"solver.average_nodal_pressure=sometimes"},
       "--set solver.average_nodal_pressure",
       "solver.average_nodal_pressure",
       "average_nodal_pressure must be auto, true or false"},
      {"anp stabilization out of range",
       v,
       {"solver.anp_stabilization=2"},
       "--set solver.anp_stabilization",
       "solver.anp_stabilization",
       "must be in [0, 1]"},
      {"unknown strength law",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    strength: zerilli"),
       {},
       ":10:",
       "materials.al.strength",
       "strength must be bilinear, johnson_cook or steinberg_guinan"},
      {"a plane on a measure that takes none",
       v + "reference:\n  - {name: l, measure: length, body: block, axis: z, plane: {point: [0, 0, "
           "0], normal: [0, 0, 1]}}\n",
       {},
       ":24:",
       "reference.0.plane",
       "only the debris measures"},
      {"debris of an unknown body",
       v + "reference:\n  - {name: p, measure: perforated, body: block, plane: {point: [0, 0, 0], "
           "normal: [0, 0, 1]}, debris_of: [rod]}\n",
       {},
       ":24:",
       "reference.0.debris_of.0",
       "no body named 'rod'"},
      {"debris of a plate's own thickness",
       v + "reference:\n  - {name: t, measure: thickness_left, body: block, plane: {point: [0, 0, "
           "0], normal: [0, 0, 1]}, debris_of: [block]}\n",
       {},
       ":24:",
       "reference.0.debris_of",
       "thickness_left measures the body itself"},
      {"debris of a plate's own bulge",
       v + "reference:\n  - {name: b, measure: bulge, body: block, plane: {point: [0, 0, 0], "
           "normal: [0, 0, 1]}, debris_of: [block]}\n",
       {},
       ":24:",
       "reference.0.debris_of",
       "bulge measures the body itself"},
      {"a measure's time after the end",
       v + "reference:\n  - {name: p, measure: perforated, body: block, plane: {point: [0, 0, 0], "
           "normal: [0, 0, 1]}, time: 2.0e-6}\n",
       {},
       ":24:",
       "reference.0.time",
       "after the case's end_time"},
      {"steinberg_guinan without constants",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    strength: steinberg_guinan"),
       {},
       ":10:",
       "materials.al.strength",
       "needs the material's steinberg_guinan constants"},
      {"Ymax below Y0",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    steinberg_guinan: {Y0: 1.0e8, Ymax: 0.5e8}"),
       {},
       ":10:",
       "materials.al.steinberg_guinan.Ymax",
       "must not be below Y0"},
      {"melt law without gamma0",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    steinberg_guinan: {Y0: 1.0e8, melt_temperature: 900}"),
       {},
       ":10:",
       "materials.al.steinberg_guinan",
       "the melt law needs gamma0"},
      {"johnson_cook without constants",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    strength: johnson_cook"),
       {},
       ":10:",
       "materials.al.strength",
       "needs the material's johnson_cook constants"},
      {"melt below room",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    johnson_cook: {A: 1.0e8, melt_temperature: 200}"),
       {},
       ":10:",
       "materials.al.johnson_cook.melt_temperature",
       "above the room temperature"},
      {"ductile failure at the floor not a switch",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    ductile_failure_at_floor: sometimes"),
       {},
       ":10:",
       "materials.al.ductile_failure_at_floor",
       "expected true or false"},
      {"ductile failure without constants",
       replace(v, "    poisson_ratio: 0.3", "    poisson_ratio: 0.3\n    ductile_failure: true"),
       {},
       ":10:",
       "materials.al.ductile_failure",
       "needs the material's johnson_cook_failure constants"},
      {"failure constants without D1",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    johnson_cook_failure: {D2: 1.0}"),
       {},
       ":10:",
       "materials.al.johnson_cook_failure.D1",
       "missing required key"},
      {"D5 without a melt temperature",
       replace(v, "    poisson_ratio: 0.3",
               "    poisson_ratio: 0.3\n    ductile_failure: true\n    johnson_cook_failure: {D1: "
               "0.5, D5: 1.0}"),
       {},
       ":11:",
       "materials.al.johnson_cook_failure",
       "D5 needs a melt temperature"},
  };
  expect_errors(cases, "case-material-errors");
}

// Summaries go through nlohmann::ordered_json: keys in insertion order, doubles that read back
// bit for bit, NaN and Inf as null (never a number that was not measured), a Vec3 as [x, y, z].
TEST(Json, SummaryValuesRoundTrip) {
  Json j = Json::object();
  j["second"] = 0.1 + 0.2;
  j["first"] = Vec3(1.0 / 3.0, -2.5e-300, 7.0);
  j["nan"] = std::numeric_limits<double>::quiet_NaN();
  j["inf"] = std::numeric_limits<double>::infinity();
  const Json back = Json::parse(j.dump(2));
  EXPECT_EQ(back.begin().key(), "second");
  EXPECT_EQ(back.at("second").get<double>(), 0.1 + 0.2);
  ASSERT_EQ(back.at("first").size(), 3u);
  EXPECT_EQ(back.at("first")[0].get<double>(), 1.0 / 3.0);
  EXPECT_EQ(back.at("first")[1].get<double>(), -2.5e-300);
  EXPECT_TRUE(back.at("nan").is_null());
  EXPECT_TRUE(back.at("inf").is_null());
}

TEST(Case, ErosionRatioOutOfRangeOrWithoutParticlesIsRefused) {
  const std::string file = test::source_path("data/cases/ball-plate.yaml");
  EXPECT_EQ(load_case(file).erosion_step_ratio, 0.01);
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"fracture.erosion_step_ratio=1.5"},
        std::vector<std::string>{"fracture.erosion_step_ratio=-0.1"},
        std::vector<std::string>{"fracture.particles=false"}}) {
    try {
      load_case(file, bad);
      ADD_FAILURE() << bad[0] << " was accepted";
    } catch (const CaseError& e) {
      EXPECT_NE(std::string(e.what()).find("fracture.erosion_step_ratio"), std::string::npos)
          << e.what();
    }
  }
}

// fracture.erosion_reference: the model's first step by default, each body's on request, and
// nothing else.
TEST(Case, ErosionReferenceIsTheModelOrTheBody) {
  const std::string file = test::source_path("data/cases/ball-plate.yaml");
  EXPECT_FALSE(load_case(file).erosion_per_body);
  EXPECT_TRUE(load_case(file, {"fracture.erosion_reference=body"}).erosion_per_body);
  EXPECT_FALSE(load_case(file, {"fracture.erosion_reference=model"}).erosion_per_body);
  try {
    load_case(file, {"fracture.erosion_reference=cell"});
    ADD_FAILURE() << "erosion_reference=cell was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("fracture.erosion_reference"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("must be model or body"), std::string::npos) << e.what();
  }
}

// fracture.fragments: each cell its own particle by default, clusters on request, and nothing
// else.
TEST(Case, FragmentsAreCellsOrClusters) {
  const std::string file = test::source_path("data/cases/ball-plate.yaml");
  EXPECT_FALSE(load_case(file).fragment_clusters);
  EXPECT_TRUE(load_case(file, {"fracture.fragments=clusters"}).fragment_clusters);
  EXPECT_FALSE(load_case(file, {"fracture.fragments=cells"}).fragment_clusters);
  try {
    load_case(file, {"fracture.fragments=cubes"});
    ADD_FAILURE() << "fracture.fragments=cubes was accepted";
  } catch (const CaseError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("fracture.fragments"), std::string::npos) << what;
    EXPECT_NE(what.find("cells or clusters"), std::string::npos) << what;
  }
}

// fracture.debris: point masses by default, SPH particles on request; its settings only with
// it, in their ranges (the faces met through the kernel or by contact); no clusters of SPH
// particles.
TEST(Case, DebrisIsPointsOrSph) {
  const std::string file = test::source_path("data/cases/ball-plate.yaml");
  EXPECT_FALSE(load_case(file).sph_debris);
  const Case sph = load_case(file, {"fracture.debris=sph", "fracture.sph.smoothing=1.5"});
  EXPECT_TRUE(sph.sph_debris);
  EXPECT_EQ(sph.sph.smoothing, 1.5);
  EXPECT_EQ(sph.sph.alpha, 1.0);
  EXPECT_EQ(sph.sph.step_factor, 0.6);
  EXPECT_EQ(
      load_case(file, {"fracture.debris=sph", "fracture.sph.step_factor=1.2"}).sph.step_factor,
      1.2);
  EXPECT_TRUE(sph.sph.faces);  // the faces met through the kernel by default
  EXPECT_FALSE(load_case(file, {"fracture.debris=sph", "fracture.sph.faces=contact"}).sph.faces);
  EXPECT_FALSE(load_case(file, {"fracture.debris=points"}).sph_debris);
  for (const auto& [bad, key, words] :
       std::vector<std::tuple<std::vector<std::string>, std::string, std::string>>{
           {{"fracture.debris=dust"}, "fracture.debris", "points or sph"},
           {{"fracture.sph.smoothing=1.5"}, "fracture.sph", "fracture.debris: sph"},
           {{"fracture.debris=sph", "fracture.sph.smoothing=5"},
            "fracture.sph.smoothing",
            "[0.8, 3]"},
           {{"fracture.debris=sph", "fracture.sph.artificial_stress=-1"},
            "fracture.sph.artificial_stress",
            "[0, 1]"},
           {{"fracture.debris=sph", "fracture.sph.step_factor=0"},
            "fracture.sph.step_factor",
            "[0.1, 2]"},
           {{"fracture.debris=sph", "fracture.sph.kernel=1"}, "fracture.sph.kernel", "unknown"},
           {{"fracture.debris=sph", "fracture.sph.faces=glue"},
            "fracture.sph.faces",
            "kernel or contact"},
           {{"fracture.fragments=clusters", "fracture.debris=sph"}, "fracture.debris", "clusters"},
           {{"fracture.erosion_step_ratio=0", "fracture.particles=false", "fracture.debris=sph"},
            "fracture.debris",
            "fracture.particles true"}}) {
    try {
      load_case(file, bad);
      ADD_FAILURE() << bad.back() << " was accepted";
    } catch (const CaseError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(key), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  }
}

// end_when_released: off at 0, refused where nothing could push on a body, and refused when
// it is not shorter than end_time.
TEST(CaseFile, EndWhenReleasedNeedsSomethingToPushAndAShorterEnd) {
  const std::string taylor = test::source_path("data/cases/taylor.yaml");
  EXPECT_EQ(load_case(taylor).end_when_released, 5.0e-6);
  EXPECT_EQ(load_case(taylor, {"end_when_released=0"}).end_when_released, 0.0);
  const std::string v = std::string(k_valid) + "end_when_released: 1.0e-7\n";
  expect_errors(
      {{"nothing to push", v, {}, ":", "end_when_released", "no wall, no contact and no particles"},
       {"fracture without particles",
        v + "fracture: {particles: false, erosion_step_ratio: 0}\n",
        {},
        ":",
        "end_when_released",
        "no wall, no contact and no particles"},
       {"negative",
        v,
        {"end_when_released=-1e-7"},
        "--set",
        "end_when_released",
        "must not be negative"}},
      "end-released");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"end_when_released=1"},
        std::vector<std::string>{"end_when_released=-1"},
        std::vector<std::string>{"end_time=1.0e-4", "end_when_released=1.0e-4"}}) {
    try {
      load_case(taylor, bad);
      ADD_FAILURE() << bad.back() << " was accepted";
    } catch (const CaseError& e) {
      EXPECT_NE(std::string(e.what()).find("key 'end_when_released'"), std::string::npos)
          << e.what();
    }
  }
}

// No source path is compiled in: the data folder is found beside the program's folder (the
// build tree's ../data), or named by TETCONTACT_DATA; a wrong name is an error that says so.
TEST(Files, DataFolderBesideTheProgramOrFromTheEnvironment) {
  ::unsetenv("TETCONTACT_DATA");
  EXPECT_TRUE(std::filesystem::equivalent(data_dir(), test::source_path("data")));
  ::setenv("TETCONTACT_DATA", "/nonexistent/tetcontact-data", 1);
  EXPECT_THROW(data_dir(), std::runtime_error);
  ::setenv("TETCONTACT_DATA", test::source_path("data").c_str(), 1);
  EXPECT_EQ(data_dir(), test::source_path("data"));
  ::unsetenv("TETCONTACT_DATA");
}
