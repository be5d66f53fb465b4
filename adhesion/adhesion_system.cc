#include "adhesion/adhesion_system.h"

#include <cmath>
#include <sstream>

#include "adhesion/weld.h"

namespace climbsim::adhesion {

AdhesionMjcfText AdhesionMjcf(const std::vector<PadSpec>& pads,
                              const std::array<double, 2>& weld_solref) {
  AdhesionMjcfText text;
  std::ostringstream eq, act;
  eq.precision(17);
  act.precision(17);
  for (const PadSpec& p : pads) {
    if (p.params.model == AdhesionModel::kBonds) {
      eq << "    <weld name=\"" << WeldName(p.body) << "\" body1=\"" << p.body
         << "\" active=\"false\" solref=\"" << weld_solref[0] << " " << weld_solref[1] << "\"/>\n";
    } else {
      act << "    <adhesion name=\"" << AdhesionActuatorName(p.body) << "\" body=\"" << p.body
          << "\" gain=\"" << p.params.actuator_gain_n << "\" ctrlrange=\"0 1\"/>\n";
    }
  }
  text.equality = eq.str();
  text.actuator = act.str();
  return text;
}

AdhesionSystem::AdhesionSystem(const mjModel* m, const AdhesionSystemParams& params)
    : params_(params) {
  if (!(params_.start_gap_m > 0) || !std::isfinite(params_.start_gap_m)) {
    throw std::invalid_argument("adhesion.start_gap_m must be > 0");
  }
  if (!(params_.reach_m >= 0) || !std::isfinite(params_.reach_m)) {
    throw std::invalid_argument("adhesion.reach_m must be >= 0");
  }
  sticks_to_.assign(m->ngeom, 0);
  std::vector<uint8_t> sticky(m->ngeom, 0);
  pads_.reserve(params_.pads.size());
  for (const PadSpec& spec : params_.pads) sticky[AddPad(m, spec)] = 1;
  ResolveSurfaces(m, sticky);
  for (StickyPad& p : pads_) p.SetSurfaces(sticks_to_);
}

// Resolves one pad (its body, box, and the weld or actuator AdhesionMjcf added) and builds
// it; returns its geom.
int AdhesionSystem::AddPad(const mjModel* m, const PadSpec& spec) {
  const int body = mj_name2id(m, mjOBJ_BODY, spec.body.c_str());
  if (body < 0) throw AdhesionSetupError("pads", "no body named '" + spec.body + "'");
  for (const std::string& other : names_) {
    if (other == spec.body) throw AdhesionSetupError("pads", "pad '" + other + "' given twice");
  }
  const std::string problem = PadGeometryProblem(m, body);
  if (!problem.empty()) throw AdhesionSetupError("pads", problem);
  const PadGeometry geometry = ReadPadGeometry(m, body);
  int weld = -1, actuator = -1;
  if (spec.params.model == AdhesionModel::kBonds) {
    weld = mj_name2id(m, mjOBJ_EQUALITY, WeldName(spec.body).c_str());
    if (weld < 0 || m->eq_type[weld] != mjEQ_WELD) {
      throw AdhesionSetupError("pads", "the model lacks the weld '" + WeldName(spec.body) +
                                           "' (add AdhesionMjcf's lines)");
    }
  } else {
    actuator = mj_name2id(m, mjOBJ_ACTUATOR, AdhesionActuatorName(spec.body).c_str());
    if (actuator < 0) {
      throw AdhesionSetupError("pads", "the model lacks the actuator '" +
                                           AdhesionActuatorName(spec.body) +
                                           "' (add AdhesionMjcf's lines)");
    }
  }
  pads_.emplace_back(m, static_cast<int>(pads_.size()), geometry, spec.params, weld, actuator);
  names_.push_back(spec.body);
  return geometry.geom;
}

// sticks_to_ per geom: the named bodies' geoms and the named geoms, or every geom that is not
// a pad's (`sticky`) when none are named.
void AdhesionSystem::ResolveSurfaces(const mjModel* m, const std::vector<uint8_t>& sticky) {
  if (params_.surfaces.empty()) {
    for (int g = 0; g < m->ngeom; ++g) sticks_to_[g] = !sticky[g];
    return;
  }
  for (const std::string& name : params_.surfaces) {
    const int body = mj_name2id(m, mjOBJ_BODY, name.c_str());
    const int geom = mj_name2id(m, mjOBJ_GEOM, name.c_str());
    if (body < 0 && geom < 0) {
      throw AdhesionSetupError("surfaces", "no body or geom named '" + name + "'");
    }
    if (geom >= 0) sticks_to_[geom] = 1;
    for (int g = 0; body >= 0 && g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] == body) sticks_to_[g] = 1;
    }
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (sticky[g] && sticks_to_[g]) {
      throw AdhesionSetupError("surfaces", std::string("a sticky pad cannot be a surface: '") +
                                               mj_id2name(m, mjOBJ_GEOM, g) + "'");
    }
  }
}

int AdhesionSystem::FindPad(int body) const {
  for (int i = 0; i < size(); ++i) {
    if (pads_[i].geometry().body == body) return i;
  }
  return -1;
}

void AdhesionSystem::Reset(mjModel* m, mjData* d, PadEventSink* sink) {
  for (StickyPad& p : pads_) {
    p.Reset(m, d);
    if (p.params().model == AdhesionModel::kMujoco) {
      m->geom_margin[p.geometry().geom] = params_.reach_m;
      m->geom_gap[p.geometry().geom] = params_.reach_m;
    }
  }
  if (params_.start_attached) StartAttached(m, d, sink);
}

void AdhesionSystem::StartAttached(mjModel* m, mjData* d, PadEventSink* sink) {
  // Collision with the pads' margins widened to start_gap_m: a pad within that distance of a
  // surface gets contacts (dist < margin, so exclude == 0).
  std::vector<std::array<double, 2>> saved(pads_.size());
  for (size_t i = 0; i < pads_.size(); ++i) {
    const int g = pads_[i].geometry().geom;
    saved[i] = {m->geom_margin[g], m->geom_gap[g]};
    m->geom_margin[g] = std::max(m->geom_margin[g], params_.start_gap_m);
    m->geom_gap[g] = 0.0;
  }
  mj_fwdPosition(m, d);
  std::vector<ContactSense> sense(pads_.size());
  for (size_t i = 0; i < pads_.size(); ++i) {
    SensePadContacts(m, d, pads_[i].geometry(), sticks_to_, &sense[i]);
    const int g = pads_[i].geometry().geom;
    m->geom_margin[g] = saved[i][0];
    m->geom_gap[g] = saved[i][1];
  }
  bool kinematics_current = true;  // mj_fwdPosition ran on the current qpos
  for (size_t i = 0; i < pads_.size(); ++i) {
    if (sense[i].contacts == 0) continue;
    // Seated on the contact that found it, like a landing pad: the robot was set on the
    // surface, its pads pressed flat (a start pose a few degrees off leaves the far cells
    // beyond the gap otherwise).
    pads_[i].ForceAttach(m, d, d->time, sense[i].surface_geom, 1.0, PadCause::kStartAttached,
                         &kinematics_current, sink, params_.start_gap_m, &sense[i]);
  }
  // Leave mjData consistent with the true margins and the welds (contacts, efc forces).
  mj_forward(m, d);
}

void AdhesionSystem::BeforeStep(mjModel* m, mjData* d, PadEventSink* sink) {
  for (StickyPad& p : pads_) p.Sense(m, d, sticks_to_);
  bool kinematics_current = false;
  for (StickyPad& p : pads_) p.Decide(m, d, d->time, &kinematics_current, sink);
}

void AdhesionSystem::AfterStep(mjModel* m, mjData* d, PadEventSink* sink) {
  for (StickyPad& p : pads_) p.AfterStep(m, d, d->time, sink);
}

bool AdhesionSystem::Release(int pad, mjModel* m, mjData* d, PadEventSink* sink) {
  if (pad < 0 || pad >= size()) return false;
  return pads_[pad].Release(m, d, d->time, sink);
}

}  // namespace climbsim::adhesion
