#include "model/plugin_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>

#include "model/plugin_probe.hpp"
#include "model/plugin_registry.hpp"
#include "model/simd.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

namespace {

using namespace plugin_probe;

PluginCheck named(const std::string& name) {
  PluginCheck check;
  check.name = name;
  return check;
}

// The rules of a model's kind that a run checks at set-up (run/population_setup.cpp).
std::vector<std::string> contract_problems(const ModelInfo& info) {
  std::vector<std::string> p;
  const auto n_states = static_cast<int>(info.states.size());
  const auto n_params = static_cast<int>(info.parameters.size());
  if (info.kind == ModelKind::ionic) {
    if (info.voltage_state < 0 || info.voltage_state >= n_states)
      p.push_back("an ionic model must name its membrane potential state (voltage_state)");
    if (info.capacitance_parameter < 0 || info.capacitance_parameter >= n_params)
      p.push_back("an ionic model must name its capacitance parameter (capacitance_parameter)");
    if (info.inputs.empty() || info.inputs[0].name != "i_ext")
      p.push_back("an ionic model's first input must be i_ext [pA]");
  } else {
    if (info.inputs.size() != 1 || info.inputs[0].name != "Ca_i")
      p.push_back("a myofilament model reads exactly one input, Ca_i [mM]");
    bool sl = false;
    for (const auto& o : info.outputs) sl |= o.name == "sarcomere_length";
    if (!sl) p.push_back("a myofilament model must output sarcomere_length [um]");
  }
  for (const auto& s : info.states)
    if (s.voltage_only && !s.gate) p.push_back("state '" + s.name + "' is voltage_only but not a gate");
  return p;
}

// Runs `body`, turning an exception from the model into a fault.
template <class Body>
void guarded(PluginCheck& check, Body body) {
  try {
    body();
  } catch (const std::exception& e) {
    check.faults.push_back(std::string("evaluate() threw: ") + e.what() + " (a model must not throw)");
  } catch (...) {
    check.faults.push_back("evaluate() threw something that is not a std::exception (a model must not throw)");
  }
}


PluginCheck check_written(const CellModel& model, const Setting& setting) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("derivatives written");
  const std::size_t n = kProbeCells;
  for (const bool scalar : {false, true}) {
    const char* path = scalar ? "scalar path" : "SIMD lanes";
    for (const bool skip : {false, true}) {
      if (skip && std::none_of(info.states.begin(), info.states.end(), [](const StateInfo& s) { return s.voltage_only; }))
        continue;
      guarded(check, [&] {
        Probe p(model, n, setting.params, setting.initial, rest_input(info));
        const std::vector<double> y_before = p.y;
        p.evaluate(0, n, scalar, skip);
        for (std::size_t k = 0; k < info.states.size(); ++k) {
          if (skip && info.states[k].voltage_only) continue;
          std::size_t a_missing = 0, b_missing = 0;
          for (std::size_t c = 0; c < n; ++c) {
            a_missing += is_poison(p.a[k * n + c]);
            b_missing += is_poison(p.b[k * n + c]);
          }
          if (a_missing || b_missing) {
            const std::string which = a_missing && b_missing ? "a and b" : a_missing ? "a" : "b";
            check.faults.push_back(fmt::format(
                "state '{}' (#{}): {} not written by evaluate() in {} of {} cells ({}{}): {}", info.states[k].name, k, which,
                std::max(a_missing, b_missing), n, path, skip ? ", skipping voltage_only gates" : "",
                a_missing && b_missing ? "it would stay frozen (or take another block's stale rate)"
                                       : "dy/dt = a + b y would use a stale value"));
          }
        }
        for (std::size_t o = 0; o < info.outputs.size(); ++o) {
          std::size_t missing = 0;
          for (std::size_t c = 0; c < n; ++c) missing += is_poison(p.outputs[o * n + c]);
          if (missing)
            check.faults.push_back(fmt::format("output '{}' not written by evaluate() in {} of {} cells ({})",
                                               info.outputs[o].name, missing, n, path));
        }
        if (p.y != y_before) check.faults.push_back(std::string("evaluate() changed its states (") + path + "): y is read-only");
      });
    }
    // A block that starts and ends inside the arrays: nothing outside it written.
    guarded(check, [&] {
      Probe p(model, n, setting.params, setting.initial, rest_input(info));
      p.evaluate(1, n - 1, scalar);
      for (const std::size_t c : {std::size_t{0}, n - 1})
        for (std::size_t k = 0; k < info.states.size(); ++k)
          if (!is_poison(p.a[k * n + c]) || !is_poison(p.b[k * n + c])) {
            check.faults.push_back(fmt::format("evaluate() of cells [1, {}) wrote a or b of state '{}' of cell {}, "
                                               "outside its block ({}): use block.begin and block.end",
                                               n - 1, info.states[k].name, c, path));
            return;
          }
    });
  }
  return check;
}

// Which states' a, b or outputs are not finite in cell c, as "a of 'x' = nan".
std::vector<std::string> non_finite(const Probe& p, std::size_t c) {
  std::vector<std::string> bad;
  for (std::size_t k = 0; k < p.info.states.size(); ++k) {
    if (!std::isfinite(p.a[k * p.n + c])) bad.push_back("a of '" + p.info.states[k].name + "' = " + significant_digits(p.a[k * p.n + c], 6));
    if (!std::isfinite(p.b[k * p.n + c])) bad.push_back("b of '" + p.info.states[k].name + "' = " + significant_digits(p.b[k * p.n + c], 6));
  }
  for (std::size_t o = 0; o < p.info.outputs.size(); ++o)
    if (!std::isfinite(p.outputs[o * p.n + c]))
      bad.push_back("output '" + p.info.outputs[o].name + "' = " + significant_digits(p.outputs[o * p.n + c], 6));
  return bad;
}

std::string joined(const std::vector<std::string>& items, std::size_t most = 6) {
  std::string s;
  for (std::size_t i = 0; i < items.size() && i < most; ++i) s += (i ? ", " : "") + items[i];
  if (items.size() > most) s += fmt::format(" and {} more", items.size() - most);
  return s;
}

PluginCheck check_finite_at_rest(const CellModel& model, const std::vector<Setting>& settings) {
  PluginCheck check = named("finite at rest");
  for (const Setting& s : settings)
    guarded(check, [&] {
      Probe p(model, simd::kLanes, s.params, s.initial, rest_input(model.info()));
      p.evaluate_all();
      if (const auto bad = non_finite(p, 0); !bad.empty())
        check.faults.push_back(s.label + ", at the initial state: " + joined(bad));
    });
  return check;
}

PluginCheck check_finite_over_v(const CellModel& model, const std::vector<Setting>& settings) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("finite over V from -120 to +80 mV");
  if (!ionic(info)) {
    check.skipped = "not an ionic model (no membrane potential)";
    return check;
  }
  // Every 0.01 mV, so that removable singularities of rate expressions
  // (0/0 at a round voltage) are hit exactly.
  const std::size_t n = 20001;
  const auto v = static_cast<std::size_t>(info.voltage_state);
  for (const Setting& s : settings)
    guarded(check, [&] {
      Probe p(model, n, s.params, s.initial, rest_input(info));
      for (std::size_t c = 0; c < n; ++c) p.state(v, c) = -120.0 + 0.01 * static_cast<double>(c);
      p.evaluate_all();
      std::size_t bad_cells = 0, first = n;
      for (std::size_t c = 0; c < n; ++c)
        if (!non_finite(p, c).empty()) bad_cells++, first = std::min(first, c);
      if (bad_cells)
        check.faults.push_back(fmt::format("{}, other states at their initial values: not finite at {} of {} "
                                           "voltages, first at V = {} mV: {}",
                                           s.label, bad_cells, n, significant_digits(p.state(v, first), 6), joined(non_finite(p, first))));
    });
  return check;
}

PluginCheck check_voltage_only(const CellModel& model, const std::vector<Setting>& settings) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("voltage_only gates depend on V alone");
  std::vector<std::size_t> gates;
  for (std::size_t k = 0; k < info.states.size(); ++k)
    if (info.states[k].voltage_only) gates.push_back(k);
  if (gates.empty() || !ionic(info)) {
    check.skipped = "no voltage_only gates";
    return check;
  }
  const auto v = static_cast<std::size_t>(info.voltage_state);
  const std::size_t n_states = info.states.size(), n_inputs = std::max<std::size_t>(1, info.inputs.size());
  std::set<std::pair<std::size_t, std::size_t>> reported;
  for (const Setting& s : settings)
    for (const double V : {-100.0, -80.0, -60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0})
      guarded(check, [&] {
        // Cell 0 as given; cell 1 + j with state j moved; the last with every input moved.
        const std::size_t n = n_states + 2;
        Probe p(model, n, s.params, s.initial, rest_input(info));
        for (std::size_t c = 0; c < n; ++c) p.state(v, c) = V;
        for (std::size_t j = 0; j < n_states; ++j)
          if (j != v) p.state(j, 1 + j) = moved(info.states[j], s.initial[j]);
        for (std::size_t i = 0; i < n_inputs; ++i) p.inputs[i * n + n - 1] = 2 * p.inputs[i * n] + 100.0;
        p.evaluate_all(true);
        for (const std::size_t g : gates)
          for (std::size_t c = 1; c < n; ++c) {
            const std::size_t j = c - 1;
            if (c <= n_states && j == v) continue;
            const double a0 = p.a[g * n], b0 = p.b[g * n], a1 = p.a[g * n + c], b1 = p.b[g * n + c];
            const auto differ = [](double x, double y) { return std::abs(x - y) > 1e-12 * std::max(std::abs(x), std::abs(y)); };
            if (!differ(a0, a1) && !differ(b0, b1)) continue;
            if (!reported.insert({g, c}).second) continue;
            const std::string what =
                c <= n_states ? fmt::format("state '{}' moves from {} to {}", info.states[j].name, significant_digits(s.initial[j], 6),
                                            significant_digits(p.state(j, c), 6))
                              : std::string("the inputs move (i_ext +100 pA)");
            check.faults.push_back(fmt::format(
                "gate '{}' is marked voltage_only, but its {} changes from {} to {} when {} (V = {} mV, {}): with "
                "lookup tables (solver.lookup_tables) its rates would come from a table of V alone",
                info.states[g].name, differ(a0, a1) ? "a" : "b", significant_digits(differ(a0, a1) ? a0 : b0, 6),
                significant_digits(differ(a0, a1) ? a1 : b1, 6), what, significant_digits(V, 6), s.label));
          }
      });
  return check;
}

PluginCheck check_linear_forms(const CellModel& model, const std::vector<Setting>& settings) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("linear forms a + b y consistent");
  const std::size_t n_states = info.states.size(), n = n_states + 1;
  std::vector<double> voltages = {std::nan("")};  // nan: the initial state
  if (ionic(info)) voltages.insert(voltages.end(), {-80.0, -40.0, 0.0, 40.0});
  std::set<std::size_t> reported;
  for (const Setting& s : settings)
    for (const double V : voltages)
      guarded(check, [&] {
        Probe p(model, n, s.params, s.initial, rest_input(info));
        if (!std::isnan(V))
          for (std::size_t c = 0; c < n; ++c) p.state(static_cast<std::size_t>(info.voltage_state), c) = V;
        // Cell 1 + k: state k moved by a small step (inside its bounds).
        std::vector<double> delta(n_states);
        for (std::size_t k = 0; k < n_states; ++k) {
          const StateInfo& st = info.states[k];
          const double y = p.state(k, 0);
          double d = st.gate ? 1e-6 : 1e-6 * std::max(std::abs(y), 1e-6);
          if (y + d > st.upper) d = -d;
          delta[k] = d;
          p.state(k, 1 + k) = y + d;
        }
        p.evaluate_all(true);
        const std::string where = std::isnan(V) ? s.label + ", initial state" : fmt::format("{}, V = {} mV", s.label, significant_digits(V, 6));
        for (std::size_t k = 0; k < n_states; ++k) {
          if (reported.count(k)) continue;
          const StateInfo& st = info.states[k];
          const double a = p.a[k * n], b = p.b[k * n], y = p.state(k, 0);
          const double f0 = p.rate(k, 0), f1 = p.rate(k, 1 + k);
          if (!std::isfinite(f0) || !std::isfinite(f1)) continue;  // "finite ..." reports it
          const double fd = (f1 - f0) / delta[k];
          // Round-off of the difference quotient.
          const double noise = 1e-15 * (std::abs(f0) + std::abs(f1) + std::abs(a) + std::abs(b * y)) / std::abs(delta[k]);
          std::string fault;
          if (st.gate) {
            const double tol_y = 1e-9 * std::max({1.0, std::abs(st.lower), std::abs(st.upper)});
            if (b > 0)
              fault = fmt::format("gate '{}' has b = {} /ms > 0: it would grow away from y_inf, not relax to it", st.name, significant_digits(b, 6));
            else if (b < 0 && !(-a / b >= st.lower - tol_y && -a / b <= st.upper + tol_y))
              fault = fmt::format("gate '{}': y_inf = -a/b = {}, outside its bounds [{}, {}]", st.name, significant_digits(-a / b, 6),
                                  significant_digits(st.lower, 6), significant_digits(st.upper, 6));
            else if (std::abs(fd - b) > 1e-5 * std::abs(b) + 100 * noise)
              fault = fmt::format("gate '{}': b = {} /ms, but the slope of a + b y in {} is {} /ms (finite difference): "
                                  "its a or b depends on {} itself, so Rush-Larsen's exact step would be wrong",
                                  st.name, significant_digits(b, 6), st.name, significant_digits(fd, 6), st.name);
          } else if (b != 0 && b * fd < 0 && std::abs(fd) > 100 * noise) {
            fault = fmt::format("state '{}': its linear form's b = {} /ms has the opposite sign of the slope of its "
                                "derivative in {}, {} /ms (finite difference): an exponential step would move it the "
                                "wrong way",
                                st.name, significant_digits(b, 6), st.name, significant_digits(fd, 6));
          }
          if (!fault.empty()) {
            reported.insert(k);
            check.faults.push_back(fault + " (" + where + ")");
          }
        }
      });
  return check;
}

// One paced beat of one cell: Rush-Larsen for gates and any state whose b is
// not 0, Euler otherwise, as solver.method "rush_larsen" at 0.01 ms.
PluginCheck check_bounds_over_beat(const CellModel& model, const std::vector<Setting>& settings) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("bounds respected over a paced beat");
  constexpr double dt = 0.01, duration_ms = 1000, onset_ms = 10, pulse_ms = 2, pA_per_pF = 20;
  const std::string protocol =
      ionic(info) ? fmt::format("one beat: {} pA/pF for {} ms at t = {} ms, Rush-Larsen dt {} ms, {} ms", pA_per_pF,
                                pulse_ms, onset_ms, dt, duration_ms)
                  : fmt::format("one Ca_i transient from 0.1 uM (peak ~0.7 uM at t = {} ms), Rush-Larsen dt {} ms, {} ms",
                                onset_ms + 20, dt, duration_ms);
  for (const Setting& s : settings)
    guarded(check, [&] {
      Probe p(model, 1, s.params, s.initial, rest_input(info));
      const double C = info.capacitance_parameter >= 0 ? s.params[static_cast<std::size_t>(info.capacitance_parameter)] : 0;
      // The range of V (or of the first output) over the beat, for the note.
      double lo = INFINITY, hi = -INFINITY;
      for (long step = 0; step * dt < duration_ms; ++step) {
        const double t = static_cast<double>(step) * dt;
        if (ionic(info)) p.inputs[0] = (t >= onset_ms && t < onset_ms + pulse_ms) ? pA_per_pF * C : 0.0;
        else if (t >= onset_ms)
          p.inputs[0] = 1e-4 + 1.2e-3 * (1 - std::exp(-(t - onset_ms) / 5.0)) * std::exp(-(t - onset_ms) / 100.0);
        p.evaluate(0, 1, false, false, t);
        for (std::size_t k = 0; k < info.states.size(); ++k) {
          const double y = p.y[k], a = p.a[k], b = p.b[k];
          const double next = (info.states[k].gate && b != 0) ? -a / b + (y + a / b) * std::exp(b * dt) : y + dt * (a + b * y);
          p.y[k] = next;
        }
        const double seen = ionic(info) ? p.y[static_cast<std::size_t>(info.voltage_state)] : p.outputs.empty() ? 0 : p.outputs[0];
        lo = std::min(lo, seen), hi = std::max(hi, seen);
        for (std::size_t k = 0; k < info.states.size(); ++k) {
          const StateInfo& st = info.states[k];
          const auto slack = [](double bound) { return 1e-6 * std::max(1.0, std::abs(bound)); };
          if (!(p.y[k] >= st.lower - slack(st.lower) && p.y[k] <= st.upper + slack(st.upper))) {
            check.faults.push_back(fmt::format("{}: state '{}' = {} {} at t = {} ms, outside its bounds [{}, {}] ({})",
                                               s.label, st.name, significant_digits(p.y[k], 6), st.unit, significant_digits(t + dt, 6), significant_digits(st.lower, 6),
                                               significant_digits(st.upper, 6), protocol));
            return;
          }
        }
      }
      check.note += (check.note.empty() ? "" : "; ") + s.label + ": " +
                    (ionic(info) ? info.states[static_cast<std::size_t>(info.voltage_state)].name
                                 : (info.outputs.empty() ? std::string("-") : info.outputs[0].name)) +
                    " from " + significant_digits(lo, 6) + " to " + significant_digits(hi, 6);
    });
  return check;
}

PluginCheck check_block_equals_cell(const CellModel& model, const Setting& setting) {
  const ModelInfo& info = model.info();
  PluginCheck check = named("block results equal single-cell results");
  const std::size_t n = kProbeCells, n_states = info.states.size();
  guarded(check, [&] {
    Probe block(model, n, setting.params, setting.initial, rest_input(info));
    // Every cell different: V spread over an action potential's range, the
    // other states moved a little within their bounds, inputs varied.
    for (std::size_t c = 0; c < n; ++c) {
      const double w = static_cast<double>(c % 5) - 2.0;
      for (std::size_t k = 0; k < n_states; ++k) {
        const StateInfo& st = info.states[k];
        const double y0 = setting.initial[k];
        block.state(k, c) = std::clamp(st.gate ? y0 + 0.02 * w : y0 * (1 + 0.01 * w), st.lower, st.upper);
      }
      if (ionic(info))
        block.state(static_cast<std::size_t>(info.voltage_state), c) = -90.0 + 130.0 * static_cast<double>(c) / (n - 1);
      block.inputs[c] = info.kind == ModelKind::myofilament ? 1e-4 * (1 + c % 3) : 10.0 * static_cast<double>(c);
    }
    Probe alone = block, again = block, scalar = block;
    block.evaluate_all();
    again.evaluate_all();
    scalar.evaluate_all(true);
    auto rows = [&](Probe& p) {
      return std::vector<std::pair<std::string, std::vector<double>*>>{{"a", &p.a}, {"b", &p.b}, {"output", &p.outputs}};
    };
    auto name_of = [&](const std::string& row, std::size_t k) {
      return row == "output" ? info.outputs[k].name : info.states[k].name;
    };
    // Each cell alone, in a block of its own.
    for (std::size_t c = 0; c < n; ++c) {
      alone.poison_results();
      alone.evaluate(c, c + 1, false);
      for (auto [row, values] : rows(block)) {
        const auto& other = row == "a" ? alone.a : row == "b" ? alone.b : alone.outputs;
        for (std::size_t k = 0; k < values->size() / n; ++k)
          if (!same_bits((*values)[k * n + c], other[k * n + c])) {
            check.faults.push_back(fmt::format("cell {} of {}: {} of '{}' is {} in a block but {} evaluated alone: "
                                               "the model mixes cells or depends on where a cell sits in the block",
                                               c, n, row, name_of(row, k), significant_digits((*values)[k * n + c], 6), significant_digits(other[k * n + c], 6)));
            return;
          }
      }
    }
    for (auto [row, values] : rows(block)) {
      const auto& repeat = row == "a" ? again.a : row == "b" ? again.b : again.outputs;
      const auto& ref = row == "a" ? scalar.a : row == "b" ? scalar.b : scalar.outputs;
      for (std::size_t k = 0; k < values->size() / n; ++k) {
        double scale = 0;
        for (std::size_t c = 0; c < n; ++c) scale = std::max(scale, std::abs(ref[k * n + c]));
        for (std::size_t c = 0; c < n; ++c) {
          const double x = (*values)[k * n + c];
          if (!same_bits(x, repeat[k * n + c])) {
            check.faults.push_back(fmt::format("{} of '{}' (cell {}) differs between two evaluations of the same block "
                                               "({} then {}): evaluate() must keep no state",
                                               row, name_of(row, k), c, significant_digits(x, 6), significant_digits(repeat[k * n + c], 6)));
            return;
          }
          if (std::abs(x - ref[k * n + c]) > 1e-9 * scale && !(std::isnan(x) && std::isnan(ref[k * n + c]))) {
            check.faults.push_back(fmt::format("{} of '{}' (cell {}) is {} in SIMD lanes but {} on the scalar path "
                                               "(solver.simd false): more than round-off (1e-9 of the row's largest, {})",
                                               row, name_of(row, k), c, significant_digits(x, 6), significant_digits(ref[k * n + c], 6), significant_digits(scale, 6)));
            return;
          }
        }
      }
    }
  });
  return check;
}

}  // namespace

bool PluginCheckReport::passed() const { return failed_count() == 0; }

std::size_t PluginCheckReport::failed_count() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const PluginCheck& c) { return !c.passed(); }));
}

PluginCheckReport check_plugin(const CellModel& model) {
  const ModelInfo& info = model.info();
  PluginCheckReport report;
  PluginCheck metadata = named("metadata");
  metadata.faults = model_info_problems(info);
  for (auto& p : contract_problems(info)) metadata.faults.push_back(std::move(p));
  report.checks.push_back(metadata);
  // Probing needs states, in-range indices and the kind's inputs.
  const bool probeable = !info.states.empty() && info.voltage_state < static_cast<int>(info.states.size()) &&
                         info.capacitance_parameter < static_cast<int>(info.parameters.size()) &&
                         (info.kind == ModelKind::ionic || !info.inputs.empty());
  const auto settings = settings_of(info);
  const std::vector<std::string> names = {"derivatives written", "finite at rest", "finite over V from -120 to +80 mV",
                                          "voltage_only gates depend on V alone", "linear forms a + b y consistent",
                                          "bounds respected over a paced beat", "block results equal single-cell results"};
  if (!probeable) {
    for (const auto& name : names)
      {
      PluginCheck check = named(name);
      check.skipped = "not run: the metadata leaves nothing to probe safely";
      report.checks.push_back(check);
    }
    return report;
  }
  report.checks.push_back(check_written(model, settings.front()));
  report.checks.push_back(check_finite_at_rest(model, settings));
  report.checks.push_back(check_finite_over_v(model, settings));
  report.checks.push_back(check_voltage_only(model, settings));
  report.checks.push_back(check_linear_forms(model, settings));
  report.checks.push_back(check_bounds_over_beat(model, settings));
  report.checks.push_back(check_block_equals_cell(model, settings.front()));
  return report;
}

}  // namespace fibrodem
