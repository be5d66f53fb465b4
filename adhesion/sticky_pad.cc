#include "adhesion/sticky_pad.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "adhesion/weld.h"

namespace climbsim::adhesion {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The attach condition that fails first, in their fixed order (approach speed and angle at
// touchdown, contacts, preload now); cause kNone when all hold.
struct FailedCondition {
  PadCause cause = PadCause::kNone;
  double value = 0.0;
  long* rejected = nullptr;  // the counter of that condition
  bool final = false;        // a failure of the approach cannot improve in this episode
};

FailedCondition FirstFailedCondition(const AttachParams& a, bool count_contacts,
                                     double touchdown_speed_mps, double touchdown_angle_deg,
                                     const ContactSense& sense, PadCounts* counts) {
  FailedCondition f;
  if (touchdown_speed_mps > a.max_approach_speed_mps) {
    f.cause = PadCause::kApproachSpeed, f.value = touchdown_speed_mps, f.final = true;
    f.rejected = &counts->rejected_approach_speed;
  } else if (touchdown_angle_deg > a.max_approach_angle_deg) {
    f.cause = PadCause::kApproachAngle, f.value = touchdown_angle_deg, f.final = true;
    f.rejected = &counts->rejected_approach_angle;
  } else if (count_contacts && sense.contacts < a.min_contacts) {
    f.cause = PadCause::kContacts, f.value = sense.contacts;
    f.rejected = &counts->rejected_contacts;
  } else if (sense.preload_n < a.min_preload_n) {
    f.cause = PadCause::kPreload, f.value = sense.preload_n;
    f.rejected = &counts->rejected_preload;
  }
  return f;
}

// Conditions 1-4 of a pending landing. A conforming face that the window's press has not given
// min_contacts is judged by its touched share (condition 5) instead; before that, as a rigid one.
FailedCondition LandingCondition(const AttachParams& a, bool conforms, double since_touchdown_s,
                                 double touchdown_speed_mps, double touchdown_angle_deg,
                                 const ContactSense& sense, PadCounts* counts) {
  FailedCondition f =
      FirstFailedCondition(a, true, touchdown_speed_mps, touchdown_angle_deg, sense, counts);
  if (f.cause == PadCause::kContacts && conforms && since_touchdown_s >= a.attach_window_s) {
    f = FirstFailedCondition(a, false, touchdown_speed_mps, touchdown_angle_deg, sense, counts);
  }
  return f;
}

PadParams GridParams(const StickyPadParams& p, const PadGeometry& g) {
  PadParams grid = p.bonds;
  grid.width_m = g.width_m;
  grid.length_m = g.length_m;
  return grid;
}

void Check(bool ok, const char* key, const char* rule, double value) {
  if (ok) return;
  std::ostringstream s;
  s << "adhesion." << key << " must be " << rule << ", got " << value;
  throw std::invalid_argument(s.str());
}

}  // namespace

void ValidateStickyPadParams(const StickyPadParams& p) {
  keys::Validate(p.attach, "adhesion");
  Check(std::isfinite(p.release_contact_delay_s) && p.release_contact_delay_s >= 0,
        "release_contact_delay_s", ">= 0 and finite", p.release_contact_delay_s);
  if (p.law == PadLaw::kFrictional) ValidateFrictionalParams(p.frictional);
  if (p.law == PadLaw::kTabulated) ValidateTabulatedParams(p.tabulated);
  if (p.model == AdhesionModel::kMujoco) {
    Check(std::isfinite(p.actuator_gain_n) && p.actuator_gain_n > 0, "gain_n", "> 0 and finite",
          p.actuator_gain_n);
    Check(p.actuator_ctrl >= 0 && p.actuator_ctrl <= 1, "ctrl", "in [0, 1]", p.actuator_ctrl);
  }
}

const char* PadEventName(PadEventKind kind) {
  switch (kind) {
    case PadEventKind::kTouchdown:
      return "touchdown";
    case PadEventKind::kAttach:
      return "attach";
    case PadEventKind::kAttachRejected:
      return "attach_rejected";
    case PadEventKind::kBondsLost:
      return "bonds_lost";
    case PadEventKind::kDetach:
      return "detach";
  }
  return "";
}

const char* PadCauseName(PadCause cause) {
  switch (cause) {
    case PadCause::kNone:
      return "";
    case PadCause::kApproachSpeed:
      return "approach_speed_mps";
    case PadCause::kApproachAngle:
      return "approach_angle_deg";
    case PadCause::kContacts:
      return "contacts";
    case PadCause::kPreload:
      return "preload_n";
    case PadCause::kContactShare:
      return "contact_share";
    case PadCause::kFractionLost:
      return "fraction_lost";
    case PadCause::kStartAttached:
      return "start_attached";
    case PadCause::kForced:
      return "forced";
    case PadCause::kPeel:
      return "peel";
    case PadCause::kOverload:
      return "overload";
    case PadCause::kReleased:
      return "released";
    case PadCause::kContactLost:
      return "contact_lost";
    case PadCause::kFailure:
      return "failure";
  }
  return "";
}

StickyPad::StickyPad(const mjModel* m, int index, const PadGeometry& geometry,
                     const StickyPadParams& params, int weld_eq, int actuator)
    : index_(index),
      geometry_(geometry),
      params_(params),
      weld_eq_(weld_eq),
      actuator_(actuator),
      contype_(m->geom_contype[geometry.geom]),
      conaffinity_(m->geom_conaffinity[geometry.geom]),
      grid_(GridParams(params, geometry)),
      probe_(m, geometry, grid_.grid_x(), grid_.grid_y()),
      touching_(grid_.size(), 1),
      surfaces_(m->ngeom, 1),
      frictional_law_(params.law == PadLaw::kFrictional ? params.frictional : FrictionalParams{}) {
  ValidateStickyPadParams(params_);
  if (params_.law == PadLaw::kTabulated) tabulated_law_.emplace(params_.tabulated);
  surfaces_[geometry.geom] = 0;
  params_.bonds = grid_.params();
  if (params_.model == AdhesionModel::kBonds && (weld_eq < 0 || weld_eq >= m->neq)) {
    throw std::invalid_argument("adhesion: pad has no weld equality");
  }
  if (params_.model == AdhesionModel::kMujoco && (actuator < 0 || actuator >= m->nu)) {
    throw std::invalid_argument("adhesion: pad has no adhesion actuator");
  }
}

void StickyPad::Reset(mjModel* m, mjData* d) {
  if (weld_eq_ >= 0) SetWeldActive(m, d, weld_eq_, false);
  m->geom_contype[geometry_.geom] = contype_;
  m->geom_conaffinity[geometry_.geom] = conaffinity_;
  if (actuator_ >= 0) {
    m->actuator_gainprm[actuator_ * mjNGAIN] = params_.actuator_gain_n;
    d->ctrl[actuator_] = 0.0;
  }
  const double tau = params_.attach.buildup_time_s;
  grow_decay_ = tau > 0 ? std::exp(-m->opt.timestep / tau) : 0.0;
  release_contact_steps_ =
      static_cast<int>(std::lround(params_.release_contact_delay_s / m->opt.timestep));
  contact_off_steps_ = 0;
  grid_.Release();
  sense_ = ContactSense{};
  load_ = PadLoad{};
  attached_ = false;
  bonds_lost_ = false;
  surface_geom_ = -1;
  episode_ = Episode::kNone;
  refused_cause_ = PadCause::kNone;
  blind_ = false;
  buildup_ = 0.0;
  lost_since_attach_ = 0;
  strength_scale_ = 1.0;
  counts_ = PadCounts{};
  frictional_utilisation_ = 0.0;
  peeling_ = false;
  disengaged_ = false;
}

double StickyPad::bonded_fraction() const {
  if (params_.model == AdhesionModel::kMujoco) return attached_ ? 1.0 : 0.0;
  return grid_.bonded_fraction();
}

double StickyPad::touched_fraction() const {
  if (params_.model == AdhesionModel::kMujoco) return 1.0;
  return static_cast<double>(grid_.touching_count()) / grid_.size();
}

double StickyPad::bondable_fraction() const {
  if (params_.model == AdhesionModel::kMujoco) return 1.0;
  if (!attached_) return touched_fraction();  // its last attachment's tears are gone
  return static_cast<double>(grid_.touching_count() - lost_since_attach_) / grid_.size();
}

void StickyPad::Sense(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to) {
  bonds_lost_ = false;
  if (attached_ && params_.model == AdhesionModel::kBonds) return;  // no contacts while welded
  SensePadContacts(m, d, geometry_, sticks_to, &sense_);
  if (!attached_) {
    SetUnweldedLoad();
  } else {
    load_ = PadLoad{};
    load_.fn_n = params_.actuator_gain_n * params_.actuator_ctrl - sense_.preload_n;
  }
}

void StickyPad::SetUnweldedLoad() {
  load_ = PadLoad{};
  load_.fn_n = -sense_.preload_n;
}

void StickyPad::WhileAttached(mjModel* m, mjData* d, double time_s, PadEventSink* sink) {
  if (params_.model == AdhesionModel::kBonds) {
    // Build-up while the pad is not pulled off (known from the weld's first step on).
    if (load_known_ && load_.fn_n <= 0.0 && buildup_ < 1.0) {
      buildup_ = 1.0 - (1.0 - buildup_) * grow_decay_;
      grid_.Grow(buildup_);
    }
  } else if (sense_.contacts + sense_.contacts_in_gap == 0) {
    Detach(m, d, time_s, PadCause::kContactLost, sink);
  }
}

void StickyPad::Decide(mjModel* m, mjData* d, double time_s, bool* kinematics_current,
                       PadEventSink* sink) {
  if (contact_off_steps_ > 0 && --contact_off_steps_ == 0) {
    m->geom_contype[geometry_.geom] = contype_;
    m->geom_conaffinity[geometry_.geom] = conaffinity_;
  }
  if (attached_) {
    WhileAttached(m, d, time_s, sink);
    return;
  }

  if (blind_) {
    // The contacts just sensed come from a step in which the pad did not collide (it was
    // welded): they cannot tell whether it has left the surface.
    blind_ = false;
    return;
  }
  if (disengaged_) {
    episode_ = Episode::kNone;  // ordinary contact; a touch when engaged again is a new one
    refused_cause_ = PadCause::kNone;
    return;
  }
  if (sense_.contacts == 0) {
    episode_ = Episode::kNone;  // left the surface: the next touch is a new episode
    refused_cause_ = PadCause::kNone;
    return;
  }
  if (episode_ == Episode::kClosed) return;
  if (episode_ == Episode::kNone) {
    episode_ = Episode::kPending;
    touchdown_time_s_ = time_s;
    touchdown_speed_mps_ = sense_.approach_speed_mps;
    touchdown_angle_deg_ = sense_.angle_rad * kRadToDeg;
    ++counts_.touchdown;
    Emit(sink, time_s, PadEventKind::kTouchdown, PadCause::kNone, 0.0, false);
  }

  const AttachParams& a = params_.attach;
  const bool conforms = params_.conform_m > 0.0 && params_.contact.partial_contact;
  FailedCondition failed =
      LandingCondition(a, conforms, time_s - touchdown_time_s_, touchdown_speed_mps_,
                       touchdown_angle_deg_, sense_, &counts_);
  if (failed.cause == PadCause::kNone) {
    const double share = LandingContactShare(m, d, kinematics_current);
    if (share >= params_.contact.min_contact_share) {
      // Pressed on by its contacts: it sinks into the soft contact by their depth.
      Attach(m, d, time_s, sense_.surface_geom, a.initial_fraction, PadCause::kNone,
             kinematics_current, sink, {0.0, sense_.depth_m, true, true});
      return;
    }
    failed = {PadCause::kContactShare, share, &counts_.rejected_contact_share, false};
  }
  if (failed.final || time_s - touchdown_time_s_ >= a.attach_window_s) {
    episode_ = Episode::kClosed;
    refused_cause_ = failed.cause;
    ++counts_.attach_rejected;
    ++*failed.rejected;
    Emit(sink, time_s, PadEventKind::kAttachRejected, failed.cause, failed.value, true);
  }
}

bool StickyPad::ForceAttach(mjModel* m, mjData* d, double time_s, int surface_geom, double fraction,
                            PadCause cause, bool* kinematics_current, PadEventSink* sink,
                            double standoff_m, const ContactSense* seat) {
  if (attached_) return false;
  sense_.surface_geom = surface_geom;
  ++counts_.touchdown;
  Emit(sink, time_s, PadEventKind::kTouchdown, PadCause::kNone, 0.0, false);
  Attach(m, d, time_s, surface_geom, fraction, cause, kinematics_current, sink,
         {standoff_m, seat != nullptr ? seat->depth_m : 0.0, seat != nullptr});
  return true;
}

void StickyPad::Attach(mjModel* m, mjData* d, double time_s, int surface_geom, double fraction,
                       PadCause cause, bool* kinematics_current, PadEventSink* sink,
                       Seating seating) {
  attached_ = true;
  surface_geom_ = surface_geom;
  lost_since_attach_ = 0;
  episode_ = Episode::kClosed;
  if (params_.model == AdhesionModel::kBonds) {
    // The poses after the last mj_step are those before its integration: bring them up to
    // date so that the weld is written where the pad is now.
    if (!*kinematics_current) {
      mj_kinematics(m, d);
      *kinematics_current = true;
    }
    SetWeldFromCurrentPoses(m, d, weld_eq_, m->geom_bodyid[surface_geom], geometry_.face_pos_body);
    SetWeldActive(m, d, weld_eq_, true);
    contact_off_steps_ = 0;  // welded: no contacts to give back
    m->geom_contype[geometry_.geom] = 0;
    m->geom_conaffinity[geometry_.geom] = 0;
    MeasureTouching(m, d, seating);
    buildup_ = fraction;
    grid_.BondFraction(fraction);
    load_ = PadLoad{};
    load_known_ = false;
  } else {
    d->ctrl[actuator_] = params_.actuator_ctrl;
  }
  ++counts_.attach;
  Emit(sink, time_s, PadEventKind::kAttach, cause, 0.0, false);
}

double StickyPad::LandingContactShare(const mjModel* m, mjData* d, bool* kinematics_current) {
  if (!params_.contact.partial_contact || params_.model != AdhesionModel::kBonds) return 1.0;
  if (!*kinematics_current) {
    mj_kinematics(m, d);
    *kinematics_current = true;
  }
  const int touched = probe_.MeasureSeated(m, d, surfaces_, params_.contact.contact_gap_m, 0.0,
                                           sense_.depth_m, touching_);
  return static_cast<double>(touched) / grid_.size();
}

void StickyPad::MeasureTouching(const mjModel* m, const mjData* d, const Seating& s) {
  if (!params_.contact.partial_contact) {
    grid_.TouchAll();
    return;
  }
  if (s.measured) {
    grid_.SetTouching(touching_);
    return;
  }
  if (s.seated) {
    probe_.MeasureSeated(m, d, surfaces_, params_.contact.contact_gap_m, s.standoff_m,
                         s.pressed_m, touching_);
  } else {
    probe_.Measure(m, d, surfaces_, params_.contact.contact_gap_m, s.standoff_m, s.pressed_m,
                   touching_);
  }
  grid_.SetTouching(touching_);
}

void StickyPad::AfterStep(mjModel* m, mjData* d, double time_s, PadEventSink* sink) {
  if (!attached_ || params_.model != AdhesionModel::kBonds) return;
  // The weld's wrench of this step, at the face centroid, into the pad frame.
  WeldWrench w;
  ReadWeldWrench(m, d, weld_eq_, &w);
  const PadFrame frame = FaceFrame(d, geometry_);
  load_ = PadLoadFromSurfaceWrench(frame.rot.transpose() * w.force_n,
                                   frame.rot.transpose() * w.torque_nm);
  load_known_ = true;
  PadLoad scaled = load_;
  if (strength_scale_ != 1.0) {
    const double k = 1.0 / strength_scale_;
    scaled = {load_.fn_n * k, load_.fx_n * k, load_.fy_n * k, load_.mx_nm * k, load_.my_nm * k};
  }
  BondGrid::UpdateResult r;
  switch (params_.law) {
    case PadLaw::kFrictional:
      r = FrictionalUpdate(&grid_, frictional_law_, scaled, &frictional_utilisation_);
      break;
    case PadLaw::kTabulated:
      r = TabulatedUpdate(&grid_, *tabulated_law_, scaled, &frictional_utilisation_);
      break;
    case PadLaw::kVonMises:
      r = grid_.Update(scaled);
      break;
  }
  if (r.broken > 0) {
    bonds_lost_ = true;
    ++counts_.bonds_lost;
    Emit(sink, time_s, PadEventKind::kBondsLost, PadCause::kFractionLost,
         static_cast<double>(r.broken) / grid_.size(), true);
  }
  if (r.detached) {
    Detach(m, d, time_s, lost_since_attach_ > 0 || peeling_ ? PadCause::kPeel : PadCause::kOverload,
           sink);
  }
  lost_since_attach_ += r.broken;
}

bool StickyPad::UtilisationGradient(Eigen::Matrix<double, 5, 1>* grad, int peak_bond) const {
  if (!attached_ || params_.model != AdhesionModel::kBonds || !load_known_ ||
      params_.law == PadLaw::kTabulated) {
    return false;
  }
  const bool frictional = params_.law == PadLaw::kFrictional;
  // The load as the grid sees it (a weak patch scales it; the frictional law's moment share),
  // and the chain factors back to the pad's own load.
  Eigen::Matrix<double, 5, 1> chain;
  const double share = frictional ? frictional_law_.params().moment_share : 1.0;
  chain << 1.0, 1.0, 1.0, share, share;
  chain /= strength_scale_;
  const PadLoad seen{load_.fn_n * chain[0], load_.fx_n * chain[1], load_.fy_n * chain[2],
                     load_.mx_nm * chain[3], load_.my_nm * chain[4]};
  if (!PadUtilisationGradient(grid_, frictional ? &frictional_law_ : nullptr, seen, grad,
                              peak_bond)) {
    return false;
  }
  *grad = grad->cwiseProduct(chain);
  return true;
}

bool StickyPad::Release(mjModel* m, mjData* d, double time_s, PadEventSink* sink) {
  if (!attached_) return false;
  Detach(m, d, time_s, PadCause::kReleased, sink);
  return true;
}

bool StickyPad::Fail(mjModel* m, mjData* d, double time_s, PadEventSink* sink) {
  if (!attached_) return false;
  bonds_lost_ = true;
  ++counts_.bonds_lost;
  Emit(sink, time_s, PadEventKind::kBondsLost, PadCause::kFractionLost, bonded_fraction(), true);
  Detach(m, d, time_s, PadCause::kFailure, sink);
  return true;
}

void StickyPad::Detach(mjModel* m, mjData* d, double time_s, PadCause cause,
                       PadEventSink* sink) {
  switch (cause) {
    case PadCause::kPeel:
      ++counts_.detach_peel;
      break;
    case PadCause::kOverload:
      ++counts_.detach_overload;
      break;
    case PadCause::kReleased:
      ++counts_.detach_released;
      break;
    case PadCause::kContactLost:
      ++counts_.detach_contact_lost;
      break;
    case PadCause::kFailure:
      ++counts_.detach_failure;
      break;
    default:
      break;
  }
  // The event carries the load and the bonds that ended the pad, before they are cleared.
  Emit(sink, time_s, PadEventKind::kDetach, cause, 0.0, false);
  if (params_.model == AdhesionModel::kBonds) {
    SetWeldActive(m, d, weld_eq_, false);
    if (cause == PadCause::kReleased && release_contact_steps_ > 0) {
      contact_off_steps_ = release_contact_steps_;  // Decide gives the contacts back
    } else {
      m->geom_contype[geometry_.geom] = contype_;
      m->geom_conaffinity[geometry_.geom] = conaffinity_;
    }
    grid_.Release();
    blind_ = true;
  } else {
    d->ctrl[actuator_] = 0.0;
  }
  attached_ = false;
  episode_ = Episode::kClosed;  // no re-attach before the pad has left the surface
  // Nothing is sensed until the next Sense: the pad carries nothing meanwhile.
  sense_ = ContactSense{};
  SetUnweldedLoad();
}

void StickyPad::Emit(PadEventSink* sink, double time_s, PadEventKind kind, PadCause cause,
                     double value, bool has_value) const {
  if (sink == nullptr) return;
  PadEvent e;
  e.time_s = time_s;
  e.kind = kind;
  e.cause = cause;
  e.cause_value = value;
  e.has_cause_value = has_value;
  e.surface_geom = attached_ ? surface_geom_ : sense_.surface_geom;
  e.bonded_fraction = bonded_fraction();
  e.load = load_;
  sink->OnPadEvent(index_, e);
}

}  // namespace climbsim::adhesion
