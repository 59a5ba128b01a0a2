// A recursive-descent evaluator of the grammar in expression.hpp.
#include "tetcontact/io/expression.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <vector>

namespace tc {
namespace {

class Parser {
 public:
  Parser(const std::string& text, const std::map<std::string, double>& names)
      : s_(text), names_(names) {}

  double parse() {
    const double v = sum();
    skip();
    if (i_ != s_.size()) fail("unexpected '" + std::string(1, s_[i_]) + "'");
    if (!std::isfinite(v)) fail("the value is not finite");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& msg) const {
    throw ExpressionError(msg + " at column " + std::to_string(i_ + 1));
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }

  double sum() {
    double v = product();
    for (;;) {
      if (eat('+')) {
        v += product();
      } else if (eat('-')) {
        v -= product();
      } else {
        return v;
      }
    }
  }
  double product() {
    double v = power();
    for (;;) {
      if (eat('*')) {
        v *= power();
      } else if (eat('/')) {
        v /= power();
      } else {
        return v;
      }
    }
  }
  double power() {
    const double base = unary();
    if (eat('^')) return std::pow(base, power());  // right-associative
    return base;
  }
  double unary() {
    if (eat('-')) return -unary();
    if (eat('+')) return unary();
    return primary();
  }
  double primary() {
    skip();
    if (i_ >= s_.size()) fail("expected a number, a name or '('");
    if (eat('(')) {
      const double v = sum();
      if (!eat(')')) fail("expected ')'");
      return v;
    }
    const char c = s_[i_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) fail("expected a number");
      i_ += static_cast<std::size_t>(end - begin);
      return v;
    }
    if (!std::isalpha(static_cast<unsigned char>(c)) && c != '_')
      fail("expected a number, a name or '('");
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
      ++i_;
    const std::string name = s_.substr(start, i_ - start);
    if (eat('(')) {
      std::vector<double> args{sum()};
      while (eat(',')) args.push_back(sum());
      if (!eat(')')) fail("expected ')'");
      return call(name, args, start);
    }
    if (const auto it = names_.find(name); it != names_.end()) return it->second;
    if (name == "pi") return std::numbers::pi;
    if (name == "deg") return std::numbers::pi / 180.0;
    i_ = start;
    fail("unknown name '" + name + "'");
  }
  double call(const std::string& f, const std::vector<double>& args, std::size_t at) {
    using One = double (*)(double);
    static const std::map<std::string, One> one{{"sin", [](double x) { return std::sin(x); }},
                                                {"cos", [](double x) { return std::cos(x); }},
                                                {"tan", [](double x) { return std::tan(x); }},
                                                {"asin", [](double x) { return std::asin(x); }},
                                                {"acos", [](double x) { return std::acos(x); }},
                                                {"atan", [](double x) { return std::atan(x); }},
                                                {"sqrt", [](double x) { return std::sqrt(x); }},
                                                {"exp", [](double x) { return std::exp(x); }},
                                                {"log", [](double x) { return std::log(x); }},
                                                {"abs", [](double x) { return std::abs(x); }},
                                                {"round", [](double x) { return std::round(x); }},
                                                {"ceil", [](double x) { return std::ceil(x); }},
                                                {"floor", [](double x) { return std::floor(x); }}};
    const bool two = f == "min" || f == "max";
    const auto it = one.find(f);
    const auto fail_at = [&](const std::string& msg) {
      i_ = at;  // the error's column: the function's name
      fail(msg);
    };
    if (!two && it == one.end()) fail_at("unknown function '" + f + "'");
    if (args.size() != (two ? 2u : 1u))
      fail_at("'" + f + "' takes " + (two ? "two arguments" : "one argument"));
    if (two) return f == "min" ? std::min(args[0], args[1]) : std::max(args[0], args[1]);
    return it->second(args[0]);
  }

  const std::string& s_;
  const std::map<std::string, double>& names_;
  std::size_t i_ = 0;
};

}  // namespace

double evaluate_expression(const std::string& text, const std::map<std::string, double>& names) {
  return Parser(text, names).parse();
}

}  // namespace tc
