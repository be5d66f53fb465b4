// climbsim::adhesion, the module's one public header: dry-adhesive pads (docs/design.md section 3).
//
//   bond_grid.h        BondGrid, PadParams, PadLoad: stresses, rupture, the cascade (no MuJoCo)
//   pulloff.h          PullOff, PulloffSweep: the figure-6 experiment as pure math
//   frictional_law.h   the directional law (frictional adhesion) on the same grid (no MuJoCo)
//   tabulated_law.h    the measured law: pull-off against angle, interpolated, per bond
//   weld.h             weld switching and the weld's wrench (MuJoCo 2.2.2)
//   pad_contact.h      pad geometry, face frame, contact sensing
//   pad_touch.h        partial contact: which cells of a pad touch the surface at attach
//   sticky_pad.h       one pad: attach conditions, weld, build-up, load → bonds → detach, events
//   adhesion_system.h  every pad of a model, their MJCF, surfaces, start attachment
//   pulloff_rig.h      the figure-6 experiment in MuJoCo, both models
//   params.h           the scenario's adhesion block (AdhesionKeys), its keys declared by the
//                      structs above
//
// adhesion/README.md is the overview.
#ifndef CLIMBSIM_ADHESION_ADHESION_H_
#define CLIMBSIM_ADHESION_ADHESION_H_

#include "adhesion/adhesion_system.h"
#include "adhesion/bond_grid.h"
#include "adhesion/frictional_law.h"
#include "adhesion/pad_contact.h"
#include "adhesion/pad_touch.h"
#include "adhesion/params.h"
#include "adhesion/pulloff.h"
#include "adhesion/pulloff_rig.h"
#include "adhesion/sticky_pad.h"
#include "adhesion/tabulated_law.h"
#include "adhesion/weld.h"

#endif  // CLIMBSIM_ADHESION_ADHESION_H_
