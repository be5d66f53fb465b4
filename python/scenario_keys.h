// A Python Scenario's keys: s["cpg.frequency_hz"], s["cpg.stride_rad[0]"] = 0.3, get, keys,
// `in`, del (back to the default), to_dict; every write checked by the scenario loader.
#ifndef CLIMBSIM_PYTHON_SCENARIO_KEYS_H_
#define CLIMBSIM_PYTHON_SCENARIO_KEYS_H_

#include <pybind11/pybind11.h>

#include "scenario/scenario.h"

namespace climbsim::python {

void BindScenarioKeys(pybind11::class_<sim::Scenario>& cls);

}  // namespace climbsim::python

#endif  // CLIMBSIM_PYTHON_SCENARIO_KEYS_H_
