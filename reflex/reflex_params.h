// The scenario's reflex block (reflex:): every leg's reflexes as one set, the GTO's robot-level
// channels and the landing, with their keys as the scenario file spells them. scenario/ reads
// it; sim/reflex_effect runs it (LegReflex per leg, LoadSharing, PostureReflex, the landing).
#ifndef CLIMBSIM_REFLEX_REFLEX_PARAMS_H_
#define CLIMBSIM_REFLEX_REFLEX_PARAMS_H_

#include <optional>

#include "keys/keys.h"
#include "reflex/foot_params.h"
#include "reflex/laws.h"
#include "reflex/leg_params.h"
#include "reflex/load_sharing.h"
#include "reflex/tail_reflex.h"

namespace climbsim::reflex {

// The gto block: a leg's GTO channels, then the robot-level ones the simulator runs across
// the legs (load sharing, posture).
struct GtoBlockParams : GtoHoldParams {
  LoadSharingParams share;
  PostureParams posture;

  template <class A>
  void Serialize(A* a) {
    GtoHoldParams::Serialize(a);
    a->Visit({"share", "",
              "load sharing among the attached pads: internal forces that drive down the worst "
              "pad's utilisation (reflex/README.md)"},
             &share);
    a->Visit({"posture", "",
              "posture: the pads' pull off the surface lowers the body (reflex/README.md)"},
             &posture);
  }
};

// The spindle block: one law for the three joints of every leg (Leg() copies it to each of
// LegSpindleParams::joints, which the block leaves unused).
struct SpindleBlockParams : LegSpindleParams {
  SpindleParams law;

  template <class A>
  void Serialize(A* a) {
    LegSpindleParams::Serialize(a);
    law.Serialize(a);
  }
};

// Landing on a directional pad (sim/reflex_effect.h, the landing channel): a pad welded at zero
// load holds no pull, so the leg that lands must neither pull it nor spring back off it.
struct LandingParams {
  double settle_s = 0.0;  // time constant of the settled target's fade, s; 0 = off
  double drag_n = 0.0;    // drag along the pad's gripping direction, N

  template <class A>
  void Serialize(A* a) {
    a->Visit({"settle_s", "s",
              "at each attach the leg's servo error is taken into its target and fades with this "
              "time constant, so the leg holds the pad where it landed; 0 = off",
              Range::NonNegative()},
             &settle_s);
    a->Visit({"drag_n", "N",
              "settle_s > 0, adhesion.law frictional: the settled target also drags the pad this "
              "much along its gripping direction (through the servos' stiffness), engaging the "
              "adhesive before it is pulled",
              Range::NonNegative()},
             &drag_n);
  }
};

struct ReflexParams {
  LandingParams landing;
  PreloadParams preload;
  SearchParams search;
  PeelParams peel;
  RegripParams regrip;
  GtoBlockParams gto;
  SpindleBlockParams spindle;
  ComplianceParams compliance;
  double max_offset_rad = LegReflexParams{}.max_offset_rad;
  // A peel that runs out of time lets the pad go (the simulator detaches it, cause released).
  bool release_failed_peel = false;
  std::optional<TailReflexParams> tail;  // absent: off (and the robot needs no tail)

  template <class A>
  void Serialize(A* a) {
    a->Visit({"preload", "", "press on touchdown"}, &preload);
    a->Visit({"search", "", "reach again when a swing finds no surface"}, &search);
    a->Visit({"peel", "", "peel the pad at swing onset"}, &peel);
    a->Visit({"regrip", "", "press again after an unexpected bond loss"}, &regrip);
    a->Visit({"gto", "", "load reflexes"}, &gto);
    a->Visit({"spindle", "", "stretch reflexes"}, &spindle);
    a->Visit({"compliance", "", "servo stiffness by phase"}, &compliance);
    a->Visit({"landing", "", "settle and drag a leg as its pad attaches"}, &landing);
    LegReflexParams::VisitMaxOffset(a, &max_offset_rad);
    a->Visit({"release_failed_peel", "",
              "when a peel runs out of time, let the pad go (detach cause released), as a foot "
              "with an active release mechanism would"},
             &release_failed_peel);
    a->Visit({"tail", "",
              "press the robot's tail on the surface when a front pad fails or the body pitches "
              "off (needs robot.tail); absent: off"},
             &tail);
  }

  // Whether the GTO's posture acts: the CPG sizes its leg IK table for it, the reflex effect
  // runs it.
  bool PostureOn() const { return gto.enabled && gto.posture.enabled; }

  // The reflex module's parameters for one leg.
  LegReflexParams Leg() const;

  // What the ranges cannot check, at the control period dt_s: the leg's durations and delays
  // (CheckControlPeriod above) and, when it acts, the posture's delay. Keys as the block
  // spells them ("spindle.delay_s", "gto.posture.delay_s"), through checker.Fail.
  void CheckControlPeriod(double dt_s, const Checker& checker) const;
};

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_REFLEX_PARAMS_H_
