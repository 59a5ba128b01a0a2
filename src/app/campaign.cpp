// `tetcontact campaign`: a case run per row of a table of experiments (campaign.hpp).
//
// A row becomes a run by overrides: every --set first, then `parameters.P=column × factor` for
// each mapped parameter and `materials.SLOT.from=ENTRY` for each mapped material. Its folder is
// keyed by the case file and those overrides (runs.hpp). A comparison of numbers reports the
// relative error e = predicted / measured − 1 and, over the rows, the median and the 90th
// percentile of |e| (the nearest rank: 90 % of the rows are within it); a comparison of
// categories reports the confusion table (measured × predicted) and the accuracy.
#include "tetcontact/app/campaign.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "tetcontact/app/runs.hpp"
#include "tetcontact/app/sweep.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/io/json.hpp"

namespace tc {
namespace {

namespace fs = std::filesystem;

std::string fmt(double x, const char* f = "%.9g") {
  if (std::isnan(x)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::optional<double> parse_number(const std::string& text) {
  const std::string s = trim(text);
  double v = 0.0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v))
    return std::nullopt;
  return v;
}

// A table of experiments: '#' lines are comments, the first other line names the columns,
// a units row may follow it; fields are separated by commas, quoted with '"' when they hold one.
struct Table {
  struct Row {
    int number = 0;  // among the data rows, from 1
    int line = 0;    // in the file
    std::vector<std::string> fields;
  };
  std::string path;
  std::vector<std::string> header;
  std::vector<Row> rows;

  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
  std::string where(const Row& r) const {
    return path + ": row " + std::to_string(r.number) + " (line " + std::to_string(r.line) + ")";
  }
  std::string columns() const {
    std::string s;
    for (const std::string& h : header) s += (s.empty() ? "" : ", ") + h;
    return s;
  }
};

std::vector<std::string> csv_fields(const std::string& line, const std::string& where) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        out.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  if (quoted) throw CaseError(where + ": a quote is not closed");
  for (std::string& f : out) f = trim(f);
  return out;
}

Table read_table(const std::string& path, bool units_row) {
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot read the table");
  Table t;
  t.path = path;
  std::string line;
  bool units_pending = units_row;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    const std::string where = path + ": line " + std::to_string(n);
    std::vector<std::string> f = csv_fields(line, where);
    if (t.header.empty()) {
      for (const std::string& h : f) {
        if (h.empty()) throw CaseError(where + ": a column without a name in the header");
        if (std::count(f.begin(), f.end(), h) > 1)
          throw CaseError(where + ": the column '" + h + "' is named twice");
      }
      t.header = std::move(f);
      continue;
    }
    if (units_pending) {  // the units under the header
      units_pending = false;
      continue;
    }
    Table::Row r{static_cast<int>(t.rows.size()) + 1, n, std::move(f)};
    if (r.fields.size() != t.header.size())
      throw CaseError(t.where(r) + ": " + std::to_string(r.fields.size()) +
                      " fields, the header has " + std::to_string(t.header.size()));
    t.rows.push_back(std::move(r));
  }
  if (t.header.empty()) throw CaseError(path + ": no header row (the columns' names)");
  return t;
}

// --rows: clauses separated by ';', each a list of row numbers and ranges or a condition on a
// column; a row runs when it meets them all.
std::vector<const Table::Row*> select_rows(const Table& t, const std::string& expr) {
  using Test = std::function<bool(const Table::Row&)>;
  std::vector<Test> tests;
  std::stringstream clauses(expr);
  for (std::string clause; std::getline(clauses, clause, ';');) {
    clause = trim(clause);
    if (clause.empty()) continue;
    const std::string bad = "--rows '" + expr + "': ";
    if (clause.find_first_not_of("0123456789-, ") == std::string::npos) {  // 1-20,35
      std::vector<std::pair<int, int>> ranges;
      std::stringstream parts(clause);
      for (std::string part; std::getline(parts, part, ',');) {
        part = trim(part);
        const auto dash = part.find('-');
        const std::string a = trim(part.substr(0, dash)),
                          b = dash == std::string::npos ? a : trim(part.substr(dash + 1));
        if (a.empty() || b.empty()) throw CaseError(bad + "'" + part + "' is not a row range");
        ranges.emplace_back(std::stoi(a), std::stoi(b));
      }
      tests.push_back([ranges](const Table::Row& r) {
        return std::any_of(ranges.begin(), ranges.end(), [&](const auto& ab) {
          return r.number >= ab.first && r.number <= ab.second;
        });
      });
      continue;
    }
    const auto at = clause.find_first_of("=!<>");
    if (at == std::string::npos || at == 0)
      throw CaseError(bad + "'" + clause +
                      "' is neither row numbers nor a condition COL=V, COL!=V, COL<V, COL>V");
    std::size_t len = 1;
    if (at + 1 < clause.size() && clause[at + 1] == '=') len = 2;
    const std::string op = clause.substr(at, len), name = trim(clause.substr(0, at)),
                      value = trim(clause.substr(at + len));
    if (op != "=" && op != "!=" && op != "<" && op != "<=" && op != ">" && op != ">=")
      throw CaseError(bad + "'" + clause + "': the comparison is one of = != < <= > >=");
    const int col = t.column(name);
    if (col < 0)
      throw CaseError(bad + "the table has no column '" + name + "' (its columns: " + t.columns() +
                      ")");
    const std::optional<double> number = parse_number(value);
    if ((op[0] == '<' || op[0] == '>') && !number)
      throw CaseError(bad + "'" + clause + "' compares with a number");
    tests.push_back([=](const Table::Row& r) {
      const std::string& field = r.fields[col];
      const std::optional<double> x = parse_number(field);
      if (op == "=") return number && x ? *x == *number : field == value;
      if (op == "!=") return number && x ? *x != *number : field != value;
      if (!x) return false;
      return op == "<"    ? *x < *number
             : op == "<=" ? *x <= *number
             : op == ">"  ? *x > *number
                          : *x >= *number;
    });
  }
  std::vector<const Table::Row*> out;
  for (const Table::Row& r : t.rows)
    if (std::all_of(tests.begin(), tests.end(), [&](const Test& f) { return f(r); }))
      out.push_back(&r);
  return out;
}

// What a row is: its overrides and inputs, and once run, what its summary says.
struct RowRun {
  const Table::Row* row = nullptr;
  std::vector<std::string> inputs;  // the mapped parameters' values, the materials' entries
  std::vector<std::string> sets;    // every override of its run
  std::string library;              // the material library its case reads
  ChildRun child;
  bool reused = false;
  std::string status = "not run";
  double wall = NAN;
  std::vector<double> predicted;                // per comparison (NaN: not measured)
  std::vector<std::optional<double>> measured;  // per comparison: a number, or a category's index
  // The case's shield equation on the row's shot (summary.shield_equation; none without it).
  std::optional<double> equation_critical_diameter;
  std::optional<bool> equation_perforated;
};

// The row's overrides and inputs, every field it reads checked (a message naming the row and
// the column).
RowRun plan_row(const Case& c, const Table& t, const Table::Row& row,
                const std::vector<std::string>& overrides) {
  const CampaignSpec& k = c.campaign;
  RowRun r;
  r.row = &row;
  r.sets = overrides;
  for (const CampaignSpec::Parameter& p : k.parameters) {
    const std::string& field = row.fields[t.column(p.column)];
    const std::optional<double> x = parse_number(field);
    if (!x)
      throw CaseError(t.where(row) + ", column " + p.column + ": '" + field +
                      "' is not a number (it sets the parameter " + p.name + ")");
    char buf[32];  // the shortest text that reads back as the same double
    const std::string value(buf, std::to_chars(buf, buf + sizeof buf, *x * p.factor).ptr);
    r.sets.push_back("parameters." + p.name + "=" + value);
    r.inputs.push_back(value);
  }
  for (const CampaignSpec::MaterialSlot& m : k.materials) {
    std::vector<std::string> values;
    for (const std::string& col : m.columns) values.push_back(row.fields[t.column(col)]);
    std::string entry;
    for (std::size_t n = values.size(); n > 0 && entry.empty(); --n) {  // longest key first
      std::string key;
      for (std::size_t i = 0; i < n; ++i) key += (i ? " | " : "") + values[i];
      for (const auto& [from, to] : m.names)
        if (from == key) entry = to;
    }
    if (entry.empty()) {
      std::string cols, key;
      for (std::size_t i = 0; i < values.size(); ++i) {
        cols += (i ? ", " : "") + m.columns[i];
        key += (i ? " | " : "") + values[i];
      }
      throw CaseError(t.where(row) + ", column " + cols + ": '" + key +
                      "' has no entry in campaign.materials." + m.slot + ".names");
    }
    r.sets.push_back("materials." + m.slot + ".from=" + entry);
    r.inputs.push_back(entry);
  }
  for (const CampaignSpec::Comparison& cmp : k.compare) {
    const int col = t.column(cmp.column);
    const std::string field = col < 0 ? std::string() : row.fields[col];
    if (field.empty()) {  // not measured in this row (or the table has no such column)
      r.measured.emplace_back();
    } else if (cmp.categories.empty()) {
      const std::optional<double> x = parse_number(field);
      if (!x)
        throw CaseError(t.where(row) + ", column " + cmp.column + ": '" + field +
                        "' is not a number (the measured " + cmp.predicted + ")");
      r.measured.emplace_back(*x * cmp.factor);
    } else {
      const auto it = std::find_if(cmp.categories.begin(), cmp.categories.end(),
                                   [&](const auto& cat) { return cat.first == field; });
      if (it == cmp.categories.end()) {
        std::string names;
        for (const auto& cat : cmp.categories) names += (names.empty() ? "" : ", ") + cat.first;
        throw CaseError(t.where(row) + ", column " + cmp.column + ": '" + field +
                        "' is none of the categories " + names);
      }
      r.measured.emplace_back(static_cast<double>(it - cmp.categories.begin()));
    }
  }
  return r;
}

// The prediction of a comparison from a measure's value: the number (times nothing), or the
// index of the category whose value is nearest.
double prediction(const CampaignSpec::Comparison& cmp, double measure) {
  if (cmp.categories.empty() || std::isnan(measure)) return measure;
  std::size_t best = 0;
  for (std::size_t i = 1; i < cmp.categories.size(); ++i)
    if (std::abs(cmp.categories[i].second - measure) <
        std::abs(cmp.categories[best].second - measure))
      best = i;
  return static_cast<double>(best);
}

// A finished run's summary: status, wall time, the compared measures.
void read_summary(const CampaignSpec& k, RowRun& r) {
  std::ifstream in(r.child.dir + "/summary.json");
  Json s;
  try {
    s = Json::parse(in);
  } catch (const std::exception&) {
    r.status = "the run wrote no summary (exit status " + std::to_string(r.child.exit_code) +
               "; see " + r.child.dir + "/run.log)";
    return;
  }
  r.status = s.value("status", std::string("?"));
  r.wall = s.value("wall_seconds", NAN);
  r.predicted.assign(k.compare.size(), NAN);
  for (std::size_t i = 0; i < k.compare.size(); ++i)
    if (s.contains("references"))
      for (const Json& ref : s["references"])
        if (ref.value("name", std::string()) == k.compare[i].predicted &&
            ref["measured"].is_number())
          r.predicted[i] = prediction(k.compare[i], ref["measured"].get<double>());
  if (const auto e = s.find("shield_equation"); e != s.end() && e->is_object()) {
    r.equation_critical_diameter = e->value("critical_diameter", NAN);
    r.equation_perforated = e->value("perforated", false);
  }
}

// The comparison the shield equation's verdict stands beside: the one whose prediction is the
// engine's verdict the case sets against it (none: the case declares no equation).
std::optional<std::size_t> equation_comparison(const Case& c) {
  if (!c.shield_equation.declared) return std::nullopt;
  for (std::size_t i = 0; i < c.campaign.compare.size(); ++i)
    if (c.campaign.compare[i].predicted == c.shield_equation.verdict &&
        !c.campaign.compare[i].categories.empty())
      return i;
  return std::nullopt;
}

// The equation's verdict as the comparison's category: the one whose value is nearest 1 (P) or
// 0 (NP).
std::optional<double> equation_category(const CampaignSpec::Comparison& cmp, const RowRun& r) {
  if (!r.equation_perforated) return std::nullopt;
  return prediction(cmp, *r.equation_perforated ? 1.0 : 0.0);
}

// The statistics of one comparison over some rows.
Json statistics(const CampaignSpec::Comparison& cmp, const std::vector<const RowRun*>& rows,
                std::size_t i, bool equation) {
  Json j = Json::object();
  if (cmp.categories.empty()) {
    std::vector<double> e, abs_e;
    for (const RowRun* r : rows)
      if (r->measured[i] && i < r->predicted.size() && !std::isnan(r->predicted[i])) {
        e.push_back(r->predicted[i] / *r->measured[i] - 1.0);
        abs_e.push_back(std::abs(e.back()));
      }
    std::sort(abs_e.begin(), abs_e.end());
    const std::size_t n = abs_e.size();
    j["compared"] = n;
    const auto rank = [&](double q) {  // nearest rank: a fraction q of the rows within it
      return abs_e[static_cast<std::size_t>(std::max(1.0, std::ceil(q * n))) - 1];
    };
    j["median_abs_error"] = n == 0  ? NAN
                            : n % 2 ? abs_e[n / 2]
                                    : 0.5 * (abs_e[n / 2 - 1] + abs_e[n / 2]);
    j["p90_abs_error"] = n == 0 ? NAN : rank(0.9);
    j["max_abs_error"] = n == 0 ? NAN : abs_e.back();
    double sum = 0.0;
    for (const double x : e) sum += x;
    j["mean_error"] = n == 0 ? NAN : sum / n;
    if (cmp.tolerance > 0.0) {
      j["tolerance"] = cmp.tolerance;
      j["within_tolerance"] =
          n == 0 ? NAN
                 : static_cast<double>(std::count_if(
                       abs_e.begin(), abs_e.end(), [&](double x) { return x <= cmp.tolerance; })) /
                       n;
    }
  } else {
    const std::size_t m = cmp.categories.size();
    std::vector<std::vector<long>> table(m, std::vector<long>(m, 0));
    long right = 0, n = 0;
    for (const RowRun* r : rows)
      if (r->measured[i] && i < r->predicted.size() && !std::isnan(r->predicted[i])) {
        const auto a = static_cast<std::size_t>(*r->measured[i]),
                   b = static_cast<std::size_t>(r->predicted[i]);
        ++table[a][b];
        ++n;
        right += a == b;
      }
    j["compared"] = n;
    j["accuracy"] = n == 0 ? NAN : static_cast<double>(right) / n;
    Json confusion = Json::object();  // measured → predicted → rows
    for (std::size_t a = 0; a < m; ++a) {
      Json line = Json::object();
      for (std::size_t b = 0; b < m; ++b) line[cmp.categories[b].first] = table[a][b];
      confusion[cmp.categories[a].first] = line;
    }
    j["confusion"] = confusion;
    if (equation) {  // the shield equation on the same rows
      long eq_right = 0, eq_n = 0;
      for (const RowRun* r : rows)
        if (const auto e = equation_category(cmp, *r);
            e && r->measured[i] && i < r->predicted.size() && !std::isnan(r->predicted[i])) {
          ++eq_n;
          eq_right += *e == *r->measured[i];
        }
      j["equation_compared"] = eq_n;
      j["equation_accuracy"] = eq_n == 0 ? NAN : static_cast<double>(eq_right) / eq_n;
    }
  }
  return j;
}

std::string group_of(const CampaignSpec& k, const Table& t, const Table::Row& row) {
  std::string g;
  for (const std::string& col : k.group_by)
    g += (g.empty() ? "" : " | ") + row.fields[t.column(col)];
  return g;
}

std::string predictions_csv(const Case& c, const Table& t, const std::vector<RowRun>& runs) {
  const CampaignSpec& k = c.campaign;
  std::ostringstream csv;
  csv << "row,line";
  for (const std::string& g : k.group_by) csv << ',' << csv_field(g);
  for (const auto& p : k.parameters) csv << ',' << csv_field("parameters." + p.name);
  for (const auto& m : k.materials) csv << ',' << csv_field("materials." + m.slot);
  for (const auto& cmp : k.compare)
    csv << ',' << csv_field("predicted:" + cmp.predicted) << ','
        << csv_field("measured:" + cmp.predicted) << ','
        << csv_field((cmp.categories.empty() ? "error:" : "right:") + cmp.predicted);
  const std::optional<std::size_t> eq = equation_comparison(c);
  if (eq)  // the shield equation beside the engine: its critical diameter (m) and verdict
    csv << ",equation:critical_diameter," << csv_field("equation:" + k.compare[*eq].predicted)
        << ',' << csv_field("right:equation");
  csv << ",status,wall_seconds,folder\n";
  for (const RowRun& r : runs) {
    csv << r.row->number << ',' << r.row->line;
    for (const std::string& g : k.group_by) csv << ',' << csv_field(r.row->fields[t.column(g)]);
    for (const std::string& in : r.inputs) csv << ',' << csv_field(in);
    for (std::size_t i = 0; i < k.compare.size(); ++i) {
      const auto& cmp = k.compare[i];
      const double p = i < r.predicted.size() ? r.predicted[i] : NAN;
      const std::optional<double>& m = r.measured[i];
      if (cmp.categories.empty()) {
        csv << ',' << fmt(p) << ',' << (m ? fmt(*m) : "") << ','
            << (m && !std::isnan(p) ? fmt(p / *m - 1.0, "%.6g") : "");
      } else {
        const auto name = [&](double x) {
          return csv_field(cmp.categories[static_cast<std::size_t>(x)].first);
        };
        csv << ',' << (std::isnan(p) ? "" : name(p)) << ',' << (m ? name(*m) : "") << ','
            << (m && !std::isnan(p) ? (static_cast<double>(*m) == p ? "1" : "0") : "");
      }
    }
    if (eq) {
      const auto& cmp = k.compare[*eq];
      const std::optional<double> e = equation_category(cmp, r);
      const std::optional<double>& m = r.measured[*eq];
      csv << ','
          << (r.equation_critical_diameter ? fmt(*r.equation_critical_diameter) : std::string())
          << ','
          << (e ? csv_field(cmp.categories[static_cast<std::size_t>(*e)].first) : std::string())
          << ',' << (e && m ? (*e == *m ? "1" : "0") : "");
    }
    csv << ',' << csv_field(r.status) << ',' << fmt(r.wall, "%.4g") << ','
        << csv_field(fs::path(r.child.dir).filename().string()) << '\n';
  }
  return csv.str();
}

Json statistics_json(const Case& c, const Table& t, const std::vector<RowRun>& runs) {
  const CampaignSpec& k = c.campaign;
  Json j = Json::object();
  j["case"] = c.file;
  j["table"] = t.path;
  j["rows"] = runs.size();
  j["failed"] =
      std::count_if(runs.begin(), runs.end(), [](const RowRun& r) { return r.status != "ok"; });
  Json comparisons = Json::array();
  for (std::size_t i = 0; i < k.compare.size(); ++i) {
    Json one = Json::object();
    one["predicted"] = k.compare[i].predicted;
    one["measured"] = k.compare[i].column;
    std::vector<const RowRun*> all;
    std::map<std::string, std::vector<const RowRun*>> groups;  // sorted by the group's values
    for (const RowRun& r : runs) {
      all.push_back(&r);
      if (!k.group_by.empty()) groups[group_of(k, t, *r.row)].push_back(&r);
    }
    const bool equation = equation_comparison(c) == i;
    one["all"] = statistics(k.compare[i], all, i, equation);
    if (!k.group_by.empty()) {
      Json g = Json::object();
      for (const auto& [name, rows] : groups) g[name] = statistics(k.compare[i], rows, i, equation);
      one["groups"] = g;
    }
    comparisons.push_back(one);
  }
  j["comparisons"] = comparisons;
  return j;
}

// The console's table: a line per comparison and group.
std::string statistics_table(const Case& c, const Json& stats) {
  std::ostringstream os;
  const auto line = [&](const std::string& group, const Json& s, bool categories) {
    os << "  " << group << ": " << s["compared"].get<long>() << " compared";
    const auto pct = [](const Json& x) {
      return x.is_number() ? fmt(100.0 * x.get<double>(), "%.1f") + " %" : std::string("-");
    };
    if (categories) {
      os << ", accuracy " << pct(s["accuracy"]) << " (measured → predicted:";
      for (const auto& [a, row] : s["confusion"].items())
        for (const auto& [b, n] : row.items()) os << " " << a << "→" << b << " " << n.get<long>();
      os << ")";
      if (s.contains("equation_accuracy"))
        os << "; Christiansen's equation on the same rows: accuracy "
           << pct(s["equation_accuracy"]);
    } else {
      os << ", |error| median " << pct(s["median_abs_error"]) << ", 90 % within "
         << pct(s["p90_abs_error"]) << ", max " << pct(s["max_abs_error"]) << ", mean error "
         << pct(s["mean_error"]);
      if (s.contains("within_tolerance"))
        os << ", within " << pct(s["tolerance"]) << ": " << pct(s["within_tolerance"]);
    }
    os << "\n";
  };
  for (std::size_t i = 0; i < c.campaign.compare.size(); ++i) {
    const Json& one = stats["comparisons"][i];
    const bool categories = !c.campaign.compare[i].categories.empty();
    os << one["predicted"].get<std::string>() << " against " << one["measured"].get<std::string>()
       << "\n";
    line("all", one["all"], categories);
    if (one.contains("groups"))
      for (const auto& [name, s] : one["groups"].items()) line(name, s, categories);
  }
  return os.str();
}

// The figure, by tools/post/plot_campaign.py beside the data folder run by Debian's python3
// (with matplotlib) when it is there; a note when it cannot be made (no python3 or matplotlib, or
// the tools are not there), never an error of the campaign.
void plot(const std::string& dir, bool quiet) {
  std::string script;
  try {
    script = (fs::path(data_dir()).parent_path() / "tools/post/plot_campaign.py").string();
  } catch (const std::exception&) {
  }
  std::string note;
  if (script.empty() || !fs::exists(script)) {
    note = "tools/post/plot_campaign.py not found beside the data folder";
  } else if (const int code = run_program(
                 {fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3", script, dir},
                 dir + "/plot.log");
             code != 0) {
    note = "plot_campaign.py exit status " + std::to_string(code) + " (see " + dir + "/plot.log)";
  } else {
    fs::remove(dir + "/plot.log");
    return;
  }
  if (!quiet) std::cerr << "campaign: no figure: " << note << "\n";
}

}  // namespace

int campaign_command(const CampaignOptions& o) {
  // Everything is checked before anything runs: the case, the table, each selected row's
  // overrides and the case they make.
  Case c;
  Table t;
  std::vector<RowRun> runs;
  InputFiles inputs;  // the text the runs' keys hold: an edit meanwhile stops the campaign
  try {
    if (fs::is_regular_file(o.case_path)) inputs.add(o.case_path);  // else load_case says why
    c = load_case(o.case_path, o.overrides);
    if (!c.campaign.declared)
      throw CaseError(o.case_path +
                      ": the case has no `campaign:` block (which columns set which parameters, "
                      "which measure is compared with which column)");
    t = read_table(o.table_path, c.campaign.units_row);
    std::vector<std::string> needed;
    for (const auto& p : c.campaign.parameters) needed.push_back(p.column);
    for (const auto& m : c.campaign.materials)
      needed.insert(needed.end(), m.columns.begin(), m.columns.end());
    needed.insert(needed.end(), c.campaign.group_by.begin(), c.campaign.group_by.end());
    for (const std::string& col : needed)
      if (t.column(col) < 0)
        throw CaseError(t.path + ": no column '" + col +
                        "', which the case's campaign reads (the table's columns: " + t.columns() +
                        ")");
    for (const auto& cmp : c.campaign.compare)
      if (t.column(cmp.column) < 0 && !o.quiet)
        std::cerr << "campaign: the table has no column '" << cmp.column << "': " << cmp.predicted
                  << " is predicted, not compared\n";
    const std::vector<const Table::Row*> rows = select_rows(t, o.rows);
    if (rows.empty())
      throw CaseError(t.path + ": no row selected" +
                      (o.rows.empty() ? std::string() : " by --rows '" + o.rows + "'"));
    for (const Table::Row* row : rows) {
      RowRun r = plan_row(c, t, *row, o.overrides);
      try {
        r.library = load_case(o.case_path, r.sets).material_library;
      } catch (const CaseError& e) {
        throw CaseError(t.where(*row) + ": " + e.what());
      }
      inputs.add(r.library);
      runs.push_back(std::move(r));
    }
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  if (o.check) {
    std::cout << "campaign: " << runs.size() << " of " << t.rows.size() << " rows of " << t.path
              << " checked: each makes a valid case; nothing run\n";
    return 0;
  }
  const std::string dir = o.out_dir.empty() ? "results/" + c.name + "-campaign" : o.out_dir;
  RunsFolderLock lock;
  try {
    lock = prepare_runs_folder(dir);
  } catch (const OutputError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }

  std::vector<ChildRun*> todo;
  for (RowRun& r : runs) {
    r.child.key = run_key(o.case_path, r.sets, r.library);
    r.child.dir =
        dir + "/runs/" + run_folder_name("row-" + std::to_string(r.row->number), r.child.key);
    r.child.args = {"run", o.case_path, "--out", r.child.dir, "--force", "--threads", "1"};
    for (const std::string& s : r.sets) r.child.args.insert(r.child.args.end(), {"--set", s});
    if (finished_run(r.child)) {
      r.reused = true;
      read_summary(c.campaign, r);
    } else {
      todo.push_back(&r.child);
    }
  }
  const int jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
  const auto started = std::chrono::steady_clock::now();
  const bool tty = isatty(STDERR_FILENO);
  std::size_t done = 0, failed = 0;
  const std::size_t reused = runs.size() - todo.size();
  if (!o.quiet)
    std::cerr << "campaign: " << runs.size() << " rows of " << t.path << ", " << reused
              << " read from earlier runs, " << todo.size() << " to run, " << jobs
              << " at a time, into " << dir << "\n";
  try {
    run_children(
        todo, jobs,
        [&](ChildRun& child) {
          for (RowRun& r : runs)
            if (&r.child == &child) {
              read_summary(c.campaign, r);
              failed += r.status != "ok";
            }
          ++done;
          if (o.quiet) return;
          const double s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
          std::cerr << (tty ? "\r" : "") << "campaign: " << done << "/" << todo.size() << " run, "
                    << failed << " failed, " << fmt(s, "%.0f") << " s, about "
                    << fmt(s / done * (todo.size() - done), "%.0f") << " s left"
                    << (tty ? "   " : "\n");
        },
        &inputs);
  } catch (const InputsChanged& e) {
    std::cerr << (tty && !o.quiet ? "\n" : "") << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  if (tty && !o.quiet && !todo.empty()) std::cerr << "\n";

  try {
    inputs.require_unchanged();  // an edit after the last run started, or before any did
  } catch (const InputsChanged& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
    return 2;
  }
  const Json stats = statistics_json(c, t, runs);
  write_file_atomic(dir + "/predictions.csv", predictions_csv(c, t, runs));
  write_file_atomic(dir + "/statistics.json", stats.dump(2) + "\n");
  plot(dir, o.quiet);
  std::cout << statistics_table(c, stats) << "written: " << dir << "/predictions.csv, " << dir
            << "/statistics.json\n";
  failed = static_cast<std::size_t>(stats["failed"].get<long>());
  if (failed > 0)
    std::cerr << "campaign: " << failed << " of " << runs.size()
              << " runs failed (predictions.csv's status column says why)\n";
  return failed > 0 ? 1 : 0;
}

}  // namespace tc
