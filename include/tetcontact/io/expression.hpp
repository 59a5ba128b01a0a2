// Arithmetic expressions over a case's parameters (the values a designer varies, as
// case keys). A case file's scalar that starts with '=' is an expression:
//   radius: "= d / 2"
//   velocity: ["= v * sin(theta * deg)", 0, "= -v * cos(theta * deg)"]
// over the names of its `parameters:` map, which `--set parameters.NAME=VALUE` changes.
//
// Grammar: sum := product (('+' | '-') product)*; product := power (('*' | '/') power)*;
// power := unary ('^' power)?; unary := ('-' | '+') unary | primary; primary := number | name |
// name '(' sum (',' sum)* ')' | '(' sum ')'. Functions: sin cos tan asin acos atan sqrt exp log
// abs round ceil floor (a cell count must come out an integer), and min max of two.
// Constants: pi, deg (= pi / 180).
#pragma once

#include <map>
#include <stdexcept>
#include <string>

namespace tc {

/// An expression that cannot be evaluated: the message says why and where (a column).
struct ExpressionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Evaluates `text` (without the leading '=') with `names` bound; throws ExpressionError on a
/// syntax error, an unknown name or function, or a result that is not finite.
double evaluate_expression(const std::string& text, const std::map<std::string, double>& names);

}  // namespace tc
