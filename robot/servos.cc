#include "robot/servos.h"

#include <array>

namespace climbsim::sim {

namespace {

// Catalogue figures as we know them (manufacturers' data sheets at the stated voltage; the
// sandbox had no network to re-read them: check before quoting). kp, damping and armature
// follow the rules of servos.h; the three servos of the stock robots keep the values their
// models were built with (hs35hd, hs65hb, hk5320).
constexpr std::array<ServoModel, 7> kCatalogue{{
    {"hk5320", "HobbyKing HK-5320 ultra-micro", 3.7, 0.0017, 0.0078, 17.45, 150, 0.0039, 0.15,
     0.00045, 1e-6, {0.0073, 0.0033, 0.0073}},
    {"hs35hd", "Hitec HS-35HD sub-micro", 4.8, 0.0045, 0.078, 10.5, 300, 0.039, 1.5, 0.0075, 3e-5,
     {0.008, 0.004, 0.008}},
    {"hs40", "Hitec HS-40 sub-micro", 4.8, 0.0048, 0.0588, 11.6, 300, 0.0294, 1.1, 0.0051, 3e-5,
     {0.0099, 0.0042, 0.0095}},
    {"hs55", "Hitec HS-55 sub-micro", 4.8, 0.008, 0.108, 6.16, 300, 0.054, 2.1, 0.0175, 1e-4,
     {0.0112, 0.0058, 0.0121}},
    {"sg90", "TowerPro SG90 micro", 4.8, 0.009, 0.176, 10.5, 280, 0.088, 3.4, 0.0168, 1e-4,
     {0.0116, 0.0062, 0.0114}},
    {"hs65hb", "Hitec HS-65HB micro", 4.8, 0.0119, 0.176, 7.48, 280, 0.088, 3.4, 0.0235, 2.5e-4,
     {0.0118, 0.0058, 0.012}},
    {"hs82mg", "Hitec HS-82MG micro", 4.8, 0.019, 0.275, 8.73, 280, 0.1375, 5.3, 0.0315, 3e-4,
     {0.0149, 0.0059, 0.0148}},
}};

}  // namespace

std::span<const ServoModel> ServoCatalogue() { return kCatalogue; }

const ServoModel* FindServo(std::string_view name) {
  for (const ServoModel& s : kCatalogue)
    if (s.name == name) return &s;
  return nullptr;
}

std::string ServoNames() {
  std::string names;
  for (const ServoModel& s : kCatalogue) names += (names.empty() ? "" : ", ") + std::string(s.name);
  return names;
}

}  // namespace climbsim::sim
