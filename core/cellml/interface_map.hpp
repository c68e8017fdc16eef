// What an imported model is at fibrodem's boundary: which state is the
// membrane potential, which quantity is the CellML's own stimulus, the
// membrane capacitance, a myofilament model's Ca_i input, the --map outputs,
// and the scale factors from the CellML's time and voltage units to ms and mV.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cellml/model_analysis.hpp"
#include "cellml/plugin_writer.hpp"

namespace fibrodem::cellml {

struct InterfaceMap {
  int v = -1;         // the membrane potential (a state)
  int stim = -1;      // the CellML's stimulus, or -1
  int c_param = -1;   // the CellML's capacitance constant [pF], when it is the capacitance parameter
  int ca_input = -1;  // a myofilament model's input Ca_i
  std::map<std::string, int> mapped;  // --map signal -> quantity
  double time_scale = 1.0;  // t_src = t_ms * time_scale
  double v_scale = 1.0;     // V_mV = V_src * v_scale
  double gain = 0.0;        // d(dV/dt)/d(stim), source units
  // The stimulus takes fibrodem's i_ext [pA] in its own units:
  // stim = i_ext * stim_per_pA, divided by C_pF at run time if stim_over_C.
  double stim_per_pA = 0.0;
  bool stim_over_C = false;
  std::string v_rule, stim_rule;  // why they were chosen: annotation, name, units or structure, an option
  double capacitance_pF = 100.0;
  std::string area_note;  // currents per membrane area: how C_pF relates to the area
  std::vector<std::string> notes;
  std::string summary;  // one line: what V and the stimulus are and why (the plugin's description)
};

InterfaceMap map_interface(const Model& model, const WriterOptions& options);

// A double as a C++ literal that reads back to the same value.
std::string lit(double x);

}  // namespace fibrodem::cellml
