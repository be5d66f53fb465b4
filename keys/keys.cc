#include "keys/keys.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace climbsim {

std::string ShortNumber(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return std::to_string(static_cast<long long>(v));
  std::ostringstream s;
  s << v;
  return s.str();
}

bool Range::Contains(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::Describe() const {
  const bool has_lo = lo > -1e299, has_hi = hi < 1e299;
  if (has_lo && has_hi) {
    return std::string("must be in ") + (lo_open ? "(" : "[") + ShortNumber(lo) + ", " +
           ShortNumber(hi) + (hi_open ? ")" : "]");
  }
  if (has_lo) return std::string("must be ") + (lo_open ? "> " : ">= ") + ShortNumber(lo);
  if (has_hi) return std::string("must be ") + (hi_open ? "< " : "<= ") + ShortNumber(hi);
  return "must be finite";
}

namespace keys {

std::string FormatValue(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  return buf;
}

std::string KeyPath(std::string_view name, std::string_view key) {
  if (name.empty()) return std::string(key);
  return std::string(name) + "." + std::string(key);
}

void CheckArchive::Number(const Field& f, double v) const {
  if (f.range.Contains(v)) return;
  throw std::invalid_argument(KeyPath(name_, f.key) + " " + f.range.Describe() + ", got " +
                              FormatValue(v));
}

std::string CheckArchive::Join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace keys
}  // namespace climbsim
