// Case parameters and their expressions.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../test_util.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/expression.hpp"

using namespace tc;

// Precedence, associativity, unary minus, functions and constants against the values C++
// computes for the same formulas.
TEST(Expression, EvaluatesWithPrecedenceFunctionsAndNames) {
  const std::map<std::string, double> n{{"d", 3.0e-3}, {"v", 6500.0}, {"theta", 30.0}};
  EXPECT_EQ(evaluate_expression("1 + 2 * 3", n), 7.0);
  EXPECT_EQ(evaluate_expression("(1 + 2) * 3", n), 9.0);
  EXPECT_EQ(evaluate_expression("2 ^ 3 ^ 2", n), 512.0);  // right-associative
  EXPECT_EQ(evaluate_expression("-2 ^ 2", n), 4.0);       // unary minus binds first
  EXPECT_EQ(evaluate_expression("8 / 4 / 2", n), 1.0);    // left-associative
  EXPECT_EQ(evaluate_expression(" d / 2 ", n), 1.5e-3);
  EXPECT_EQ(evaluate_expression("1.5e-3 * 2", n), 3.0e-3);
  EXPECT_DOUBLE_EQ(evaluate_expression("-v * cos(theta * deg)", n),
                   -6500.0 * std::cos(30.0 * std::numbers::pi / 180.0));
  EXPECT_DOUBLE_EQ(evaluate_expression("sqrt(abs(-16)) + exp(0) + log(1) + atan(1) * 4", n),
                   4.0 + 1.0 + 0.0 + std::numbers::pi);
  EXPECT_EQ(evaluate_expression("round(2.5) + ceil(0.1) + floor(-0.1)", n), 3.0 + 1.0 - 1.0);
  EXPECT_EQ(evaluate_expression("max(1, round(d / 2e-3)) + min(-1, 2)", n), 2.0 - 1.0);
}

TEST(Expression, ErrorsNameTheProblemAndTheColumn) {
  const std::map<std::string, double> n{{"d", 1.0}};
  const auto message = [&](const std::string& text) {
    try {
      evaluate_expression(text, n);
    } catch (const ExpressionError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("d * q"), "unknown name 'q' at column 5");
  EXPECT_EQ(message("foo(1)"), "unknown function 'foo' at column 1");
  EXPECT_EQ(message("(d + 1"), "expected ')' at column 7");
  EXPECT_EQ(message("d +"), "expected a number, a name or '(' at column 4");
  EXPECT_EQ(message("d 2"), "unexpected '2' at column 3");
  EXPECT_EQ(message("1 / 0"), "the value is not finite at column 6");
  EXPECT_EQ(message("max(1)"), "'max' takes two arguments at column 1");
}

namespace {
const char* k_parametric = R"yaml(name: parametric
parameters:
  d: 4.0e-3
  r: "= d / 2"
  v: 6500
  theta: 30
end_time: 1.0e-6
materials:
  al: {density: 2700, youngs_modulus: 70.0e9, poisson_ratio: 0.3}
bodies:
  - name: ball
    material: al
    mesh: {sphere: {radius: "= r", cells_across: 4}}
    velocity: ["= v * sin(theta * deg)", 0, "= -v * cos(theta * deg)"]
)yaml";
}  // namespace

// Expressions anywhere in the case, over parameters that may use the ones before them; --set
// changes a parameter and every expression that uses it; the parameters reach the case.
TEST(CaseFile, ParametersAndExpressions) {
  test::TempDir dir("case-parameters");
  test::write_text(dir / "p.yaml", k_parametric);
  const Case c = load_case(dir / "p.yaml");
  EXPECT_EQ(c.bodies[0].mesh.radius, 2.0e-3);
  EXPECT_DOUBLE_EQ(c.bodies[0].velocity.x(), 6500.0 * std::sin(std::numbers::pi / 6.0));
  EXPECT_DOUBLE_EQ(c.bodies[0].velocity.z(), -6500.0 * std::cos(std::numbers::pi / 6.0));
  ASSERT_EQ(c.parameters.size(), 4u);
  EXPECT_EQ(c.parameters[1].first, "r");
  EXPECT_EQ(c.parameters[1].second, 2.0e-3);
  const Case set = load_case(dir / "p.yaml", {"parameters.d=6.0e-3", "parameters.theta=0"});
  EXPECT_EQ(set.bodies[0].mesh.radius, 3.0e-3);
  EXPECT_EQ(set.bodies[0].velocity.x(), 0.0);
  EXPECT_EQ(set.bodies[0].velocity.z(), -6500.0);
  // A parameter the case does not declare is refused with the closest name it does.
  for (const auto& [set, expect] : std::vector<std::pair<std::string, std::string>>{
           {"parameters.D=6.0e-3",
            "no parameter 'D' (did you mean 'd'?); its parameters: d, r, v, theta"},
           {"parameters.thetta=10", "no parameter 'thetta' (did you mean 'theta'?)"},
           {"parameters.speed=1", "no parameter 'speed'; its parameters"}}) {
    try {
      load_case(dir / "p.yaml", {set});
      ADD_FAILURE() << set << " accepted";
    } catch (const CaseError& e) {
      EXPECT_NE(std::string(e.what()).find("--set " + set + ": the case declares " + expect),
                std::string::npos)
          << e.what();
    }
  }
  // An error names the file's line, the key and the expression.
  test::write_text(
      dir / "bad.yaml",
      std::string(k_parametric).replace(std::string(k_parametric).find("= r\""), 4, "= q*2\""));
  try {
    load_case(dir / "bad.yaml");
    FAIL() << "an unknown name accepted";
  } catch (const CaseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(":13:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("bodies.0.mesh.sphere.radius"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown name 'q'"), std::string::npos) << msg;
  }
}
