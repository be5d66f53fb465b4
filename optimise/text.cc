#include "optimise/text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace climbsim::optimise {

void Appendf(std::string* out, const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::max(0, std::vsnprintf(nullptr, 0, format, args));
  va_end(args);
  std::string text(static_cast<size_t>(n) + 1, '\0');
  std::vsnprintf(text.data(), text.size(), format, again);
  va_end(again);
  text.resize(static_cast<size_t>(n));
  *out += text;
}

}  // namespace climbsim::optimise
