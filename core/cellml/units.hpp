// CellML units: each named unit reduced to a scale factor on a product of base
// dimensions (SI base units, plus any base unit a model declares itself), so
// that two variables' units can be compared and converted (CellML 1.0 section
// 5, CellML 2.0 section 9).
#pragma once

#include <map>
#include <optional>
#include <string>

namespace fibrodem::cellml {

struct Unit {
  double scale = 1.0;   // value in SI (or base) units = scale * value + offset
  double offset = 0.0;  // only celsius-like units have one
  std::map<std::string, double> dims;  // base unit -> exponent (zero exponents absent)

  bool same_dims(const Unit& other) const;
  std::string dims_text() const;  // "kilogram^1 metre^2 second^-3 ampere^-1"
  // The unit as a model writes it and what it is: "mV = 0.001 x
  // ampere^-1 kilogram^1 metre^2 second^-3"; the name alone where the two
  // say the same ("dimensionless", "volt = ..." keeps its dimensions).
  std::string described_as(const std::string& written) const;
};

// Built-in units of CellML (SI base and derived), or nothing.
std::optional<Unit> builtin_unit(const std::string& name);
// A prefix by name ("milli") or as a power of ten ("-3"), or nothing.
std::optional<double> prefix_exponent(const std::string& prefix);

// Dimensions fibrodem cares about at its boundary.
Unit volt_unit();
Unit second_unit();
Unit ampere_unit();
Unit farad_unit();
Unit molar_unit();  // mol/m^3 = mM

}  // namespace fibrodem::cellml
