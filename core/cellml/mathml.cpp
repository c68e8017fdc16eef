#include "cellml/mathml.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

#include "cellml/import_error.hpp"

namespace fibrodem::cellml {

namespace {

const std::set<std::string>& operators() {
  static const std::set<std::string> ops = {
      "plus",    "minus",   "times",   "divide",  "power",   "root",    "exp",     "ln",
      "log",     "abs",     "floor",   "ceiling", "min",     "max",     "rem",     "eq",
      "neq",     "gt",      "lt",      "geq",     "leq",     "and",     "or",      "xor",
      "not",     "sin",     "cos",     "tan",     "sec",     "csc",     "cot",     "sinh",
      "cosh",    "tanh",    "sech",    "csch",    "coth",    "arcsin",  "arccos",  "arctan",
      "arcsec",  "arccsc",  "arccot",  "arcsinh", "arccosh", "arctanh", "arcsech", "arccsch",
      "arccoth"};
  return ops;
}

double parse_number(const std::string& text, const std::string& path) {
  const char* begin = text.c_str();
  while (*begin == ' ' || *begin == '\n' || *begin == '\t' || *begin == '\r') ++begin;
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  while (end && (*end == ' ' || *end == '\n' || *end == '\t' || *end == '\r')) ++end;
  if (end == begin || (end && *end != '\0'))
    throw ImportError(path + ": <cn> '" + text + "' is not a number");
  return value;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

Expr read_cn(const pugi::xml_node& node, const std::string& path) {
  Expr e;
  e.kind = Expr::Kind::number;
  e.path = path;
  e.units = attribute(node, "units");
  const std::string type = attribute(node, "type");
  if (type == "e-notation") {
    // <cn type="e-notation">mantissa<sep/>exponent</cn>
    std::string mantissa, exponent;
    bool after_sep = false;
    for (const auto& child : node.children()) {
      if (child.type() == pugi::node_element && local_name(child) == "sep") after_sep = true;
      else if (child.type() == pugi::node_pcdata) (after_sep ? exponent : mantissa) += child.value();
    }
    e.value = parse_number(mantissa, path) * std::pow(10.0, parse_number(exponent, path));
  } else if (type.empty() || type == "real" || type == "integer" || type == "double") {
    e.value = parse_number(node.text().get(), path);
  } else {
    throw ImportError(path + ": <cn type=\"" + type + "\"> is not supported (real, integer, e-notation are)");
  }
  return e;
}

// d(x)/d(t) inside an expression: op "diff", args {x, t} (CellML 1.0 section
// 4.2.3 admits <diff> anywhere in the MathML subset; Nygren 1998 reads a
// state's rate this way). model_analysis.cpp gives it the rate of x.
Expr read_derivative(const pugi::xml_node& node, const std::string& text, const std::string& path) {
  Expr e;
  e.kind = Expr::Kind::apply;
  e.op = "diff";
  e.path = path;
  Expr x, t;
  for (const auto& child : node.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string ct = local_name(child);
    if (ct == "diff") continue;
    if (ct == "bvar") {
      for (const auto& c : child.children()) {
        if (c.type() != pugi::node_element) continue;
        if (local_name(c) == "degree")
          throw ImportError(element_path(c, text) + ": a derivative of order other than 1 is not supported");
        if (local_name(c) != "ci")
          throw ImportError(element_path(c, text) + ": the <bvar> of a derivative must be a <ci>");
        t = read_expression(c, text);
      }
    } else if (ct == "ci") {
      x = read_expression(child, text);
    } else {
      throw ImportError(element_path(child, text) + ": the derivative of <" + ct + "> (only of a variable)");
    }
  }
  if (x.name.empty() || t.name.empty())
    throw ImportError(path + ": a derivative needs <bvar><ci>t</ci></bvar> and <ci>x</ci>");
  e.args.push_back(std::move(x));
  e.args.push_back(std::move(t));
  return e;
}

}  // namespace

bool supported_operator(const std::string& op) { return operators().count(op) > 0; }

std::string local_name(const pugi::xml_node& node) {
  const std::string name = node.name();
  const auto colon = name.find(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

std::string attribute(const pugi::xml_node& node, const std::string& name) {
  for (const auto& a : node.attributes()) {
    std::string n = a.name();
    const auto colon = n.find(':');
    if (colon != std::string::npos) {
      if (n.rfind("xmlns", 0) == 0) continue;
      n = n.substr(colon + 1);
    }
    if (n == name) return a.value();
  }
  return "";
}

std::string element_path(const pugi::xml_node& node, const std::string& text) {
  std::string path;
  for (auto n = node; n && n.type() == pugi::node_element; n = n.parent()) {
    int index = 0, same = 0;
    for (auto s = n.parent().first_child(); s; s = s.next_sibling()) {
      if (s.type() != pugi::node_element || std::string(s.name()) != n.name()) continue;
      ++same;
      if (s == n) index = same;
    }
    std::string step = "/" + local_name(n);
    const std::string name = attribute(n, "name");
    if (!name.empty()) step += "[@name='" + name + "']";
    else if (same > 1) step += "[" + std::to_string(index) + "]";
    path = step + path;
  }
  const auto offset = node.offset_debug();
  if (offset >= 0 && static_cast<std::size_t>(offset) <= text.size())
    path += " (line " + std::to_string(1 + std::count(text.begin(), text.begin() + offset, '\n')) + ")";
  return path;
}

Expr read_expression(const pugi::xml_node& node, const std::string& text) {
  const std::string path = element_path(node, text);
  const std::string tag = local_name(node);
  if (tag == "cn") return read_cn(node, path);
  if (tag == "ci") {
    Expr e;
    e.kind = Expr::Kind::variable;
    e.name = trimmed(node.text().get());
    e.path = path;
    return e;
  }
  if (tag == "pi" || tag == "exponentiale" || tag == "true" || tag == "false" || tag == "notanumber" ||
      tag == "infinity") {
    Expr e;
    e.kind = Expr::Kind::constant;
    e.op = tag;
    e.path = path;
    return e;
  }
  if (tag == "piecewise") {
    Expr e;
    e.kind = Expr::Kind::piecewise;
    e.path = path;
    Expr otherwise;
    for (const auto& child : node.children()) {
      if (child.type() != pugi::node_element) continue;
      const std::string ct = local_name(child);
      std::vector<Expr> parts;
      for (const auto& c : child.children())
        if (c.type() == pugi::node_element) parts.push_back(read_expression(c, text));
      if (ct == "piece") {
        if (parts.size() != 2) throw ImportError(element_path(child, text) + ": <piece> needs a value and a condition");
        e.args.push_back(std::move(parts[0]));
        e.args.push_back(std::move(parts[1]));
      } else if (ct == "otherwise") {
        if (parts.size() != 1) throw ImportError(element_path(child, text) + ": <otherwise> needs one value");
        otherwise = std::move(parts[0]);
        e.has_otherwise = true;
      } else {
        throw ImportError(element_path(child, text) + ": <" + ct + "> inside <piecewise> (only piece, otherwise)");
      }
    }
    if (e.has_otherwise) e.args.push_back(std::move(otherwise));
    return e;
  }
  if (tag != "apply")
    throw ImportError(path + ": unsupported MathML element <" + tag + ">");
  Expr e;
  e.kind = Expr::Kind::apply;
  e.path = path;
  Expr qualifier;
  bool has_qualifier = false;
  bool first = true;
  for (const auto& child : node.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string ct = local_name(child);
    if (first) {
      first = false;
      e.op = ct;
      if (ct == "diff") return read_derivative(node, text, path);
      if (!supported_operator(ct))
        throw ImportError(element_path(child, text) + ": unsupported MathML element <" + ct + ">");
      continue;
    }
    if (ct == "degree" || ct == "logbase") {
      for (const auto& c : child.children())
        if (c.type() == pugi::node_element) {
          qualifier = read_expression(c, text);
          has_qualifier = true;
        }
      continue;
    }
    if (ct == "bvar") throw ImportError(element_path(child, text) + ": <bvar> outside a derivative is not supported");
    e.args.push_back(read_expression(child, text));
  }
  if (first) throw ImportError(path + ": empty <apply>");
  if (e.op == "root" || e.op == "log") {
    if (!has_qualifier) {
      qualifier.kind = Expr::Kind::number;
      qualifier.value = e.op == "root" ? 2.0 : 10.0;
      qualifier.path = path;
    }
    e.args.push_back(std::move(qualifier));
  }
  const std::size_t n = e.args.size();
  const bool unary = e.op == "exp" || e.op == "ln" || e.op == "abs" || e.op == "floor" || e.op == "ceiling" ||
                     e.op == "not" || (e.op.size() > 2 && (e.op.rfind("sin") != std::string::npos ||
                                                           e.op.rfind("cos") != std::string::npos ||
                                                           e.op.rfind("tan") != std::string::npos ||
                                                           e.op.rfind("sec") != std::string::npos ||
                                                           e.op.rfind("csc") != std::string::npos ||
                                                           e.op.rfind("cot") != std::string::npos));
  const bool binary = e.op == "divide" || e.op == "power" || e.op == "rem" || e.op == "eq" || e.op == "neq" ||
                      e.op == "gt" || e.op == "lt" || e.op == "geq" || e.op == "leq" || e.op == "root" ||
                      e.op == "log";
  if ((unary && n != 1) || (binary && n != 2 && e.op != "root" && e.op != "log") ||
      ((e.op == "root" || e.op == "log") && n != 2) || (e.op == "minus" && n != 1 && n != 2) || n == 0)
    throw ImportError(path + ": <" + e.op + "> with " + std::to_string(n) + " operand(s)");
  return e;
}

}  // namespace fibrodem::cellml
