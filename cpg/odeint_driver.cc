#include "cpg/internal/odeint_driver.h"

#include "cpg/cpg.h"
#include "cpg/internal/checks.h"

namespace climbsim::cpg::internal {

OdeintDriver::OdeintDriver(const StepperParams& params, std::size_t state_size)
    : method_(params.type == Stepper::kEuler ? Method::kEuler
              : params.type == Stepper::kRk4 ? Method::kRk4
                                             : Method::kDopri5),
      x_(state_size, 0.0),
      dopri5_(Dopri5::error_checker_type(params.abs_tol, params.rel_tol, 1.0, 1.0)) {
  // Size every stepper's scratch now, so that no Step ever resizes (allocates).
  euler_.adjust_size(x_);
  rk4_.adjust_size(x_);
  dopri5_.adjust_size(x_);
  // The FSAL controller's adjust_size (Boost 1.74) sizes its own buffers but not those of the
  // Dopri5 stepper inside it: six vectors that the first step would otherwise allocate.
  dopri5_.stepper().adjust_size(x_);
}

void OdeintDriver::Restart() {
  dopri5_.reset();
  dt_hint_s_ = 0.0;
  accepted_steps_ = 0;
  rejected_steps_ = 0;
}

}  // namespace climbsim::cpg::internal
