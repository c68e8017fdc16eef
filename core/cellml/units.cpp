#include "cellml/units.hpp"
#include "util/number_text.hpp"

#include <cmath>
#include <sstream>

namespace fibrodem::cellml {

namespace {

Unit make(double scale, std::initializer_list<std::pair<const char*, double>> dims) {
  Unit u;
  u.scale = scale;
  for (const auto& [name, exponent] : dims) u.dims[name] = exponent;
  return u;
}

}  // namespace

bool Unit::same_dims(const Unit& other) const {
  auto clean = [](const std::map<std::string, double>& d) {
    std::map<std::string, double> out;
    for (const auto& [k, v] : d)
      if (std::fabs(v) > 1e-12) out[k] = v;
    return out;
  };
  const auto a = clean(dims), b = clean(other.dims);
  if (a.size() != b.size()) return false;
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    if (it == b.end() || std::fabs(it->second - v) > 1e-9) return false;
  }
  return true;
}

std::string Unit::dims_text() const {
  std::ostringstream out;
  for (const auto& [k, v] : dims)
    if (std::fabs(v) > 1e-12) out << (out.tellp() > 0 ? " " : "") << k << "^" << v;
  const std::string text = out.str();
  return text.empty() ? "dimensionless" : text;
}

std::string Unit::described_as(const std::string& written) const {
  std::string si = dims_text();
  if (std::fabs(scale - 1.0) > 1e-12) {
    si = significant_digits(scale, 6) + " x " + si;
  }
  return si == written ? written : written + " = " + si;
}

std::optional<Unit> builtin_unit(const std::string& n) {
  // SI base units, then the derived units CellML defines (1.0 table 2, 2.0 table 3).
  if (n == "ampere") return make(1, {{"ampere", 1}});
  if (n == "candela") return make(1, {{"candela", 1}});
  if (n == "kelvin") return make(1, {{"kelvin", 1}});
  if (n == "kilogram") return make(1, {{"kilogram", 1}});
  if (n == "metre" || n == "meter") return make(1, {{"metre", 1}});
  if (n == "mole") return make(1, {{"mole", 1}});
  if (n == "second") return make(1, {{"second", 1}});
  if (n == "dimensionless" || n == "radian" || n == "steradian") return make(1, {});
  if (n == "becquerel" || n == "hertz") return make(1, {{"second", -1}});
  if (n == "celsius") {
    Unit u = make(1, {{"kelvin", 1}});
    u.offset = 273.15;
    return u;
  }
  if (n == "coulomb") return make(1, {{"ampere", 1}, {"second", 1}});
  if (n == "farad") return make(1, {{"kilogram", -1}, {"metre", -2}, {"second", 4}, {"ampere", 2}});
  if (n == "gram") return make(1e-3, {{"kilogram", 1}});
  if (n == "gray" || n == "sievert") return make(1, {{"metre", 2}, {"second", -2}});
  if (n == "henry") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -2}, {"ampere", -2}});
  if (n == "joule") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -2}});
  if (n == "katal") return make(1, {{"mole", 1}, {"second", -1}});
  if (n == "liter" || n == "litre") return make(1e-3, {{"metre", 3}});
  if (n == "lumen") return make(1, {{"candela", 1}});
  if (n == "lux") return make(1, {{"candela", 1}, {"metre", -2}});
  if (n == "newton") return make(1, {{"kilogram", 1}, {"metre", 1}, {"second", -2}});
  if (n == "ohm") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -3}, {"ampere", -2}});
  if (n == "pascal") return make(1, {{"kilogram", 1}, {"metre", -1}, {"second", -2}});
  if (n == "siemens") return make(1, {{"kilogram", -1}, {"metre", -2}, {"second", 3}, {"ampere", 2}});
  if (n == "tesla") return make(1, {{"kilogram", 1}, {"second", -2}, {"ampere", -1}});
  if (n == "volt") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -3}, {"ampere", -1}});
  if (n == "watt") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -3}});
  if (n == "weber") return make(1, {{"kilogram", 1}, {"metre", 2}, {"second", -2}, {"ampere", -1}});
  return std::nullopt;
}

std::optional<double> prefix_exponent(const std::string& p) {
  static const std::map<std::string, double> named = {
      {"yotta", 24}, {"zetta", 21}, {"exa", 18},   {"peta", 15},   {"tera", 12},   {"giga", 9},
      {"mega", 6},   {"kilo", 3},   {"hecto", 2},  {"deka", 1},    {"deca", 1},    {"deci", -1},
      {"centi", -2}, {"milli", -3}, {"micro", -6}, {"nano", -9},   {"pico", -12},  {"femto", -15},
      {"atto", -18}, {"zepto", -21}, {"yocto", -24}};
  if (const auto it = named.find(p); it != named.end()) return it->second;
  try {
    std::size_t used = 0;
    const double value = std::stod(p, &used);
    if (used == p.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

Unit volt_unit() { return *builtin_unit("volt"); }
Unit second_unit() { return *builtin_unit("second"); }
Unit ampere_unit() { return *builtin_unit("ampere"); }
Unit farad_unit() { return *builtin_unit("farad"); }
Unit molar_unit() { return make(1, {{"mole", 1}, {"metre", -3}}); }

}  // namespace fibrodem::cellml
