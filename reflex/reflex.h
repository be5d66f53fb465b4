// climbsim::reflex: leg-level reflex laws and the leg-level climbing reflex state machine.
// This umbrella header is what users include; the module is split by topic:
//   laws.h          delay line, spindle-like and GTO-like laws (GtoLaw, GtoUnloadKpFraction)
//   foot_params.h   preload, search, peel and re-grip parameters and their keys
//   leg_params.h    GTO hold, spindle and compliance parameters; LegReflexParams
//   leg_reflex.h    LegReflex: sensing, events, output, state and the state machine
//   push_hold.h     PushHold: the spindles' push hold for the robot
//   load_sharing.h  the GTO's robot-level channels: LoadSharing, PostureReflex, grip targets
//   reflex_params.h the scenario's reflex block (ReflexParams) with the landing
// Each parameter struct declares its scenario keys (Serialize: name, unit, range, doc; the
// default is the field's initialiser); the constructors check a struct against that
// declaration (keys::Validate) and, by hand, only what needs the control period.
//
// Pure controller code: Eigen only, no MuJoCo. Every object here is built once from a Params
// struct and a fixed control period `dt_s`, validated in the constructor (bad Params throw
// std::invalid_argument naming the key and the value), and then updated once per control
// period with `Update(...)`, which never allocates and never throws. `Reset()` returns an
// object to the state it had just after construction.
//
// Notation (docs/control.md): [z]₊ = max(0, z); X(t−Δ) is X delayed by Δ.
//
// Delays. The controller runs at a fixed period dt_s, so a transmission delay Δ is held as a
// whole number of samples n = round(Δ / dt_s), rounded to nearest with ties away from zero
// (std::lround): Δ = 5 ms at dt = 2 ms becomes 3 samples (6 ms). The delay that acts is
// therefore n·dt_s, within dt_s/2 of the one asked for; `delay_samples()` reports it. A delay
// is rounded rather than rejected so that one Params set works at any control period (the
// optimiser may change dt_s); Geyer and Herr's 20/10/5 ms are exact at dt = 1 ms.
//
// Joint convention for the three joints of a leg, indexed by `Joint`:
//   hip_yaw   + moves the foot forward,
//   hip_pitch + lifts the foot away from the surface,
//   knee      + lifts the foot (flexion).
// So "press into the surface" is a negative hip_pitch/knee offset, "lift" a positive one.
// Every offset below is in rad and is added to the CPG's joint target.
//
// References.
//   Geyer H, Herr H (2010) IEEE TNSRE 18:263, a reflex-based neuromuscular biped: delayed
//     length (spindle) and force (GTO) feedback, positive force feedback in stance.
//   SCONE's reflex form: u = C0 + K_F·[F̃(t−Δ) − F0] + K_L·[l̃(t−Δ) − L0] + K_V·[ṽ(t−Δ) − V0]₊.
//   Ekeberg Ö, Pearson K (2005) J Neurophysiol 94:4256: a leg leaves stance when unloaded.
//   Tian Y et al. (2006) PNAS 103:19320: geckos detach by rolling their toes up and back
//     (hyperextension), which cuts adhesion by orders of magnitude; Autumn K et al. (2006)
//     J Exp Biol 209:3569 find the toe releases at a critical angle rather than like tape.
//   Kendall K (1975) J Phys D 8:1449: peeling needs far less force than a normal pull-off.
//   Dürr V (2001) J Exp Biol 204:1589: a leg that finds no ground searches in rhythmic loops.
#ifndef CLIMBSIM_REFLEX_REFLEX_H_
#define CLIMBSIM_REFLEX_REFLEX_H_

#include "reflex/foot_params.h"
#include "reflex/laws.h"
#include "reflex/leg_params.h"
#include "reflex/leg_reflex.h"
#include "reflex/load_sharing.h"
#include "reflex/push_hold.h"
#include "reflex/reflex_params.h"

#endif  // CLIMBSIM_REFLEX_REFLEX_H_
