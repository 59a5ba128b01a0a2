#include "tetcontact/io/json.hpp"

#include <cmath>
#include <cstdio>

#include "tetcontact/io/files.hpp"

namespace tc {

Json& Json::operator[](const std::string& key) {
  if (!std::holds_alternative<Object>(v_)) v_ = Object{};
  auto& obj = std::get<Object>(v_);
  for (auto& [k, v] : obj)
    if (k == key) return v;
  obj.emplace_back(key, Json());
  return obj.back().second;
}

void Json::push_back(Json value) {
  if (!std::holds_alternative<Array>(v_)) v_ = Array{};
  std::get<Array>(v_).push_back(std::move(value));
}

std::string Json::dump(int indent) const {
  std::string out;
  dump_to(out, indent, 0);
  out += '\n';
  return out;
}

namespace {
void escape(std::string& out, const std::string& s) {
  out += '"';
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  out += '"';
}
}  // namespace

void Json::dump_to(std::string& out, int indent, int depth) const {
  const std::string pad(static_cast<std::size_t>(indent * (depth + 1)), ' ');
  const std::string pad_end(static_cast<std::size_t>(indent * depth), ' ');
  if (std::holds_alternative<std::nullptr_t>(v_)) {
    out += "null";
  } else if (const bool* b = std::get_if<bool>(&v_)) {
    out += *b ? "true" : "false";
  } else if (const double* d = std::get_if<double>(&v_)) {
    out += std::isfinite(*d) ? format_double(*d) : "null";
  } else if (const std::string* s = std::get_if<std::string>(&v_)) {
    escape(out, *s);
  } else if (const Array* a = std::get_if<Array>(&v_)) {
    // Short arrays of scalars stay on one line (vectors, bounding boxes).
    bool flat = a->size() <= 4;
    for (const Json& e : *a)
      flat = flat && !std::holds_alternative<Array>(e.v_) && !std::holds_alternative<Object>(e.v_);
    out += '[';
    for (std::size_t i = 0; i < a->size(); ++i) {
      out += i ? "," : "";
      if (flat) {
        out += i ? " " : "";
      } else {
        out += "\n" + pad;
      }
      (*a)[i].dump_to(out, indent, depth + 1);
    }
    if (!flat && !a->empty()) out += "\n" + pad_end;
    out += ']';
  } else {
    const Object& o = std::get<Object>(v_);
    out += '{';
    for (std::size_t i = 0; i < o.size(); ++i) {
      out += i ? ",\n" : "\n";
      out += pad;
      escape(out, o[i].first);
      out += ": ";
      o[i].second.dump_to(out, indent, depth + 1);
    }
    if (!o.empty()) out += "\n" + pad_end;
    out += '}';
  }
}

}  // namespace tc
