// climbsim::cpg — central pattern generators for legged climbers.
//
// One oscillator per leg, coupled so that the legs keep a gait's phase offsets; each
// oscillator's phase and amplitude are then shaped into three joint targets per leg. Two kinds
// of oscillator share one interface (OscillatorNetwork), both integrated with Boost.Odeint:
//
//   PhaseNetwork  phase oscillators with amplitude (Ijspeert et al. 2007, Science 315:1416):
//                   dθ_i/dt = 2πf + Σ_j w_ij·r_j·sin(θ_j − θ_i − φ_ij) + feedback_i
//                   dr_i/dt = a·(R_i − r_i)
//   HopfNetwork   Hopf oscillators whose frequency switches between stance and swing
//                 (Righetti and Ijspeert 2008, ICRA, doi 10.1109/ROBOT.2008.4543306), coupled
//                 through rotation matrices so that any phase offset can be asked for.
//
// Phase convention (Owaki et al. 2013, generalised to any duty factor D): θ ∈ [0, 2π);
// swing for θ ∈ [0, 2π(1−D)), stance for θ ∈ [2π(1−D), 2π). A network's phase_rad() follows it.
//
// Gaits are phase offsets: leg i lags by offset_i cycles, θ_i = 2πft − 2π·offset_i in steady
// state (HopfNetwork: in its phase that is uniform in time), which the coupling enforces
// through φ_ij = 2π·(offset_i − offset_j).
//
// Nothing here knows of MuJoCo. Parameters are plain structs, checked once when a network is
// built (std::invalid_argument naming the field and the value); Step never throws on numbers
// and never allocates; trouble while integrating is reported by status(), not thrown.
// The README next to this file has the laws, the defaults, a snippet and the test map.
#ifndef CLIMBSIM_CPG_CPG_H_
#define CLIMBSIM_CPG_CPG_H_

// By topic: oscillator_network.h (the interface, stepper, status), gait.h (offsets, presets,
// bias and coupling), phase_network.h, hopf_network.h, leg_shape.h (Tegotae feedback, phase
// -> joint targets), params.h (the scenario's cpg keys).
#include "cpg/gait.h"
#include "cpg/hopf_network.h"
#include "cpg/leg_shape.h"
#include "cpg/oscillator_network.h"
#include "cpg/params.h"
#include "cpg/phase_network.h"

#endif  // CLIMBSIM_CPG_CPG_H_
