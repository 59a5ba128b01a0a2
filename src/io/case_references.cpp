// The case file's `reference:` values and measures and its `expect:` bounds.
#include "case_reader.hpp"

#include <algorithm>
#include <limits>

#include "tetcontact/diagnostics/expect.hpp"

namespace tc {
namespace case_file {

// The case's reference values and measures.
void read_references(const Reader& r, const YAML::Node& root, Case& c) {
  // A body the case has, by name.
  const auto body_name = [&](const YAML::Node& node, const std::string& path) {
    const std::string name = r.string(node, path);
    if (std::none_of(c.bodies.begin(), c.bodies.end(),
                     [&](const BodySpec& s) { return s.name == name; }))
      r.fail(node, path, "no body named '" + name + "'");
    return name;
  };
  // Reference values.
  if (const YAML::Node refs = root["reference"]) {
    r.each(refs, "reference", "reference values", [&](const YAML::Node& n, const std::string& p) {
      r.keys(n, p,
             {"name", "measure", "body", "axis", "component", "region", "area", "plane",
              "debris_of", "within", "time", "value", "tolerance", "source", "kind"});
      ReferenceSpec ref;
      ref.name = r.string(r.require(n, p, "name"), join(p, "name"));
      if (n["kind"]) {
        ref.kind = r.string(n["kind"], join(p, "kind"));
        if (ref.kind != "physical" && ref.kind != "regression")
          r.fail(n["kind"], join(p, "kind"), "kind must be physical or regression");
      }
      const YAML::Node m = r.require(n, p, "measure");
      using M = ReferenceSpec::Measure;
      ref.measure = r.choice(m, join(p, "measure"), ReferenceSpec::k_measure_names, "measure");
      const bool debris = ref.measure >= M::mass_through;
      for (const char* k : {"plane", "debris_of", "within"})
        if (!debris && n[k])
          r.fail(n[k], join(p, k),
                 "only the debris measures (perforated, mass_through, ...), thickness_left "
                 "and bulge take it");
      if ((ref.measure == M::thickness_left || ref.measure == M::bulge) && n["debris_of"])
        r.fail(n["debris_of"], join(p, "debris_of"),
               std::string(name_of(ReferenceSpec::k_measure_names, ref.measure)) +
                   " measures the body itself: it takes no debris_of");
      if (ref.measure == M::contact_duration || ref.measure == M::contact_max_force) {
        // whole-run figures: nothing more to say
      } else if (debris) {
        ref.body = body_name(r.require(n, p, "body"), join(p, "body"));
        const std::string pp = join(p, "plane");
        const YAML::Node pl = r.require(n, p, "plane");
        r.map(pl, pp);
        r.keys(pl, pp, {"point", "normal"});
        ref.plane_point = r.vec3(r.require(pl, pp, "point"), join(pp, "point"));
        const Vec3 normal = r.vec3(r.require(pl, pp, "normal"), join(pp, "normal"));
        if (normal.norm() == 0.0) r.fail(pl["normal"], join(pp, "normal"), "must be non-zero");
        ref.plane_normal = normal.normalized();
        if (n["within"]) ref.within = r.positive(n["within"], join(p, "within"), "m");
        if (const YAML::Node of = n["debris_of"])
          r.each(of, join(p, "debris_of"), "body names",
                 [&](const YAML::Node& e, const std::string& ep) {
                   ref.debris_of.push_back(body_name(e, ep));
                 });
      } else if (ref.measure == M::contact_mean_pressure) {
        ref.area = r.positive(r.require(n, p, "area"), join(p, "area"), "m^2");
      } else if (ref.measure == M::length || ref.measure == M::radius ||
                 ref.measure == M::velocity || ref.measure == M::hole_diameter) {
        ref.body = body_name(r.require(n, p, "body"), join(p, "body"));
        const YAML::Node a = r.require(n, p, "axis");
        const std::string axis = r.string(a, join(p, "axis"));
        if (axis != "x" && axis != "y" && axis != "z")
          r.fail(a, join(p, "axis"), "axis must be x, y or z");
        ref.axis = axis[0] - 'x';
        if (ref.measure == M::hole_diameter) {
          const Region reg = parse_region(r, r.require(n, p, "region"), join(p, "region"));
          ref.region_min = reg.min;
          ref.region_max = reg.max;
        }
      } else {
        const Region reg = parse_region(r, r.require(n, p, "region"), join(p, "region"));
        ref.region_min = reg.min;
        ref.region_max = reg.max;
        if (ref.measure == M::mean_stress) {
          const YAML::Node cmp = r.require(n, p, "component");
          static const std::vector<std::string> names{"xx", "yy", "zz", "xy", "yz", "xz"};
          const std::string cs = r.string(cmp, join(p, "component"));
          const auto it = std::find(names.begin(), names.end(), cs);
          if (it == names.end())
            r.fail(cmp, join(p, "component"), "component must be xx, yy, zz, xy, yz or xz");
          ref.component = static_cast<int>(it - names.begin());
        }
      }
      // Without value and tolerance a measure is reported, not judged.
      if (n["value"] || n["tolerance"]) {
        ref.value = r.number(r.require(n, p, "value"), join(p, "value"));
        if (ref.value == 0.0)
          r.fail(n["value"], join(p, "value"),
                 "a reference value must be non-zero (errors are relative)");
        ref.tolerance = r.positive(r.require(n, p, "tolerance"), join(p, "tolerance"), "relative");
      } else {
        ref.value = ref.tolerance = std::numeric_limits<double>::quiet_NaN();
      }
      if (n["source"]) ref.source = r.string(n["source"], join(p, "source"));
      if (const YAML::Node t = n["time"]) {
        if (ref.measure == M::contact_duration || ref.measure == M::contact_max_force ||
            ref.measure == M::contact_mean_pressure || ref.measure == M::velocity)
          r.fail(t, join(p, "time"), "this measure is of the whole run: it has no time");
        ref.time = r.positive(t, join(p, "time"), "s");
        if (ref.time > c.end_time) r.fail(t, join(p, "time"), "after the case's end_time");
      }
      c.references.push_back(ref);
    });
  }
}

// The bounds the run must hold (`expect`).
void read_expect(const Reader& r, const YAML::Node& root, Case& c) {
  // Bounds the run must hold (the stability cases state theirs).
  if (const YAML::Node e = root["expect"]) {
    const std::vector<std::string>& known = expect_figure_names();
    r.keys(e, "expect", known);
    for (const std::string& k : known)
      if (e[k]) {
        const double v = r.number(e[k], "expect." + k);
        if (!(v >= 0.0)) r.fail(e[k], "expect." + k, "a bound must be >= 0");
        c.expect.emplace_back(k, v);
      }
  }
}

}  // namespace case_file

}  // namespace tc
