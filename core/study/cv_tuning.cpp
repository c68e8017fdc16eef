#include "study/cv_tuning.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "measure/conduction_velocity.hpp"
#include "run/simulation.hpp"
#include "tissue/builders/column_tissue.hpp"

namespace fibrodem {

namespace {

constexpr double kBand_mm = 0.3;              // the paced band at the tissue's edge
// Wide enough that the sheet's lateral edges (cells with fewer side
// neighbours) hardly slow the wave: along, 0.25 mm measured 3.4 % and 1 mm
// 0.6 % below a 4 mm wide sheet (colman2013_caf, D_m_side_nS 4x D_m_nS).
constexpr double kAlongSheetWidth_mm = 1;    // 42 columns
constexpr double kAcrossSheetLength_mm = 1;  // 8 rows (7 in the odd columns)
constexpr double kStimulusStart_ms = 2;

// The brick lattice's continuum conductivities (docs/topics/fibrosis.md#anisotropy)
// per unit of conductance: sigma_yy = kEnd g_e + kSideAlong g_s, sigma_xx =
// kSideAcross g_s, from each cell's two end-to-end junctions 125 um away
// and four side-to-side ones 62.5 um along and 23.57 um across it.
constexpr double kEnd = 2 * kMyocyteLength_um * kMyocyteLength_um;
constexpr double kSideAlong = 4 * (kMyocyteLength_um / 2) * (kMyocyteLength_um / 2);
constexpr double kSideAcross = 4 * kColumnPitch_um * kColumnPitch_um;
// Along, the side junctions count as this share of an end-to-end one.
constexpr double kSideWeight = kSideAlong / kEnd;

double continuum_ratio(double g_e, double g_s) {  // CV across / along
  return std::sqrt(kSideAcross * g_s / (kEnd * g_e + kSideAlong * g_s));
}

// A power law CV = a G^p through the iterates (ln G, ln CV): p by secant
// from the last two, 1/2 (continuous tissue) before there are two or when
// they do not tell (the same G, or a slope outside [0.1, 1.5]).
struct PowerLaw {
  double p = 0.5;
  double last_log_G = NAN, last_log_cv = NAN;
  void add(double G, double cv) {
    const double lg = std::log(G), lc = std::log(cv);
    if (std::isfinite(last_log_G) && std::abs(lg - last_log_G) > 1e-6) {
      const double slope = (lc - last_log_cv) / (lg - last_log_G);
      if (slope >= 0.1 && slope <= 1.5) p = slope;
    }
    last_log_G = lg;
    last_log_cv = lc;
  }
  // The G that gives `target` by the law through the last iterate.
  double toward(double G, double cv, double target) const { return G * std::pow(target / cv, 1 / p); }
};

bool within(const std::optional<double>& cv, const std::optional<double>& target, double tolerance) {
  return !target || (cv && std::abs(*cv / *target - 1) <= tolerance);
}

std::string m_per_s(double v) { return fmt::format("{:.4g} m/s", v); }

}  // namespace

const std::vector<CvPreset>& cv_presets() {
  static const double kAugmentaCvRatio = std::sqrt(3.75 * 0.62);  // CV ~ sqrt(sigma): 1.52
  static const std::vector<CvPreset> presets = {
      {"atrium-control", 0.98, 0.98 / kAugmentaCvRatio,
       "LA local CV in sinus rhythm 0.98 m/s (Fukumoto et al. 2016); across: AugmentA's bulk anisotropy"},
      {"atrium-caf", 0.69, 0.69 / kAugmentaCvRatio,
       "LA CV in persistent AF 0.69 m/s (Bendikas, ..., Williams, KCL); across: AugmentA's bulk anisotropy"},
  };
  return presets;
}

const CvPreset* find_cv_preset(const std::string& name) {
  for (const auto& p : cv_presets())
    if (name == p.name) return &p;
  return nullptr;
}

json with_conductances(json manifest, double D_m_nS, double D_m_side_nS) {
  manifest["coupling"]["D_m_nS"] = D_m_nS;
  manifest["coupling"]["D_m_side_nS"] = D_m_side_nS;
  return manifest;
}

json cv_measuring_manifest(const json& manifest, CvDirection direction, double length_mm, double D_m_nS,
                           double D_m_side_nS, double expected_m_per_s) {
  const json& tissue = manifest.at("tissue");
  const std::string builder = tissue.value("builder", "");
  json m = manifest;
  for (const char* key : {"effects", "mechanics", "mechano_electric_feedback", "initial_state", "settle"}) m.erase(key);
  // The bulk's conductances are tuned: regions and maps are relative to them.
  if (m.contains("coupling") && m["coupling"].is_object())
    for (const char* key : {"regions", "field"}) m["coupling"].erase(key);
  if (builder == "strand") {
    if (direction == CvDirection::across)
      throw ManifestError("tissue.builder", "a strand has no side-to-side junctions: CV across the fibres is "
                                            "measured on a fibrotic_sheet");
    m["tissue"] = {{"builder", "strand"}, {"type", "myocyte"},
                   {"cells", std::max(8L, std::lround(length_mm * 1000 / kMyocyteLength_um))}};
  } else if (builder == "fibrotic_sheet") {
    const bool along = direction == CvDirection::along;
    m["tissue"] = {{"builder", "fibrotic_sheet"},
                   {"width_mm", along ? kAlongSheetWidth_mm : length_mm},
                   {"length_mm", along ? length_mm : kAcrossSheetLength_mm}};
  } else {
    throw ManifestError("tissue.builder", "tune-cv measures on a strand or a fibrotic_sheet, got \"" + builder + "\"");
  }
  const json& first = manifest.contains("stimulus") && manifest["stimulus"].is_array() && !manifest["stimulus"].empty()
                          ? manifest["stimulus"][0]
                          : json();
  if (!first.is_object() || !first.contains("amplitude_pA"))
    throw ManifestError("stimulus[0]", "tune-cv paces with stimulus[0]'s amplitude_pA (and duration_ms): the manifest "
                                       "has none");
  const double pulse_ms = first.value("duration_ms", 2.0);
  json band = {{"x_min_mm", -1}, {"x_max_mm", 1e3}, {"y_min_mm", -1}, {"y_max_mm", 1e3}, {"type", "myocyte"}};
  band[direction == CvDirection::along ? "y_max_mm" : "x_max_mm"] = kBand_mm;
  m["stimulus"] = json::array({{{"target", band}, {"start_ms", kStimulusStart_ms}, {"duration_ms", pulse_ms},
                                {"amplitude_pA", first["amplitude_pA"]}}});
  // Time for the wave to cross at half the expected speed, and to rise.
  m["duration_ms"] = kStimulusStart_ms + pulse_ms + 10 + 2 * length_mm / expected_m_per_s;
  m["output"] = {{"report", false}};
  return with_conductances(std::move(m), D_m_nS, D_m_side_nS);
}

namespace {

// The run's first beat as conduction samples along y or x.
struct FirstBeat {
  std::vector<ConductionSample> samples;
  // Every paced cell overshot 0 mV (a pulse too weak only depolarises them,
  // and that spreads some way passively), and every cell carried the wave.
  bool band_fired = true, crossed = false;
};

FirstBeat first_beat(const json& manifest, CvDirection direction) {
  Simulation sim(parse_scene(manifest));
  sim.run();
  const Tissue& t = sim.tissue();
  int first = -1;
  for (const auto& b : sim.biomarkers()) first = first < 0 ? b.beat : std::min(first, b.beat);
  FirstBeat beat;
  std::size_t carried = 0;
  for (const auto& b : sim.biomarkers()) {
    if (b.beat != first) continue;
    const auto c = static_cast<std::size_t>(b.cell);
    const double position_um = direction == CvDirection::along ? t.y_um[c] : t.x_um[c];
    const bool paced = position_um <= 1000 * kBand_mm + 1e-9;
    if (paced) beat.band_fired &= fired(b) && b.apo_mV > 0;
    carried += carried_wave(b) ? 1 : 0;
    beat.samples.push_back({position_um, b.activation_ms, paced, carried_wave(b)});
  }
  beat.crossed = carried == t.cell_count();
  return beat;
}

}  // namespace

std::optional<double> measured_cv_m_per_s(const json& measuring_manifest, CvDirection direction) {
  json m = measuring_manifest;
  FirstBeat beat = first_beat(m, direction);
  // The pulse only starts the wave: stronger until the band fires (its
  // sink grows with the conductances), up to 16 times.
  json& amplitude = m["stimulus"][0]["amplitude_pA"];
  for (int doubling = 0; doubling < 4 && !beat.band_fired; ++doubling) {
    amplitude = 2 * amplitude.get<double>();
    beat = first_beat(m, direction);
  }
  if (!beat.band_fired)
    throw std::runtime_error(fmt::format("the paced band does not fire at {} pA (16 x stimulus[0].amplitude_pA) "
                                         "with D_m_nS {}, D_m_side_nS {}",
                                         amplitude.get<double>(), m["coupling"]["D_m_nS"].get<double>(),
                                         m["coupling"]["D_m_side_nS"].get<double>()));
  if (!beat.crossed) {  // slower than expected, or blocked: 4x as long before calling it blocked
    m["duration_ms"] = 4 * m["duration_ms"].get<double>();
    beat = first_beat(m, direction);
    if (!beat.crossed) return std::nullopt;
  }
  const auto fit = fit_conduction_velocity(beat.samples);
  if (!fit) return std::nullopt;
  return fit->cv_cm_per_s / 100;
}

CvTuningResult tune_conduction_velocity(const json& manifest, const CvTuningOptions& o) {
  const auto& T_y = o.along_m_per_s;
  const auto& T_x = o.across_m_per_s;
  if (!T_y && !T_x) throw std::invalid_argument("tune-cv: no target conduction velocity");
  const double limit = std::sqrt(kSideAcross / kSideAlong);  // CV across / along as g_e -> 0
  if (T_y && T_x && *T_x / *T_y >= limit)
    throw CvTargetUnreachable(
        fmt::format("CV across {} is {:.3f} of CV along {}; the brick layout reaches at most {:.3f} of it "
                    "(2.65 : 1, side-to-side junctions alone, continuum limit; less on the discrete lattice): "
                    "the closest reachable across is below {}",
                    m_per_s(*T_x), *T_x / *T_y, m_per_s(*T_y), limit, m_per_s(limit * *T_y)),
        limit * *T_y);
  const Scene scene = parse_scene(manifest);  // (checks the manifest first)
  double g_e = scene.coupling.D_m_nS, g_s = scene.coupling.D_m_side_nS;
  const double side_share = g_e > 0 ? g_s / g_e : 1;  // kept when only CV along is a target
  PowerLaw along_law, across_law;
  CvTuningResult result;
  for (int iteration = 1; iteration <= o.max_iterations; ++iteration) {
    CvTuningStep step{iteration, g_e, g_s, std::nullopt, std::nullopt};
    if (T_y)
      step.along_m_per_s = measured_cv_m_per_s(
          cv_measuring_manifest(manifest, CvDirection::along, o.length_mm, g_e, g_s, *T_y), CvDirection::along);
    if (T_x)
      step.across_m_per_s = measured_cv_m_per_s(
          cv_measuring_manifest(manifest, CvDirection::across, o.length_mm, g_e, g_s, *T_x), CvDirection::across);
    result.steps.push_back(step);
    if (o.on_step) o.on_step(step);
    result.D_m_nS = g_e;
    result.D_m_side_nS = g_s;
    result.along_m_per_s = step.along_m_per_s;
    result.across_m_per_s = step.across_m_per_s;
    if (within(step.along_m_per_s, T_y, o.tolerance) && within(step.across_m_per_s, T_x, o.tolerance)) {
      result.converged = true;
      break;
    }
    // A wave that does not cross (conduction block): 4x the conductance
    // that direction needs, and again.
    const bool along_blocked = T_y && !step.along_m_per_s, across_blocked = T_x && !step.across_m_per_s;
    if (along_blocked || across_blocked) {
      if (along_blocked) g_e *= 4;
      if (across_blocked || !T_x) g_s = across_blocked ? 4 * g_s : side_share * g_e;
      continue;
    }
    if (T_x) {
      across_law.add(g_s, *step.across_m_per_s);
      g_s = across_law.toward(g_s, *step.across_m_per_s, *T_x);
    }
    if (T_y && T_x) {
      // Along through S = g_e + w g_s, the side junctions' part fixed by CV across.
      const double S = g_e + kSideWeight * step.D_m_side_nS;
      along_law.add(S, *step.along_m_per_s);
      g_e = along_law.toward(S, *step.along_m_per_s, *T_y) - kSideWeight * g_s;
      if (g_e <= 0) {
        // The lattice's limit, as the continuum's scaled by how far the
        // measured ratio falls below the continuum's at this iterate.
        const double measured = *step.across_m_per_s / *step.along_m_per_s;
        const double reachable = limit * measured / continuum_ratio(step.D_m_nS, step.D_m_side_nS);
        throw CvTargetUnreachable(
            fmt::format("CV across {} with CV along {} needs D_m_nS <= 0 on the brick layout (measured across / along "
                        "{:.3f} at D_m_nS {:.4g}, D_m_side_nS {:.4g}); it reaches at most about {:.3f} of CV along "
                        "with side-to-side junctions alone: the closest reachable across is about {}",
                        m_per_s(*T_x), m_per_s(*T_y), measured, step.D_m_nS, step.D_m_side_nS, reachable,
                        m_per_s(reachable * *T_y)),
            reachable * *T_y);
      }
    } else if (T_y) {
      along_law.add(g_e, *step.along_m_per_s);
      g_e = along_law.toward(g_e, *step.along_m_per_s, *T_y);
      g_s = side_share * g_e;
    }
  }
  return result;
}

}  // namespace fibrodem
