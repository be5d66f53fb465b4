// printf onto the end of a string: the terminal texts the library hands the CLI (and a
// binding) instead of printing them itself.
#ifndef CLIMBSIM_OPTIMISE_TEXT_H_
#define CLIMBSIM_OPTIMISE_TEXT_H_

#include <string>

namespace climbsim::optimise {

__attribute__((format(printf, 2, 3))) void Appendf(std::string* out, const char* format, ...);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_TEXT_H_
