// The case file's `campaign:` block: how `tetcontact campaign` maps a table of experiments onto
// the case (app/campaign.hpp). Everything it names is checked here, against the case: the
// parameters it declares, the materials it has (taken `from` the library), the library's
// entries, the `reference:` measures.
#include <algorithm>

#include "case_reader.hpp"

namespace tc {
namespace case_file {

namespace {

// A column's name: a non-empty string.
std::string column_name(const Reader& r, const YAML::Node& n, const std::string& path) {
  const std::string s = r.string(n, path);
  if (s.empty()) r.fail(n, path, "a column's name must not be empty");
  return s;
}

void read_campaign_parameters(const Reader& r, const YAML::Node& p, Case& c) {
  r.map(p, "campaign.parameters");
  for (auto it = p.begin(); it != p.end(); ++it) {
    const std::string name = it->first.Scalar(), path = join("campaign.parameters", name);
    if (std::none_of(c.parameters.begin(), c.parameters.end(),
                     [&](const auto& q) { return q.first == name; }))
      r.fail(it->first, path, "the case declares no parameter '" + name + "'");
    CampaignSpec::Parameter q;
    q.name = name;
    if (it->second.IsMap()) {  // {column: C, factor: F}
      r.keys(it->second, path, {"column", "factor"});
      q.column = column_name(r, r.require(it->second, path, "column"), join(path, "column"));
      if (it->second["factor"]) q.factor = r.number(it->second["factor"], join(path, "factor"));
    } else {  // C
      q.column = column_name(r, it->second, path);
    }
    c.campaign.parameters.push_back(q);
  }
}

void read_campaign_materials(const Reader& r, const YAML::Node& root, const YAML::Node& m,
                             Case& c) {
  r.map(m, "campaign.materials");
  YAML::Node library;  // the entries the names map to
  bool library_loaded = false;
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string slot = it->first.Scalar(), path = join("campaign.materials", slot);
    const YAML::Node entry = root["materials"] ? root["materials"][slot] : YAML::Node();
    if (!entry || !entry.IsMap() || !entry["from"])
      r.fail(it->first, path,
             "the case has no material '" + slot +
                 "' taken `from:` the library (the table names a library entry for it)");
    r.keys(it->second, path, {"column", "columns", "names"});
    CampaignSpec::MaterialSlot s;
    s.slot = slot;
    if (it->second["column"] && it->second["columns"])
      r.fail(it->second, path, "give column or columns, not both");
    if (const YAML::Node one = it->second["column"]) {
      s.columns.push_back(column_name(r, one, join(path, "column")));
    } else {
      const YAML::Node list = r.require(it->second, path, "columns");
      r.each(list, join(path, "columns"), "column names",
             [&](const YAML::Node& e, const std::string& ep) {
               s.columns.push_back(column_name(r, e, ep));
             });
      if (s.columns.empty()) r.fail(list, join(path, "columns"), "name at least one column");
    }
    if (!library_loaded) {
      library = YAML::LoadFile(c.material_library.empty() ? default_material_library()
                                                          : c.material_library);
      library_loaded = true;
    }
    const YAML::Node names = r.require(it->second, path, "names");
    r.map(names, join(path, "names"));
    for (auto n = names.begin(); n != names.end(); ++n) {
      const std::string to = r.string(n->second, join(join(path, "names"), n->first.Scalar()));
      const YAML::Node& lib = library;  // const: a lookup must not add the key
      if (!lib[to])
        r.fail(n->second, join(join(path, "names"), n->first.Scalar()),
               "no material '" + to + "' in the library");
      s.names.emplace_back(n->first.Scalar(), to);
    }
    c.campaign.materials.push_back(s);
  }
}

void read_campaign_compare(const Reader& r, const YAML::Node& list, Case& c) {
  r.each(list, "campaign.compare", "comparisons", [&](const YAML::Node& n, const std::string& p) {
    r.keys(n, p, {"predicted", "measured", "factor", "tolerance", "categories"});
    CampaignSpec::Comparison k;
    k.predicted = r.string(r.require(n, p, "predicted"), join(p, "predicted"));
    if (std::none_of(c.references.begin(), c.references.end(),
                     [&](const ReferenceSpec& ref) { return ref.name == k.predicted; }))
      r.fail(n["predicted"], join(p, "predicted"),
             "no `reference:` entry named '" + k.predicted + "' (the measure predicted)");
    k.column = column_name(r, r.require(n, p, "measured"), join(p, "measured"));
    if (n["factor"]) k.factor = r.number(n["factor"], join(p, "factor"));
    if (n["tolerance"]) k.tolerance = r.positive(n["tolerance"], join(p, "tolerance"), "relative");
    if (const YAML::Node cat = n["categories"]) {
      r.map(cat, join(p, "categories"));
      for (auto e = cat.begin(); e != cat.end(); ++e)
        k.categories.emplace_back(
            e->first.Scalar(), r.number(e->second, join(join(p, "categories"), e->first.Scalar())));
      if (k.categories.size() < 2)
        r.fail(cat, join(p, "categories"), "name two categories or more");
      if (n["factor"] || n["tolerance"])
        r.fail(n, p, "a comparison of categories takes no factor or tolerance");
    }
    c.campaign.compare.push_back(k);
  });
  if (c.campaign.compare.empty())
    r.fail(list, "campaign.compare", "name at least one measure to compare");
}

}  // namespace

void read_campaign(const Reader& r, const YAML::Node& root, Case& c) {
  const YAML::Node n = root["campaign"];
  if (!n) return;
  r.keys(n, "campaign", {"units_row", "parameters", "materials", "compare", "group_by"});
  c.campaign.declared = true;
  if (n["units_row"]) c.campaign.units_row = r.boolean(n["units_row"], "campaign.units_row");
  if (n["parameters"]) read_campaign_parameters(r, n["parameters"], c);
  if (n["materials"]) read_campaign_materials(r, root, n["materials"], c);
  read_campaign_compare(r, r.require(n, "campaign", "compare"), c);
  if (const YAML::Node g = n["group_by"])
    r.each(g, "campaign.group_by", "column names", [&](const YAML::Node& e, const std::string& p) {
      c.campaign.group_by.push_back(column_name(r, e, p));
    });
}

}  // namespace case_file
}  // namespace tc
