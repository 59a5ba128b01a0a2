// The case file's validation kit: suggestions for unknown keys, overrides, YAML loading.
#include "case_reader.hpp"

#include <algorithm>

namespace tc {
namespace case_file {

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
                    const std::vector<std::string>& extra_keys) {
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

}  // namespace case_file

}  // namespace tc
