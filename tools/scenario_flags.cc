// --set KEY=VALUE: the one option every verb that reads scenario files shares.
#include <string>
#include <vector>

#include "scenario/dotted_key.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddSetOption(CLI::App* cmd) {
  cmd->add_option_function<std::vector<std::string>>(
         "--set",
         [](const std::vector<std::string>& texts) {
           std::vector<sim::KeyOverride> keys;
           for (const std::string& t : texts) keys.push_back(sim::ParseKeyOverride(t));
           sim::SetCommandLineKeys(std::move(keys));
         },
         "KEY=VALUE (repeatable): replace a key of the scenario file, dotted as optimise "
         "parameters are (cpg.frequency_hz=0.8, cpg.stride_rad[0]=0.3, "
         "scene.incline_deg=60), checked as the file's own")
      ->allow_extra_args(false)
      ->type_name("KEY=VALUE");
}

}  // namespace climbsim::tools
