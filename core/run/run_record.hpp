// The RunRecord (measure/run_record.hpp) of a finished Simulation.
#pragma once

#include <string>

#include "measure/run_record.hpp"

namespace fibrodem {

class Simulation;

RunRecord record_of(const Simulation& simulation, std::string label = "");

}  // namespace fibrodem
