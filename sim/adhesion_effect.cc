#include "sim/adhesion_effect.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/surface.h"

namespace climbsim::sim {
namespace {

adhesion::StickyPadParams PadParamsFrom(const AdhesionParams& p) {
  adhesion::StickyPadParams s;
  s.model =
      p.model == "mujoco" ? adhesion::AdhesionModel::kMujoco : adhesion::AdhesionModel::kBonds;
  s.bonds = p;  // the pad's width and length are read from its geom
  s.attach = p;
  s.actuator_ctrl = p.ctrl;
  s.law = p.law == "frictional"  ? adhesion::PadLaw::kFrictional
          : p.law == "tabulated" ? adhesion::PadLaw::kTabulated
                                 : adhesion::PadLaw::kVonMises;
  s.frictional = p.frictional;
  s.tabulated = p.tabulated;
  s.release_contact_delay_s = p.release_contact_delay_s;
  s.contact = p;
  return s;
}

std::array<double, 2> WeldSolref(const AdhesionParams& p) {
  return {p.weld_solref[0], p.weld_solref[1]};
}

// A pad's gripping direction after its overrides breaks the frictional law's own rule
// (FrictionalParams::Validate): the error is the override's, at adhesion.pad_overrides.
class OverrideChecker final : public Checker {
 public:
  OverrideChecker(const Scenario& scenario, const std::string& pad)
      : scenario_(scenario), pad_(pad) {}
  [[noreturn]] void Fail(std::string_view, const std::string& message) const override {
    throw ScenarioError(scenario_, "adhesion.pad_overrides", "'" + pad_ + "': " + message);
  }
  bool Has(std::string_view) const override { return true; }

 private:
  const Scenario& scenario_;
  const std::string& pad_;
};

// What a leg's reflexes need of an attach refusal: the approach, or which test of the place.
reflex::Refusal RefusalOf(adhesion::PadCause cause) {
  switch (cause) {
    case adhesion::PadCause::kApproachSpeed:
    case adhesion::PadCause::kApproachAngle:
      return reflex::Refusal::kApproach;
    case adhesion::PadCause::kContacts:
      return reflex::Refusal::kContacts;
    case adhesion::PadCause::kContactShare:
      return reflex::Refusal::kShare;
    default:
      return reflex::Refusal::kNone;
  }
}

}  // namespace

std::vector<adhesion::PadSpec> AdhesionPadSpecs(const Scenario& scenario,
                                                const AdhesionParams& params, const mjModel* m,
                                                const RobotInfo& robot) {
  std::vector<std::string> names = params.pads;
  if (names.empty()) {
    for (const LegInfo& leg : robot.legs) names.push_back(mj_id2name(m, mjOBJ_BODY, leg.pad_body));
    // An adhesive tail tip (robot/tail.h) is a sticky pad too, after the legs'.
    if (robot.tail.pad_body >= 0) names.push_back(mj_id2name(m, mjOBJ_BODY, robot.tail.pad_body));
    if (names.empty()) {
      throw ScenarioError(scenario, "adhesion.pads",
                          "the robot declares no legs (custom text climbsim_legs): name the pads");
    }
  }
  // A soft foam in the legs' pad backing (robot.pads.foam_m) lets their faces follow relief
  // farther than the adhesive's own reach (mjcf/README.md, climbsim_pad_conform_m).
  double conform_m = 0.0;
  if (CustomNumeric(m, "climbsim_pad_conform_m", 1, &conform_m) && !(conform_m >= 0)) {
    throw ScenarioError(scenario, "robot", "climbsim_pad_conform_m must be >= 0");
  }
  std::vector<adhesion::PadSpec> specs;
  for (const std::string& name : names) {
    const int body = mj_name2id(m, mjOBJ_BODY, name.c_str());
    if (body < 0) throw ScenarioError(scenario, "adhesion.pads", "no body named '" + name + "'");
    const std::string problem = adhesion::PadGeometryProblem(m, body);
    if (!problem.empty()) throw ScenarioError(scenario, "adhesion.pads", problem);
    const adhesion::PadGeometry geometry = adhesion::ReadPadGeometry(m, body);
    for (const auto& s : specs) {
      if (s.body == name)
        throw ScenarioError(scenario, "adhesion.pads", "'" + name + "' given twice");
    }
    adhesion::PadSpec spec{name, PadParamsFrom(params)};
    if (std::any_of(robot.legs.begin(), robot.legs.end(),
                    [&](const LegInfo& leg) { return leg.pad_body == body; })) {
      spec.params.contact.contact_gap_m += conform_m;
      spec.params.conform_m = conform_m;
    }
    double sigma = params.sigma_t_pa;
    std::optional<double> gain = params.gain_n;
    for (const AdhesionPadOverride& o : params.pad_overrides) {
      if (o.pad != name) continue;
      if (o.sigma_t_pa) sigma = spec.params.bonds.sigma_t_pa = *o.sigma_t_pa;
      if (o.mu) spec.params.bonds.mu = *o.mu;
      if (o.gain_n) gain = o.gain_n;
      if (o.grip_x) spec.params.frictional.grip_x = *o.grip_x;
      if (o.grip_y) spec.params.frictional.grip_y = *o.grip_y;
      spec.params.frictional.Validate(OverrideChecker(scenario, name));
    }
    // Every other value was checked where it was read (the pad's gain: σ_T·A > 0).
    spec.params.actuator_gain_n = gain.value_or(sigma * geometry.width_m * geometry.length_m);
    specs.push_back(std::move(spec));
  }
  for (const AdhesionPadOverride& o : params.pad_overrides) {
    if (std::none_of(specs.begin(), specs.end(), [&](const auto& s) { return s.body == o.pad; })) {
      throw ScenarioError(scenario, "adhesion.pad_overrides",
                          "'" + o.pad + "' is not one of the sticky pads");
    }
  }
  return specs;
}

void AddAdhesionMjcf(const Scenario& scenario, const AdhesionParams& params,
                     MjcfAdditions* additions) {
  // The pads are the robot's legs unless named: compile robot and scene once to read them.
  const std::unique_ptr<CompiledModel> base = CompiledModel::Build(scenario, MjcfAdditions{});
  const auto specs = AdhesionPadSpecs(scenario, params, base->model(), base->robot());
  const adhesion::AdhesionMjcfText text = adhesion::AdhesionMjcf(specs, WeldSolref(params));
  additions->equality += text.equality;
  additions->actuator += text.actuator;
}

AdhesionEffect::AdhesionEffect(const Scenario& scenario, const AdhesionParams& params, World& world)
    : params_(params),
      seed_(scenario.seed),
      weak_patches_(scenario.scene.weak_patches),
      world_(&world) {
  mjModel* m = world.model();
  adhesion::AdhesionSystemParams sys;
  sys.pads = AdhesionPadSpecs(scenario, params, m, world.robot());
  sys.surfaces = params.surfaces;
  sys.start_attached = params.start_attached;
  sys.start_gap_m = params.start_gap_m;
  sys.reach_m = params.reach_m;
  // The pads were resolved above; the surfaces are names only the model can resolve, and
  // the system says which list a name came from.
  try {
    system_ = std::make_unique<adhesion::AdhesionSystem>(m, sys);
  } catch (const adhesion::AdhesionSetupError& e) {
    throw ScenarioError(scenario, "adhesion." + e.key(), e.what());
  }
  // Weld softness on this run's model copy (the compiled model may come from another value).
  for (const adhesion::PadSpec& spec : sys.pads) {
    const int eq = mj_name2id(m, mjOBJ_EQUALITY, adhesion::WeldName(spec.body).c_str());
    if (eq < 0) continue;
    m->eq_solref[eq * mjNREF] = params.weld_solref[0];
    m->eq_solref[eq * mjNREF + 1] = params.weld_solref[1];
  }
  const auto& legs = world.robot().legs;
  pad_of_leg_.assign(legs.size(), -1);
  leg_of_pad_.assign(system_->size(), -1);
  for (size_t leg = 0; leg < legs.size(); ++leg) {
    const int pad = system_->FindPad(legs[leg].pad_body);
    pad_of_leg_[leg] = pad;
    if (pad >= 0) leg_of_pad_[pad] = static_cast<int>(leg);
  }
  fail_at_s_.assign(system_->size(), std::numeric_limits<double>::infinity());
  attach_count_.assign(system_->size(), 0);
  utilisation_.assign(system_->size(), 0.0);
  peak_bond_.assign(system_->size(), -1);
  peak_utilisation_.assign(system_->size(), 0.0);
  peeling_.assign(system_->size(), 0);
  stance_peak_.assign(system_->size(), 0.0);
  peel_peak_.assign(system_->size(), 0.0);
  stance_histogram_.assign(static_cast<size_t>(system_->size()) * (kStanceBins + 1), 0);
}

void AdhesionEffect::Reset(World& world, RunContext& ctx) {
  legs_ = ctx.legs;
  events_ = ctx.events;
  std::fill(fail_at_s_.begin(), fail_at_s_.end(), std::numeric_limits<double>::infinity());
  std::fill(attach_count_.begin(), attach_count_.end(), 0);
  system_->Reset(world.model(), world.data(), this);
  std::fill(peak_utilisation_.begin(), peak_utilisation_.end(), 0.0);
  std::fill(peeling_.begin(), peeling_.end(), 0);
  std::fill(stance_peak_.begin(), stance_peak_.end(), 0.0);
  std::fill(peel_peak_.begin(), peel_peak_.end(), 0.0);
  std::fill(stance_histogram_.begin(), stance_histogram_.end(), 0);
  UpdateUtilisation();
  FillSignals();
}

void AdhesionEffect::BeforeStep(World& world, RunContext&) {
  system_->BeforeStep(world.model(), world.data(), this);
  FillSignals();
}

void AdhesionEffect::AfterStep(World& world, RunContext&) {
  mjModel* m = world.model();
  mjData* d = world.data();
  system_->AfterStep(m, d, this);
  for (int i = 0; i < system_->size(); ++i) {
    if (d->time >= fail_at_s_[i]) {
      fail_at_s_[i] = std::numeric_limits<double>::infinity();
      system_->pad(i).Fail(m, d, d->time, this);
    }
  }
  UpdateUtilisation();
  FillSignals();
}

void AdhesionEffect::DrawDisturbances(int pad, double time_s) {
  adhesion::StickyPad& p = system_->pad(pad);
  const long n = attach_count_[pad]++;
  fail_at_s_[pad] = std::numeric_limits<double>::infinity();
  if (params_.pad_failure_probability > 0.0 &&
      UnitDraw(seed_, kStreamPadFailure, pad, 2 * n) < params_.pad_failure_probability) {
    fail_at_s_[pad] =
        time_s + params_.pad_failure_window_s * UnitDraw(seed_, kStreamPadFailure, pad, 2 * n + 1);
  }
  if (weak_patches_) {
    const adhesion::PadFrame face = adhesion::FaceFrame(world_->data(), p.geometry());
    p.SetStrengthScale(PatchStrength(*weak_patches_, seed_, face.pos.x(), face.pos.y()));
  }
}

// Each attached pad's peak utilisation (BondGrid::PeakUtilisation), once per step after the bonds
// have seen the step's load; a pad that let go reads 0. An attached pad's step also counts as
// stance or peel (the split of summary.json).
void AdhesionEffect::UpdateUtilisation() {
  for (int i = 0; i < system_->size(); ++i) {
    const adhesion::StickyPad& p = system_->pad(i);
    double u = 0.0;
    const int last_peak = peak_bond_[i];  // the peak rarely moves: the scan's hint
    peak_bond_[i] = -1;
    const bool bonds = p.attached() && p.params().model == adhesion::AdhesionModel::kBonds;
    if (bonds) {
      u = std::min(p.params().law != adhesion::PadLaw::kVonMises
                       ? p.frictional_utilisation()
                       : p.grid().PeakUtilisation(&peak_bond_[i], last_peak),
                   kUtilisationCap);
      if (!(u >= 0.0)) u = kUtilisationCap;  // NaN: no field the bonds could carry
    }
    utilisation_[i] = u;
    peak_utilisation_[i] = std::max(peak_utilisation_[i], u);
    if (!bonds) continue;
    if (peeling_[i]) {
      peel_peak_[i] = std::max(peel_peak_[i], u);
    } else {
      stance_peak_[i] = std::max(stance_peak_[i], u);
      const int bin = std::min(static_cast<int>(u * kStanceBins), kStanceBins);
      ++stance_histogram_[static_cast<size_t>(i) * (kStanceBins + 1) + bin];
    }
  }
}

double AdhesionEffect::stance_p99_utilisation(int pad) const {
  const long* h = stance_histogram_.data() + static_cast<size_t>(pad) * (kStanceBins + 1);
  long total = 0;
  for (int b = 0; b <= kStanceBins; ++b) total += h[b];
  if (total == 0) return 0.0;
  // Nearest rank: the smallest bin holding the ceil(0.99 n)-th smallest sample.
  const long rank = (99 * total + 99) / 100;
  long seen = 0;
  int b = 0;
  for (; b < kStanceBins; ++b) {
    seen += h[b];
    if (seen >= rank) break;
  }
  // The bin's upper edge; the last bin (≥ 1) ends at the peak.
  if (b == kStanceBins) return stance_peak_[pad];
  return std::min(static_cast<double>(b + 1) / kStanceBins, stance_peak_[pad]);
}

bool AdhesionEffect::RequestRelease(int pad) {
  const bool released = system_->Release(pad, world_->model(), world_->data(), this);
  if (released) {
    utilisation_[pad] = 0.0;
    FillSignals();
  }
  return released;
}

bool AdhesionEffect::RequestReleaseLeg(int leg) {
  const int pad = pad_of_leg(leg);
  return pad >= 0 && RequestRelease(pad);
}

void AdhesionEffect::FillSignals() {
  if (legs_ == nullptr) return;
  for (int i = 0; i < system_->size(); ++i) {
    const int leg = leg_of_pad_[i];
    if (leg < 0 || leg >= static_cast<int>(legs_->size())) continue;
    const adhesion::StickyPad& p = system_->pad(i);
    LegSignals& s = (*legs_)[leg];
    s.touching = p.touching();
    s.attached = p.attached();
    s.bonded_fraction = p.bonded_fraction();
    s.touched_fraction = p.touched_fraction();
    s.bondable_fraction = p.bondable_fraction();
    s.refusal = RefusalOf(p.refused_cause());
    s.normal_load_n = p.load().fn_n;
    // A welded pad does not collide: its compression is in the weld.
    const bool welded = p.attached() && p.params().model == adhesion::AdhesionModel::kBonds;
    s.preload_n = welded ? std::max(0.0, -p.load().fn_n) : p.sense().preload_n;
    s.load_n = welded ? std::sqrt(p.load().fn_n * p.load().fn_n + p.load().fx_n * p.load().fx_n +
                                  p.load().fy_n * p.load().fy_n)
                      : 0.0;
    // Latched until a controller reads it (the reflex effect clears it): a loss in this
    // step's AfterStep must survive the next BeforeStep's refresh.
    s.bonds_lost = s.bonds_lost || p.bonds_lost_this_step();
    s.utilisation = p.attached() ? utilisation_[i] : 0.0;
  }
}

void AdhesionEffect::OnPadEvent(int pad, const adhesion::PadEvent& e) {
  if (e.kind == adhesion::PadEventKind::kAttach) DrawDisturbances(pad, e.time_s);
  if (events_ == nullptr) return;
  Event row;
  row.time_s = e.time_s;
  row.pad = pad;
  row.kind = adhesion::PadEventName(e.kind);
  row.cause = adhesion::PadCauseName(e.cause);
  row.cause_value = e.cause_value;
  row.has_cause_value = e.has_cause_value;
  row.surface_geom = e.surface_geom;
  row.bonded_fraction = e.bonded_fraction;
  row.load = {e.load.fn_n, e.load.fx_n, e.load.fy_n, e.load.mx_nm, e.load.my_nm};
  events_->Add(row);
}

void AdhesionEffect::TrajectoryColumns(std::vector<std::string>* names) const {
  for (int i = 0; i < system_->size(); ++i)
    names->push_back(system_->pad_name(i) + "_bonded_fraction");
  for (int i = 0; i < system_->size(); ++i)
    names->push_back(system_->pad_name(i) + "_utilisation");
  // The load the bond layer carries (PadLoad, pad frame; 0 when not attached).
  static constexpr const char* kLoad[5] = {"_fn_n", "_fx_n", "_fy_n", "_mx_nm", "_my_nm"};
  for (int i = 0; i < system_->size(); ++i)
    for (const char* c : kLoad) names->push_back(system_->pad_name(i) + c);
}

void AdhesionEffect::TrajectoryValues(const World&, double* out) const {
  const int n = system_->size();
  for (int i = 0; i < n; ++i) out[i] = system_->pad(i).bonded_fraction();
  for (int i = 0; i < n; ++i) out[n + i] = system_->pad(i).attached() ? utilisation_[i] : 0.0;
  for (int i = 0; i < n; ++i) {
    const adhesion::StickyPad& p = system_->pad(i);
    const adhesion::PadLoad l = p.attached() ? p.load() : adhesion::PadLoad{};
    double* row = out + 2 * n + 5 * i;
    row[0] = l.fn_n, row[1] = l.fx_n, row[2] = l.fy_n, row[3] = l.mx_nm, row[4] = l.my_nm;
  }
}

void AdhesionEffect::Summarise(const World&, nlohmann::json* summary) const {
  nlohmann::json pads = nlohmann::json::object();
  for (int i = 0; i < system_->size(); ++i) {
    const adhesion::StickyPad& p = system_->pad(i);
    const adhesion::PadCounts& c = p.counts();
    nlohmann::json j;
    j["touchdown"] = c.touchdown;
    j["attach"] = c.attach;
    j["attach_rejected"] = c.attach_rejected;
    using adhesion::PadCause, adhesion::PadCauseName;
    j["attach_rejected_by"] = {
        {PadCauseName(PadCause::kApproachSpeed), c.rejected_approach_speed},
        {PadCauseName(PadCause::kApproachAngle), c.rejected_approach_angle},
        {PadCauseName(PadCause::kContacts), c.rejected_contacts},
        {PadCauseName(PadCause::kPreload), c.rejected_preload},
        {PadCauseName(PadCause::kContactShare), c.rejected_contact_share}};
    j["bonds_lost_steps"] = c.bonds_lost;
    j["detach_peel"] = c.detach_peel;
    j["detach_overload"] = c.detach_overload;
    j["detach_released"] = c.detach_released;
    j["detach_contact_lost"] = c.detach_contact_lost;
    j["detach_failure"] = c.detach_failure;
    j["attached_at_end"] = p.attached();
    j["bonded_fraction_at_end"] = p.bonded_fraction();
    j["peak_utilisation"] = peak_utilisation_[i];
    j["utilisation_stance_peak"] = stance_peak_[i];
    j["utilisation_stance_p99"] = stance_p99_utilisation(i);
    j["utilisation_peel_peak"] = peel_peak_[i];
    pads[system_->pad_name(i)] = j;
  }
  (*summary)["adhesion"] = {{"model", params_.model}, {"pads", pads}};
}

AdhesionEffect* FindAdhesion(const std::vector<std::unique_ptr<Effect>>& effects) {
  for (const auto& e : effects) {
    if (auto* a = dynamic_cast<AdhesionEffect*>(e.get())) return a;
  }
  return nullptr;
}

}  // namespace climbsim::sim
