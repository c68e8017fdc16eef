// Gap-junction conductances for target conduction velocities (fibrodem
// tune-cv; docs/topics/fibrosis.md#tuning-conduction-velocity), as openCARP's
// tuneCV tunes conductivities (Costa et al. 2013, Comput Cardiol 40:373): a
// short strand or sheet of the manifest's cells and layout is paced from
// one edge, its conduction velocity measured as summary.json measures it
// (measure/conduction_velocity.hpp), and the conductance updated by the
// power law CV ~ D^p, p = 1/2 (continuous tissue) until two iterates give
// p by secant, until every CV is within the tolerance of its target.
//
// Along the fibres the brick sheet's side junctions carry part of the
// current (docs/topics/fibrosis.md#anisotropy: sigma_yy ~ 2 g_e 125^2 + 4 g_s
// 62.5^2, sigma_xx ~ 4 g_s 23.57^2), so with both targets the side
// conductance g_s follows CV across alone and the end-to-end g_e follows
// CV along through S = g_e + g_s / 2; a target that needs g_e <= 0 (across
// / along above what side junctions alone give, 23.57 / 62.5 = 0.377 in the
// continuum limit) is out of the layout's reach: CvTargetUnreachable.
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// Human atrial conduction velocities [m/s] (docs/reference/references.md#conduction-velocity).
struct CvPreset {
  const char* name;
  double along_m_per_s, across_m_per_s;
  const char* source;
};
// atrium-control: LA 0.98 m/s (Fukumoto et al. 2016); atrium-caf: 0.69 m/s
// in persistent AF (Williams et al. 2017); across: along / sqrt(2.325), the
// anisotropy of AugmentA's bulk atrium (transverse conductivity
// g_L / (3.75 x 0.62); Azzolin et al. 2023).
const std::vector<CvPreset>& cv_presets();
const CvPreset* find_cv_preset(const std::string& name);  // nullptr if none

struct CvTuningStep {
  int iteration = 0;
  double D_m_nS = 0, D_m_side_nS = 0;
  // Measured [m/s]; nullopt when not a target, or the wave did not cross the strand.
  std::optional<double> along_m_per_s, across_m_per_s;
};

struct CvTuningOptions {
  std::optional<double> along_m_per_s, across_m_per_s;  // targets; at least one
  double tolerance = 0.01;  // |CV / target - 1| for every target
  int max_iterations = 10;
  double length_mm = 5;     // of the measuring strand or sheet, in the wave's direction
  std::function<void(const CvTuningStep&)> on_step;  // after each iteration
};

struct CvTuningResult {
  double D_m_nS = 0, D_m_side_nS = 0;  // of the last iteration
  std::optional<double> along_m_per_s, across_m_per_s;  // reached with them
  std::vector<CvTuningStep> steps;
  bool converged = false;
};

// A target the layout cannot reach; closest_across_m_per_s: the fastest
// conduction across it reaches with the along target met.
class CvTargetUnreachable : public std::runtime_error {
 public:
  CvTargetUnreachable(const std::string& what, double closest_across_m_per_s)
      : std::runtime_error(what), closest_across_m_per_s_(closest_across_m_per_s) {}
  double closest_across_m_per_s() const { return closest_across_m_per_s_; }

 private:
  double closest_across_m_per_s_;
};

enum class CvDirection { along, across };

// The manifest tune-cv runs to measure CV in one direction: the manifest's
// cells, solver and coupling scheme on a strand (builder `strand`) or a
// fibrotic_sheet without fibrosis (1 mm wide along, 1 mm long across),
// `length_mm` long in the wave's direction, paced once in a 0.3 mm band at
// one edge with stimulus[0]'s amplitude and duration (measured_cv_m_per_s
// doubles the amplitude until the band fires); electrophysiology and
// coupling only, nothing written. ManifestError for another builder, or
// across on a strand.
json cv_measuring_manifest(const json& manifest, CvDirection direction, double length_mm, double D_m_nS,
                           double D_m_side_nS, double expected_m_per_s);

// The first beat's CV [m/s] of a measuring manifest's run, fitted as
// summary.json's cv_cm_per_s, along y or x; nullopt if the wave did not
// cross the tissue (block). The pulse only starts the wave: if the paced
// band does not fire, it is run again at twice the amplitude, up to 16x
// (then std::runtime_error).
std::optional<double> measured_cv_m_per_s(const json& measuring_manifest, CvDirection direction);

CvTuningResult tune_conduction_velocity(const json& manifest, const CvTuningOptions& options);

// The manifest with coupling.D_m_nS and D_m_side_nS set.
json with_conductances(json manifest, double D_m_nS, double D_m_side_nS);

}  // namespace fibrodem
