// `fibrodem import-cellml` and units: slips inside equations are imported
// with the numbers as written and a warning each (refused, all listed, under
// --strict-units); structural faults are refused either way. The models are
// small ones written for these tests (tests/cellml, tests/cellml/errors); the
// expected rates are computed by hand from the numbers in the CellML.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "cellml/import.hpp"
#include "cellml/import_error.hpp"
#include "cellml/model_analysis.hpp"
#include "cellml/model_reader.hpp"
#include "model/plugin_registry.hpp"
#include "support/cellml_plugins.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

namespace {

using testing::kCellml;
const std::string kVolt = "ampere^-1 kilogram^1 metre^2 second^-3";

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("fibrodem_cellml_units_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

cellml::ImportOptions options(const fs::path& file, bool strict) {
  cellml::ImportOptions o;
  o.input = file;
  o.name = "units_" + file.stem().string();
  o.out = scratch(o.name);
  o.strict_units = strict;
  return o;
}

cellml::ImportResult import(const fs::path& file) { return cellml::import_cellml(options(file, false)); }

// The ImportError's text (no plugin folder may then exist), "" if the import succeeded.
std::string refusal(const fs::path& file, bool strict) {
  const auto o = options(file, strict);
  try {
    cellml::import_cellml(o);
  } catch (const cellml::ImportError& e) {
    CHECK_FALSE(fs::exists(o.out));
    return e.what();
  }
  return "";
}

// dV/dt [mV/ms] of a one-state plugin at V_mV, no i_ext (dy/dt = a + b y).
double rate(const std::string& plugin, double V_mV) {
  const auto model = testing::load(plugin);
  REQUIRE(model->info().states.size() == 1);
  return testing::evaluate(*model, {V_mV}, 0.0, 0.0, false).dydt[0];
}

const std::string kSlipPath = "/model[@name='background_slip']/component[@name='membrane']/math/";
// The two slips of background_slip_*.cellml, as the importer must word them:
// Eb (dimensionless) subtracted from V (mV), and exp of V/kx (mV).
const std::vector<std::string> kSlipWarnings = {
    "inconsistent units in membrane.i_b at " + kSlipPath +
        "apply[1]/apply/apply (line 25): the operands of <minus> differ in dimension: 'V' [mV = 0.001 x " + kVolt +
        "] against 'Eb' [dimensionless]",
    "inconsistent units in membrane.i_x at " + kSlipPath +
        "apply[2]/apply/apply[1]/apply (line 28): the argument of <exp> is not dimensionless: 'V / kx' [mV / "
        "dimensionless = 0.001 x " + kVolt + "] against dimensionless"};

}  // namespace

TEST_CASE("import-cellml units: a dimensionless constant in a background current is imported with a warning each") {
  std::string first_source;
  for (const std::string version : {"1_0", "2_0"}) {
    const auto result = import(kCellml / ("background_slip_" + version + ".cellml"));
    CHECK(result.unit_warnings == kSlipWarnings);
    // Every warning is in the generated source's header, one per line.
    const std::string source = testing::read_file(result.folder / ("units_background_slip_" + version + ".cpp"));
    const std::string header = source.substr(0, source.find("#include"));
    for (const auto& w : kSlipWarnings) CHECK(header.find("//   - " + w + "\n") != std::string::npos);
    CHECK(header.find("Unit inconsistencies in the CellML (2), imported with the numbers as written") != std::string::npos);
  }
}

TEST_CASE("import-cellml units: the background current's plugin computes dV/dt with the numbers as written") {
  // By hand from background_slip_1_0.cellml: i_b = gb (V - Eb) = 0.3 (V + 54.4),
  // i_x = gx exp(V / kx) (V - Ex) = 0.02 exp(V / 25) (V + 90), dV/dt = -(i_b + i_x) / Cm, Cm = 1.
  // At V = -75: 0.3 * 20.6 - 0.3 exp(-3) = 6.18 - 0.014936 = 6.165064 mV/ms.
  for (double V : {-75.0, -60.0, 10.0}) {
    const double expected = -(0.3 * (V + 54.4) + 0.02 * std::exp(V / 25.0) * (V + 90.0)) / 1.0;
    CHECK(rate("cellml_background_slip", V) == doctest::Approx(expected).epsilon(1e-12));
  }
  CHECK(rate("cellml_background_slip", -75.0) == doctest::Approx(6.165064).epsilon(1e-6));
}

TEST_CASE("import-cellml units: --strict-units refuses the background current, listing every inconsistency") {
  for (const std::string version : {"1_0", "2_0"}) {
    const std::string error = refusal(kCellml / ("background_slip_" + version + ".cellml"), true);
    CHECK(error.find("--strict-units: 2 unit inconsistencies in the equations:") == 0);
    for (const auto& w : kSlipWarnings) CHECK(error.find("\n  " + w) != std::string::npos);
  }
}

TEST_CASE("import-cellml units: a slip of scale alone is warned about and the numbers are not rescaled") {
  const auto result = import(kCellml / "scale_slip_2_0.cellml");
  REQUIRE(result.unit_warnings.size() == 1);
  CHECK(result.unit_warnings[0] ==
        "inconsistent units in membrane.E at /model[@name='scale_slip']/component[@name='membrane']/math/apply[1]/apply "
        "(line 16): the operands of <plus> differ in scale by a factor of 1000: 'E_base' [mV = 0.001 x " + kVolt +
        "] against 'E_shift' [volt = " + kVolt + "]");
  // By hand: E = E_base + E_shift = -80 + 10 = -70 as written (with E_shift
  // converted to mV it would be 9920), dV/dt = (E - V) / tau, tau = 10 ms.
  CHECK(rate("cellml_scale_slip", -80.0) == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(rate("cellml_scale_slip", -75.0) == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(refusal(kCellml / "scale_slip_2_0.cellml", true).find("1 unit inconsistency") != std::string::npos);
}

TEST_CASE("import-cellml units: models with consistent units (scaled across connections) import without warnings") {
  // rc_membrane connects V in volt to V in mV and i_leak in pA to ampere:
  // conversions at connections, not slips. derivative_on_rhs: d(O)/d(time) on a right side has O's
  // units over time's (dimensionless / ms against B's mM and dCa/dt's mM/ms).
  for (const std::string file : {"rc_membrane_1_0", "rc_membrane_1_1", "rc_membrane_2_0", "hh_1952_1_0",
                                 "fitzhugh_nagumo_2_0", "mathml_coverage_2_0", "derivative_on_rhs_1_0"}) {
    auto o = options(kCellml / (file + ".cellml"), true);
    if (file.rfind("fitzhugh", 0) == 0) o.stimulus = "stimulus.z";
    CHECK_MESSAGE(cellml::import_cellml(o).unit_warnings.empty(), file);
  }
}

TEST_CASE("import-cellml units: the error corpus's equation slips are warnings, refused under --strict-units") {
  const fs::path errors = kCellml / "errors";
  const auto sum = import(errors / "equation_units.cellml").unit_warnings;
  REQUIRE(sum.size() == 1);
  CHECK(sum[0] == "inconsistent units in membrane.d(V)/d(time) at /model[@name='equation_units']/component[@name='membrane']"
                  "/math/apply/apply[2]/apply (line 11): the operands of <plus> differ in dimension: 'V' [mV = 0.001 x " +
                      kVolt + "] against 'time' [ms = 0.001 x second^1]");
  // i_leak is declared in nA where (V - E)/R is in pA, and dV/dt then divides
  // nA by pF: two sides a factor of 1000 apart, twice.
  const auto scale = import(errors / "scale_mismatch.cellml").unit_warnings;
  REQUIRE(scale.size() == 2);
  CHECK(scale[0] == "inconsistent units in membrane.i_leak at /model[@name='scale_mismatch']/component[@name='membrane']"
                    "/math/apply[1] (line 17): the two sides of the equation differ in scale by a factor of 1000: "
                    "'i_leak' [nA = 1e-09 x ampere^1] against '(V - E) / R' [mV / GOhm = 1e-12 x ampere^1]");
  CHECK(scale[1].find("inconsistent units in membrane.d(V)/d(time) at /model[@name='scale_mismatch']/component[@name="
                      "'membrane']/math/apply[2] (line 18): the two sides of the equation differ in scale by a factor "
                      "of 1000: 'd(V)/d(time)' [mV / ms = ") == 0);
  CHECK(refusal(errors / "equation_units.cellml", true) == "--strict-units: 1 unit inconsistency in the equations:\n  " + sum[0]);
  CHECK(refusal(errors / "scale_mismatch.cellml", true) ==
        "--strict-units: 2 unit inconsistencies in the equations:\n  " + scale[0] + "\n  " + scale[1]);
}

TEST_CASE("import-cellml units: structural faults are refused with or without --strict-units") {
  const fs::path errors = kCellml / "errors";
  for (bool strict : {false, true}) {
    CAPTURE(strict);
    // A connection between a voltage and a current, CellML 1.1 and 2.0.
    const std::string v11 = refusal(errors / "inconsistent_units.cellml", strict);
    CHECK(v11.find("/model[@name='inconsistent_units']/connection/map_variables (line 18): inconsistent units: "
                   "membrane.V [mV = " + kVolt + "] connected to leak.V [pA = ampere^1]") == 0);
    const std::string v20 = refusal(errors / "connection_dimensions_2_0.cellml", strict);
    CHECK(v20.find("/model[@name='connection_dimensions']/connection/map_variables (line 19): inconsistent units: "
                   "membrane.V [mV = " + kVolt + "] connected to leak.V [pA = ampere^1]") == 0);
    // No membrane potential, no time: refused before (or despite) any slip.
    const std::string no_v = refusal(errors / "no_voltage.cellml", strict);
    if (strict) CHECK(no_v.find("--strict-units: 1 unit inconsistency") == 0);
    else CHECK(no_v.find("cannot tell which state is the membrane potential (0 candidates)") != std::string::npos);
    const std::string no_t = refusal(errors / "time_not_time.cellml", strict);
    if (strict) CHECK(no_t.find("--strict-units: 1 unit inconsistency") == 0);
    else CHECK(no_t.find("/model[@name='time_not_time']/component[@name='membrane']/variable[@name='t'] (line 6): "
                         "the independent variable membrane.t is in 'mV'") == 0);
  }
}

TEST_CASE("import-cellml units: an initial value naming a constant is converted, or taken as written across dimensions") {
  const fs::path file = kCellml / "initial_value_slip_2_0.cellml";
  // The model as analysed: V starts at V_rest, -0.08 V converted to -80 mV;
  // w (dimensionless) at w_time, 0.25 ms, which no conversion makes
  // dimensionless: 0.25 as written, with the warning below.
  const cellml::Model model = cellml::analyse(cellml::read_cellml(file));
  std::map<std::string, double> initial;
  for (int q : model.states) initial[model.source(q).name] = model.quantities[static_cast<std::size_t>(q)].initial;
  CHECK(initial.at("V") == doctest::Approx(-80.0).epsilon(1e-12));
  CHECK(initial.at("w") == 0.25);
  REQUIRE(model.initial_value_unit_issues.size() == 1);
  const auto result = import(file);
  REQUIRE(result.unit_warnings.size() == 1);
  CHECK(result.unit_warnings[0].rfind("inconsistent units in the initial value of membrane.w at ", 0) == 0);
  CHECK(result.unit_warnings[0].find("it names 'w_time' [ms = 0.001 x second^1], of another dimension than "
                                     "membrane.w [dimensionless]; its number is taken as written") != std::string::npos);
  const std::string refused = refusal(file, true);
  CHECK(refused.find("1 unit inconsistency") != std::string::npos);
  CHECK(refused.find("membrane.w") != std::string::npos);
}
