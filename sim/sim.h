// climbsim's simulation layer: scenario files, world assembly, the effect pipeline, the step
// loop and recorders. The public header of sim/; tools/ and tests include only this.
//
//   climbsim::sim::Scenario s = climbsim::sim::LoadScenario("examples/gecko_floor.yaml");
//   auto model = climbsim::sim::CompileScenario(s);      // once; read-only afterwards
//   climbsim::sim::Simulation run(s, *model);             // owns its model copy and data
//   climbsim::sim::RunResult r = run.Run();
//   climbsim::sim::WriteRunDirectory("runs/gecko_floor", run);
#ifndef CLIMBSIM_SIM_SIM_H_
#define CLIMBSIM_SIM_SIM_H_

#include "sim/controller.h"
#include "common/common.h"
#include "common/run_folder.h"
#include "scenario/scenario.h"
#include "sim/simulation.h"
#include "sim/surface.h"
#include "sim/world.h"

#ifdef CLIMBSIM_PACKAGE_MJCF_DIR
// Set by climbsimConfig.cmake for programs built against an installed climbsim: the bundled
// models are found in the package (PREFIX/share/climbsim/mjcf) before the program starts.
namespace climbsim::sim::detail {
inline const bool kPackageMjcfDirRegistered =
    (SetPackageMjcfDir(CLIMBSIM_PACKAGE_MJCF_DIR), true);
}  // namespace climbsim::sim::detail
#endif

#endif  // CLIMBSIM_SIM_SIM_H_
