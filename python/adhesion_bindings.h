// climbsim._core's pad functions, pulloff and fit_adhesion (python/adhesion_bindings.cc).
#ifndef CLIMBSIM_PYTHON_ADHESION_BINDINGS_H_
#define CLIMBSIM_PYTHON_ADHESION_BINDINGS_H_

#include <pybind11/pybind11.h>

namespace climbsim::python {

// Defines pulloff (replacing an earlier one of the same name) and fit_adhesion on `m`.
void BindAdhesion(pybind11::module_& m);

}  // namespace climbsim::python

#endif  // CLIMBSIM_PYTHON_ADHESION_BINDINGS_H_
