// Plots are drawn by gnuplot (Debian's gnuplot-nox), run as a child process. Each output
// file is written by gnuplot to a temporary name and renamed when gnuplot succeeds, so a
// plot is either complete or absent. Internal to climbsim's tools; never in a step loop.
#ifndef CLIMBSIM_SIM_GNUPLOT_H_
#define CLIMBSIM_SIM_GNUPLOT_H_

#include <string>
#include <vector>

namespace climbsim::sim {

// Runs `script` with gnuplot. In the script, write `set output OUTPUT(k)` for the k-th file
// of `outputs` (it is replaced by the quoted temporary name). Returns "" on success, else
// what went wrong (gnuplot missing, gnuplot's error output); the outputs are then absent.
std::string RunGnuplot(const std::string& script, const std::vector<std::string>& outputs);

// Escapes a string for a gnuplot double-quoted string.
std::string GnuplotQuote(const std::string& s);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_GNUPLOT_H_
