#include "run/settle.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "integrate/cell_system.hpp"
#include "integrate/integrator.hpp"
#include "io/csv_writer.hpp"
#include "util/sha256.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

// The integrator reports steps; settling wants none of them.
struct Quiet : StepObserver {
  double next_sample_ms() const override { return std::numeric_limits<double>::infinity(); }
  void on_sample(double) override {}
  void on_step(double, double, const double*) override {}
};

fs::path cache_dir() {
  if (const char* dir = std::getenv("FIBRODEM_CACHE_DIR")) return fs::path(dir) / "settle";
  if (const char* xdg = std::getenv("XDG_CACHE_HOME")) return fs::path(xdg) / "fibrodem" / "settle";
  if (const char* home = std::getenv("HOME")) return fs::path(home) / ".cache" / "fibrodem" / "settle";
  return {};
}

// Everything that determines the settled state.
json cache_key(const Population& pop, const SettleSpec& spec) {
  return {{"model", pop.info().name}, {"version", pop.info().version}, {"variant", pop.variant},
          {"parameters", pop.params}, {"initial_state", pop.initial_state},
          {"settle", {spec.ms, spec.period_ms, spec.duration_ms, spec.amplitude_pA}}};
}

std::vector<double> integrate_alone(const Population& prototype, const SettleSpec& spec) {
  CellSystem system;
  Population pop = prototype;
  pop.cells = {0};
  pop.lower_limit.clear();
  pop.upper_limit.clear();
  pop.table.reset();
  pop.fault = std::make_shared<ModelFault>();
  pop.reset();
  system.populations.push_back(std::move(pop));
  system.numbering = CellNumbering(1);
  system.where = {{0, 0}};
  system.V_mV.assign(1, 0.0);
  system.i_ext_pA.assign(1, 0.0);
  if (spec.period_ms > 0 && spec.amplitude_pA != 0) {
    Tissue one;
    one.add_cell(prototype.type, 0, 0);
    StimulusSpec pulses;
    pulses.target.kind = StimulusTarget::Kind::cells;
    pulses.target.cells = {0};
    pulses.start_ms = 0;
    pulses.duration_ms = spec.duration_ms;
    pulses.amplitude_pA = spec.amplitude_pA;
    pulses.period_ms = spec.period_ms;
    pulses.count = static_cast<long long>(spec.ms / spec.period_ms) + 1;
    system.stimulus = Stimulus({pulses}, one);
  }
  SolverSpec cvode;
  cvode.method = "cvode";
  cvode.rtol = 1e-6;
  cvode.atol = 1e-8;
  Quiet quiet;
  make_integrator(cvode)->advance(system, 0.0, spec.ms, quiet);
  const Population& done = system.populations.front();
  for (double y : done.y)
    if (!std::isfinite(y))
      throw std::runtime_error("settle: model " + done.info().name + " alone went to NaN/Inf within " +
                               format_number(spec.ms) + " ms");
  return done.y;
}

}  // namespace

SettleResult settle_cell(const Population& prototype, const SettleSpec& spec) {
  SettleResult result;
  const json key = cache_key(prototype, spec);
  const std::string key_text = key.dump();
  const fs::path dir = cache_dir();
  const fs::path file = dir.empty() ? fs::path() : dir / (sha256_hex(key_text) + ".json");
  const std::string what = fmt::format("{} ({}), {} ms {}", prototype.info().name, cell_type_name(prototype.type),
                                       format_number(spec.ms),
                                       spec.period_ms > 0 ? fmt::format("paced every {} ms", format_number(spec.period_ms))
                                                          : std::string("at rest"));
  if (!file.empty()) {
    std::ifstream in(file);
    const json cached = in ? json::parse(in, nullptr, /*allow_exceptions=*/false) : json();
    if (cached.is_object() && cached.value("key", json()) == key && cached["states"].is_array() &&
        cached["states"].size() == prototype.n_states()) {
      result.states = cached["states"].get<std::vector<double>>();
      result.from_cache = true;
      result.note = "settle: " + what + ", from the cache " + file.string();
      return result;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  result.states = integrate_alone(prototype, spec);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.note = fmt::format("settle: {}, computed in {:.3g} s", what, seconds);
  if (!file.empty()) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    const fs::path temporary = file.string() + ".tmp";
    {
      std::ofstream out(temporary);
      out << json{{"key", key}, {"states", result.states}}.dump();
    }
    fs::rename(temporary, file, ec);
    result.note += ec ? " (not cached: " + ec.message() + ")" : ", cached in " + file.string();
  }
  return result;
}

}  // namespace fibrodem
