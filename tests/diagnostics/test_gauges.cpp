// Gauges (diagnostics/gauges.hpp, gauges.csv): the interpolation on one cell against an affine
// motion (exact), and a column of cells in uniaxial strain striking a rigid wall against the
// plane elastic wave it launches (the analytic solution), then the file a run writes.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "../test_util.hpp"
#include "tetcontact/app/setup.hpp"
#include "tetcontact/diagnostics/gauges.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/solver/run_loop.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

Mesh one_tet() {
  Mesh m;
  m.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.tets = {Tet{0, 1, 2, 3}};
  m.tet_body = {0};
  m.node_body = {0, 0, 0, 0};
  return m;
}

State state_of(const Mesh& m) {
  State st;
  st.x = m.x;
  st.v.assign(m.x.size(), Vec3::Zero());
  const std::size_t n = m.tets.size();
  st.s.assign(n, Sym6{});
  st.p.assign(n, 0.0);
  st.q.assign(n, 0.0);
  st.eps_p.assign(n, 0.0);
  st.temperature.assign(n, 293.0);
  st.damage.assign(n, Damage::intact);
  return st;
}

}  // namespace

// An affine motion x = A X + c, v = B X + w: a material gauge's position and velocity are A X0
// + c and B X0 + w exactly (linear shape functions reproduce affine fields); a space gauge
// reads the velocity at its fixed point, B A⁻¹ (p − c) + w; a point outside the cell is not
// measured; a material gauge outside every cell is refused by name.
TEST(Gauges, ReproduceAnAffineMotionExactly) {
  const Mesh m = one_tet();
  const Vec3 X0(0.2, 0.3, 0.1), p(0.25, 0.2, 0.15);
  Gauges g(m, {{"inside", X0, true}, {"fixed", p, false}, {"away", Vec3(2, 2, 2), false}});
  Mat3 A, B;
  A << 1.1, 0.1, 0.0, -0.05, 0.9, 0.2, 0.0, 0.1, 1.2;
  B << 3.0, -1.0, 0.5, 0.0, 2.0, 1.0, -2.0, 0.0, 1.0;
  const Vec3 c(0.01, -0.02, 0.03), w(5.0, -4.0, 3.0);
  State st = state_of(m);
  for (std::size_t i = 0; i < m.x.size(); ++i) {
    st.x[i] = A * m.x[i] + c;
    st.v[i] = B * m.x[i] + w;
  }
  st.p[0] = 1.5e9;
  st.eps_p[0] = 0.25;
  st.damage[0] = Damage::damaged;
  const std::vector<GaugeReading> r = g.read(st);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_LT((r[0].x - (A * X0 + c)).norm(), 1e-14);
  EXPECT_LT((r[0].v - (B * X0 + w)).norm(), 1e-13);
  EXPECT_EQ(r[0].pressure, 1.5e9);
  EXPECT_EQ(r[0].stress(2, 2), -1.5e9);
  EXPECT_EQ(r[0].plastic_strain, 0.25);
  EXPECT_EQ(r[0].damage, Damage::damaged);
  ASSERT_EQ(r[1].cell, 0);
  EXPECT_LT((r[1].x - p).norm(), 1e-14);
  EXPECT_LT((r[1].v - (B * A.inverse() * (p - c) + w)).norm(), 1e-12);
  EXPECT_EQ(r[2].cell, -1);
  try {
    Gauges bad(m, {{"lost", Vec3(-1, 0, 0), true}});
    ADD_FAILURE() << "a gauge outside every cell was placed";
  } catch (const GaugeError& e) {
    EXPECT_NE(std::string(e.what()).find("gauge 'lost'"), std::string::npos) << e.what();
  }
}

namespace {

// A column 10 mm tall of 100 cells, elastic (linear EOS), held by rollers on its sides
// (uniaxial strain), striking a rigid wall at z = 0 at v0 = 100 m/s from t = 0. The wave it
// launches runs up at c_L = sqrt((K + 4G/3)/ρ) and leaves the material behind it at rest under
// σzz = −ρ c_L v0; at the free top face it reflects, and the face leaves at +v0.
constexpr const char* k_column = R"yaml(name: gauge-column
end_time: 2.5e-6
materials:
  al: {density: 2700, youngs_modulus: 70.0e9, poisson_ratio: 0.3}
bodies:
  - name: column
    material: al
    mesh: {box: {size: [1.0e-4, 1.0e-4, 10.0e-3], cells: [1, 1, 100], split: 6}}
    transform: [{translate: [0, 0, 5.0e-3]}]
    velocity: [0, 0, -100]
boundary_conditions:
  - {body: column, type: fixed, components: [x, y]}
walls:
  - {name: wall, point: [0, 0, 0], normal: [0, 0, 1]}
output: {interval: 2.5e-6, fields: [velocity]}
gauges:
  interval: 1.0e-8
  points:
    - {name: middle, at: [0, 0, 5.0e-3]}
    - {name: top, at: [0, 0, 10.0e-3]}
    - {name: fixed, at: [0, 0, 2.5e-3], follows: space}
)yaml";

struct Row {
  double t;
  std::vector<GaugeReading> r;
};

class Recorder : public Observer {
 public:
  explicit Recorder(Gauges& g) : g_(g) {}
  void observe(const State& st, const Sample& s) override { rows.push_back({s.t, g_.read(st)}); }
  std::vector<Row> rows;

 private:
  Gauges& g_;
};

}  // namespace

TEST(Gauges, SeeThePlaneElasticWaveOfAColumnOnAWall) {
  test::TempDir dir("gauges-column");
  test::write_text(dir / "column.yaml", k_column);
  const Case c = load_case(dir / "column.yaml");
  Simulation sim(build_model(c), solver_settings(c));
  Gauges g(sim.model().mesh, c.output.gauges);
  Recorder rec(g);
  sim.add_observer(&rec, "test:gauges");
  ASSERT_EQ(run_to_end(sim, {}), "ok");
  const double rho = 2700, E = 70.0e9, nu = 0.3, v0 = 100.0;
  const double c_l = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho);  // 5,908 m/s
  const double sigma = rho * c_l * v0;                                           // 1.595 GPa
  const double cell = 0.1e-3 / c_l;  // a cell's transit, 17 ns
  const double arrive_mid = 5.0e-3 / c_l, arrive_top = 10.0e-3 / c_l,
               back_mid = 15.0e-3 / c_l;  // the reflection back at the middle
  // The middle: −v0 until the wave, then at rest under −ρ c_L v0; the wave's arrival (the
  // velocity through −v0/2) within two cells' transit of 5 mm / c_L.
  double crossed = -1.0, v_before = 0.0, v_after = 0.0, s_after = 0.0;
  int before = 0, after = 0;
  for (const Row& row : rec.rows) {
    const GaugeReading& m = row.r[0];
    if (crossed < 0.0 && m.v.z() > -0.5 * v0) crossed = row.t;
    if (row.t < arrive_mid - 5 * cell) v_before += m.v.z(), ++before;
    if (row.t > arrive_mid + 10 * cell && row.t < back_mid - 10 * cell)
      v_after += m.v.z(), s_after += m.stress(2, 2), ++after;
  }
  ASSERT_GT(before, 10);
  ASSERT_GT(after, 10);
  EXPECT_NEAR(crossed, arrive_mid, 2 * cell);
  EXPECT_NEAR(v_before / before, -v0, 0.01 * v0);
  EXPECT_NEAR(v_after / after, 0.0, 0.02 * v0);
  EXPECT_NEAR(s_after / after, -sigma, 0.02 * sigma);
  // The top face: −v0 until the wave reaches it, +v0 after (the free face doubles the
  // particle velocity's change); its position falls at v0 until then.
  double top_after = 0.0;
  int n_top = 0;
  for (const Row& row : rec.rows) {
    const GaugeReading& top = row.r[1];
    if (row.t < 0.8 * arrive_top) {  // ahead of the wave's numerical foot
      EXPECT_NEAR(top.v.z(), -v0, 0.02 * v0) << row.t;
      EXPECT_NEAR(top.x.z(), 10.0e-3 - v0 * row.t, 1e-9) << row.t;
    }
    if (row.t > arrive_top + 10 * cell) top_after += top.v.z(), ++n_top;
  }
  ASSERT_GT(n_top, 10);
  EXPECT_NEAR(top_after / n_top, v0, 0.03 * v0);
  // The space gauge stays where it is and reads the cell there: at rest under the wave once it
  // has passed 2.5 mm (the column's material moves through the point before).
  for (const Row& row : rec.rows) {
    const GaugeReading& f = row.r[2];
    ASSERT_GE(f.cell, 0) << row.t;
    EXPECT_LT((f.x - Vec3(0, 0, 2.5e-3)).norm(), 1e-15);
    if (row.t > 2.5e-3 / c_l + 10 * cell && row.t < back_mid - 10 * cell) {
      EXPECT_NEAR(f.v.z(), 0.0, 0.05 * v0) << row.t;
    }
  }
}

// The file: a row at the first step at or after each multiple of the interval and at the end,
// the columns named by the gauges; a gauge that no cell holds is refused before anything is
// written (exit 2, naming the file and the gauge), and so is a malformed entry.
TEST(Gauges, RunWritesGaugesCsvAndRefusesBadGauges) {
  test::TempDir dir("gauges-cli");
  // The case's gauges and one fixed in space above the column, where no cell ever is.
  std::string text = k_column;
  const std::string last = "    - {name: fixed, at: [0, 0, 2.5e-3], follows: space}\n";
  ASSERT_NE(text.find(last), std::string::npos);
  text.replace(text.find(last), last.size(),
               last + "    - {name: above, at: [0, 0, 20.0e-3], follows: space}\n");
  test::write_text(dir / "column.yaml", text);
  const auto r = test::run_cli(
      "run '" + dir / "column.yaml" + "' --quiet --out '" + dir / "out" + "' --set end_time=0.5e-6",
      dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(test::read_text(dir / "out/gauges.csv"));
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("step,t,middle:x,middle:y,middle:z,middle:vx,", 0), 0u) << header;
  EXPECT_NE(header.find(",fixed:damage"), std::string::npos);
  long rows = 0;
  double last_t = -1.0;
  while (std::getline(in, line)) {
    ++rows;
    std::stringstream ls(line);
    std::string step, t;
    std::getline(ls, step, ',');
    std::getline(ls, t, ',');
    last_t = std::stod(t);
  }
  // Every row has 16 fields a gauge (read_csv refuses another count); the gauge above the
  // column has every one empty, the others none.
  for (const auto& row : test::read_csv(dir / "out/gauges.csv"))
    for (const char* q : {"x", "vz", "pressure", "szz", "damage"}) {
      EXPECT_TRUE(row.at(std::string("above:") + q).empty());
      EXPECT_FALSE(row.at(std::string("fixed:") + q).empty());
    }
  EXPECT_GE(rows, 50);  // 0.5 µs at 10 ns, and the start
  EXPECT_LE(rows, 52);
  EXPECT_GE(last_t, 0.5e-6);  // the run's last step, at or just after the end time
  EXPECT_LT(last_t, 0.5e-6 + 1e-8);
  const auto refused = [&](const std::string& set, const std::string& what) {
    const auto b = test::run_cli(
        "run '" + dir / "column.yaml" + "' --quiet --out '" + dir / "bad" + "' --set '" + set + "'",
        dir.str());
    EXPECT_EQ(b.code, 2) << set;
    EXPECT_NE(b.err.find(what), std::string::npos) << b.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad")) << set;
  };
  refused("gauges.points.0.at=[0, 0, 20.0e-3]", "gauges: gauge 'middle': no cell");
  refused("gauges.points.0.follows=body", "follows must be material or space");
  refused("gauges.points.1.name=middle", "two gauges named 'middle'");
  refused("gauges.points.1.name=a,b", "no comma");
  refused("gauges.points.1.name=a:b", "colon");
}
