#include "cellml/model_reader.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "cellml/import_error.hpp"

namespace fibrodem::cellml {

namespace {

const std::map<std::string, std::string> kVersions = {
    {"http://www.cellml.org/cellml/1.0#", "1.0"},
    {"http://www.cellml.org/cellml/1.1#", "1.1"},
    {"http://www.cellml.org/cellml/2.0#", "2.0"}};

std::vector<pugi::xml_node> elements(const pugi::xml_node& parent, const std::string& tag) {
  std::vector<pugi::xml_node> out;
  for (const auto& c : parent.children())
    if (c.type() == pugi::node_element && local_name(c) == tag) out.push_back(c);
  return out;
}

// Named units of the model and of each component (1.x allows both), resolved
// on demand so that definitions may come in any order; a cycle is refused.
class UnitScope {
 public:
  UnitScope(const std::string& text) : text_(text) {}
  void define(const std::string& scope, const pugi::xml_node& units) {
    const std::string name = attribute(units, "name");
    if (name.empty()) throw ImportError(element_path(units, text_) + ": <units> without a name");
    defs_[{scope, name}] = units;
  }
  Unit resolve(const std::string& scope, const std::string& name, const std::string& where) {
    if (const auto it = done_.find({scope, name}); it != done_.end()) return it->second;
    auto def = defs_.find({scope, name});
    std::string def_scope = scope;
    if (def == defs_.end()) {
      def = defs_.find({"", name});
      def_scope = "";
    }
    if (def == defs_.end()) {
      if (auto b = builtin_unit(name)) return *b;
      throw ImportError(where + ": unknown units '" + name + "'");
    }
    if (!busy_.insert({def_scope, name}).second)
      throw ImportError(element_path(def->second, text_) + ": units '" + name + "' defined in terms of itself");
    Unit u = build(def_scope, def->second);
    busy_.erase({def_scope, name});
    done_[{scope, name}] = u;
    return u;
  }

 private:
  Unit build(const std::string& scope, const pugi::xml_node& units) {
    Unit u;
    const std::string name = attribute(units, "name");
    if (attribute(units, "base_units") == "yes") {
      u.dims[name] = 1;  // a new base unit of the model's own
      return u;
    }
    for (const auto& part : elements(units, "unit")) {
      const std::string where = element_path(part, text_);
      const Unit base = resolve(scope, attribute(part, "units"), where);
      auto number = [&](const char* attr, double fallback) {
        const std::string s = attribute(part, attr);
        if (s.empty()) return fallback;
        try {
          return std::stod(s);
        } catch (const std::exception&) {
          throw ImportError(where + ": " + attr + "=\"" + s + "\" is not a number");
        }
      };
      double prefix = 0;
      if (const std::string p = attribute(part, "prefix"); !p.empty()) {
        const auto e = prefix_exponent(p);
        if (!e) throw ImportError(where + ": unknown prefix '" + p + "'");
        prefix = *e;
      }
      const double exponent = number("exponent", 1.0), multiplier = number("multiplier", 1.0);
      const double offset = number("offset", 0.0);
      if (offset != 0.0 || base.offset != 0.0)
        throw ImportError(where + ": units with an offset (such as celsius) are not supported");
      u.scale *= multiplier * std::pow(std::pow(10.0, prefix) * base.scale, exponent);
      for (const auto& [d, x] : base.dims) u.dims[d] += x * exponent;
    }
    return u;
  }

  const std::string& text_;
  std::map<std::pair<std::string, std::string>, pugi::xml_node> defs_;
  std::map<std::pair<std::string, std::string>, Unit> done_;
  std::set<std::pair<std::string, std::string>> busy_;
};

// d(x)/d(t) on the left of an equation: returns (x, t) names.
std::pair<std::string, std::string> derivative_names(const pugi::xml_node& apply, const std::string& text) {
  std::string var, bvar;
  bool first = true;
  for (const auto& c : apply.children()) {
    if (c.type() != pugi::node_element) continue;
    const std::string tag = local_name(c);
    if (first) {
      first = false;
      continue;
    }
    if (tag == "bvar") {
      for (const auto& b : c.children()) {
        if (b.type() != pugi::node_element) continue;
        if (local_name(b) == "degree")
          throw ImportError(element_path(b, text) + ": higher derivatives are not supported");
        if (local_name(b) == "ci") bvar = read_expression(b, text).name;
      }
    } else if (tag == "ci") {
      var = read_expression(c, text).name;
    } else {
      throw ImportError(element_path(c, text) + ": the derivative of <" + tag + "> (only of a variable)");
    }
  }
  if (var.empty() || bvar.empty())
    throw ImportError(element_path(apply, text) + ": a derivative needs <bvar><ci>t</ci></bvar> and <ci>x</ci>");
  return {var, bvar};
}

void resolve_names(Expr& e, const Document& doc, const std::string& component) {
  if (e.kind == Expr::Kind::variable) {
    e.var = doc.find(component, e.name);
    if (e.var < 0)
      throw ImportError(e.path + ": <ci>" + e.name + "</ci> is not a variable of component '" + component + "'");
  }
  for (auto& a : e.args) resolve_names(a, doc, component);
}

void resolve_number_units(const Expr& e, Document& doc, const std::string& component, UnitScope& units) {
  if (e.kind == Expr::Kind::number && !e.units.empty() && !doc.number_units.count({component, e.units}))
    doc.number_units[{component, e.units}] = units.resolve(component, e.units, e.path);
  for (const auto& a : e.args) resolve_number_units(a, doc, component, units);
}

void read_math(Document& doc, const std::string& component, const pugi::xml_node& math, UnitScope& units) {
  const std::string& text = doc.text;
  for (const auto& eq : math.children()) {
    if (eq.type() != pugi::node_element) continue;
    const std::string path = element_path(eq, text);
    std::vector<pugi::xml_node> parts;
    for (const auto& c : eq.children())
      if (c.type() == pugi::node_element) parts.push_back(c);
    if (local_name(eq) != "apply" || parts.empty() || local_name(parts[0]) != "eq" || parts.size() != 3)
      throw ImportError(path + ": a <math> child must be an equation <apply><eq/> lhs rhs</apply>");
    Equation e;
    e.component = component;
    e.path = path;
    const auto& lhs = parts[1];
    std::string lhs_name, bvar_name;
    if (local_name(lhs) == "ci") {
      lhs_name = read_expression(lhs, text).name;
    } else if (local_name(lhs) == "apply" && local_name(lhs.first_child()) == "diff") {
      std::tie(lhs_name, bvar_name) = derivative_names(lhs, text);
      e.ode = true;
    } else {
      throw ImportError(element_path(lhs, text) +
                        ": the left side is not a variable or a derivative (implicit equations and DAEs "
                        "are not supported)");
    }
    e.lhs = doc.find(component, lhs_name);
    if (e.lhs < 0) throw ImportError(path + ": '" + lhs_name + "' is not a variable of component '" + component + "'");
    if (e.ode) {
      e.bvar = doc.find(component, bvar_name);
      if (e.bvar < 0)
        throw ImportError(path + ": '" + bvar_name + "' is not a variable of component '" + component + "'");
    }
    e.rhs = read_expression(parts[2], text);
    resolve_names(e.rhs, doc, component);
    resolve_number_units(e.rhs, doc, component, units);
    doc.equations.push_back(std::move(e));
  }
}

// RDF anywhere in the document: rdf:Description rdf:about="#ID" whose
// children (bqbiol:is, bqbiol:isVersionOf, ...) point with rdf:resource at an
// oxmeta term, the Oxford metadata ontology Chaste and the Physiome
// repository annotate variables with.
void read_oxmeta_annotations(const pugi::xml_document& xml, Document& doc) {
  static const std::string kOxmeta = "chaste.comlab.ox.ac.uk/cellml/ns/oxford-metadata#";
  std::map<std::string, std::vector<std::string>> terms;  // id -> terms
  std::function<void(const pugi::xml_node&)> walk = [&](const pugi::xml_node& node) {
    for (const auto& c : node.children()) {
      if (c.type() != pugi::node_element) continue;
      const std::string about = attribute(c, "about");
      if (local_name(c) == "Description" && about.size() > 1 && about[0] == '#')
        for (const auto& link : c.children()) {
          const std::string resource = attribute(link, "resource");
          const auto at = resource.find(kOxmeta);
          if (link.type() == pugi::node_element && at != std::string::npos)
            terms[about.substr(1)].push_back(resource.substr(at + kOxmeta.size()));
        }
      walk(c);
    }
  };
  walk(xml);
  for (auto& v : doc.variables)
    if (const auto it = terms.find(v.id); !v.id.empty() && it != terms.end()) v.oxmeta = it->second;
}

}  // namespace

int Document::find(const std::string& component, const std::string& name) const {
  const auto it = index.find({component, name});
  return it == index.end() ? -1 : it->second;
}

Document read_cellml(const std::filesystem::path& file) {
  Document doc;
  doc.file = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ImportError(file.string() + ": cannot be read");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  doc.text = buffer.str();
  pugi::xml_document xml;
  const auto parsed = xml.load_buffer(doc.text.data(), doc.text.size(), pugi::parse_default, pugi::encoding_auto);
  if (!parsed) {
    const auto line = 1 + std::count(doc.text.begin(), doc.text.begin() + std::min<std::size_t>(parsed.offset, doc.text.size()), '\n');
    throw ImportError(file.string() + ": line " + std::to_string(line) + ": not well-formed XML (" + parsed.description() + ")");
  }
  const auto model = xml.document_element();
  const std::string& text = doc.text;
  if (local_name(model) != "model") throw ImportError(file.string() + ": the root element is not <model>");
  const std::string ns = attribute(model, "xmlns");
  std::string prefix_ns;
  {
    const std::string name = model.name();
    const auto colon = name.find(':');
    if (colon != std::string::npos) prefix_ns = model.attribute(("xmlns:" + name.substr(0, colon)).c_str()).value();
  }
  const auto version = kVersions.find(prefix_ns.empty() ? ns : prefix_ns);
  if (version == kVersions.end())
    throw ImportError(element_path(model, text) + ": namespace '" + (prefix_ns.empty() ? ns : prefix_ns) +
                      "' is not CellML 1.0, 1.1 or 2.0");
  doc.version = version->second;
  doc.model_name = attribute(model, "name");

  for (const auto& imp : elements(model, "import"))
    throw ImportError(element_path(imp, text) + ": <import> is not supported (flatten the model first)");
  for (const auto& c : elements(model, "component"))
    for (const auto& r : elements(c, "reset"))
      throw ImportError(element_path(r, text) + ": <reset> is not supported");

  UnitScope units(text);
  for (const auto& u : elements(model, "units")) units.define("", u);
  for (const auto& c : elements(model, "component"))
    for (const auto& u : elements(c, "units")) units.define(attribute(c, "name"), u);

  for (const auto& c : elements(model, "component")) {
    const std::string component = attribute(c, "name");
    if (component.empty()) throw ImportError(element_path(c, text) + ": <component> without a name");
    for (const auto& v : elements(c, "variable")) {
      Variable var;
      var.component = component;
      var.name = attribute(v, "name");
      var.path = element_path(v, text);
      var.units_name = attribute(v, "units");
      var.initial = attribute(v, "initial_value");
      var.id = attribute(v, "id");
      if (var.name.empty() || var.units_name.empty())
        throw ImportError(var.path + ": a <variable> needs a name and units");
      var.unit = units.resolve(component, var.units_name, var.path);
      if (!doc.index.emplace(std::make_pair(component, var.name), static_cast<int>(doc.variables.size())).second)
        throw ImportError(var.path + ": variable '" + var.name + "' declared twice in '" + component + "'");
      doc.variables.push_back(std::move(var));
    }
  }
  for (const auto& c : elements(model, "component"))
    for (const auto& m : elements(c, "math")) read_math(doc, attribute(c, "name"), m, units);

  read_oxmeta_annotations(xml, doc);

  for (const auto& conn : elements(model, "connection")) {
    std::string c1 = attribute(conn, "component_1"), c2 = attribute(conn, "component_2");  // 2.0
    for (const auto& mc : elements(conn, "map_components")) {  // 1.0, 1.1
      c1 = attribute(mc, "component_1");
      c2 = attribute(mc, "component_2");
    }
    if (c1.empty() || c2.empty())
      throw ImportError(element_path(conn, text) + ": a connection needs component_1 and component_2");
    for (const auto& mv : elements(conn, "map_variables")) {
      Connection k;
      k.path = element_path(mv, text);
      const std::string v1 = attribute(mv, "variable_1"), v2 = attribute(mv, "variable_2");
      k.a = doc.find(c1, v1);
      k.b = doc.find(c2, v2);
      if (k.a < 0) throw ImportError(k.path + ": '" + c1 + "." + v1 + "' is not a variable");
      if (k.b < 0) throw ImportError(k.path + ": '" + c2 + "." + v2 + "' is not a variable");
      doc.connections.push_back(k);
    }
  }
  return doc;
}

}  // namespace fibrodem::cellml
