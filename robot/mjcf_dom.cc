#include "robot/mjcf_dom.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace climbsim::sim {

std::string MjcfNumber(double v) {
  if (v == 0.0) return "0";  // also -0
  char rounded[32];
  std::snprintf(rounded, sizeof rounded, "%.12g", v);
  const double r = std::strtod(rounded, nullptr);
  char out[32];
  const auto res = std::to_chars(out, out + sizeof out, r);
  return std::string(out, res.ptr);
}

std::string MjcfNumbers(std::initializer_list<double> values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : " ") + MjcfNumber(v);
  return s;
}

namespace {
void SetAll(tinyxml2::XMLElement* e, MjcfAttributes attributes) {
  for (const auto& [key, value] : attributes) e->SetAttribute(key, value.c_str());
}
}  // namespace

tinyxml2::XMLElement* AddElement(tinyxml2::XMLElement* parent, const char* name,
                                 MjcfAttributes attributes) {
  tinyxml2::XMLElement* e = parent->InsertNewChildElement(name);
  SetAll(e, attributes);
  return e;
}

tinyxml2::XMLElement* InsertElementAfter(tinyxml2::XMLElement* sibling, const char* name,
                                         MjcfAttributes attributes) {
  tinyxml2::XMLElement* e = sibling->GetDocument()->NewElement(name);
  sibling->Parent()->InsertAfterChild(sibling, e);
  SetAll(e, attributes);
  return e;
}

tinyxml2::XMLElement* FindNamed(tinyxml2::XMLElement* root, const char* tag,
                                const std::string& name) {
  for (tinyxml2::XMLElement* c = root->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* n = c->Attribute("name");
    if (std::strcmp(c->Name(), tag) == 0 && n && name == n) return c;
    if (tinyxml2::XMLElement* found = FindNamed(c, tag, name)) return found;
  }
  return nullptr;
}

}  // namespace climbsim::sim
