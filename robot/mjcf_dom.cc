#include "robot/mjcf_dom.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace climbsim::sim {

namespace {

// "2e-04" -> "2e-4", "1e+06" -> "1e6": the exponent without sign or leading zeros.
std::string TidyExponent(std::string s) {
  const size_t e = s.find('e');
  if (e == std::string::npos) return s;
  size_t digits = e + 1;
  if (s[digits] == '+') s.erase(digits, 1);
  if (s[digits] == '-') ++digits;
  while (digits + 1 < s.size() && s[digits] == '0') s.erase(digits, 1);
  return s;
}

}  // namespace

std::string MjcfNumber(double v) {
  if (v == 0.0) return "0";  // also -0
  char rounded[32];
  std::snprintf(rounded, sizeof rounded, "%.12g", v);
  const double r = std::strtod(rounded, nullptr);
  char out[400];
  auto res = std::to_chars(out, out + sizeof out, r, std::chars_format::scientific);
  const std::string exponent = TidyExponent(std::string(out, res.ptr));
  res = std::to_chars(out, out + sizeof out, r, std::chars_format::fixed);
  const std::string plain(out, res.ptr);
  return plain.size() <= exponent.size() + 2 ? plain : exponent;
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

// Elements above this node (a child of <mujoco> is at 1).
int Depth(const tinyxml2::XMLNode* node) {
  int depth = 0;
  for (const tinyxml2::XMLNode* p = node->Parent(); p && p->ToElement(); p = p->Parent()) ++depth;
  return depth;
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

void AddComment(tinyxml2::XMLElement* parent, std::initializer_list<std::string> lines) {
  // "<!-- " starts the first line 5 columns after the comment's indentation.
  const std::string indent(2 * (Depth(parent) + 1) + 5, ' ');
  std::string text;
  for (const std::string& line : lines) text += (text.empty() ? " " : "\n" + indent) + line;
  parent->InsertNewComment((text + " ").c_str());
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

namespace {

// tinyxml2's printer with the house's layout (PrintMjcf); it tracks the column it writes at.
class MjcfPrinter : public tinyxml2::XMLPrinter {
 public:
  using tinyxml2::XMLPrinter::Visit;
  using tinyxml2::XMLPrinter::VisitEnter;

  bool VisitEnter(const tinyxml2::XMLElement& e, const tinyxml2::XMLAttribute* a) override {
    BlankLineBefore(e);
    OpenElement(e.Name(), false);
    const size_t start = column_;  // just after "<name": attributes line up one further
    for (; a; a = a->Next()) {
      const size_t width = 4 + std::strlen(a->Name()) + std::strlen(a->Value());
      if (column_ > start && column_ + width + 2 > kColumns) {
        Write("\n");
        Write(std::string(start, ' ').c_str());
      }
      PushAttribute(a->Name(), a->Value());
    }
    return true;
  }
  bool Visit(const tinyxml2::XMLComment& c) override {
    BlankLineBefore(c);
    return tinyxml2::XMLPrinter::Visit(c);
  }

 protected:
  using tinyxml2::XMLPrinter::Write;
  void PrintSpace(int depth) override {
    for (int i = 0; i < depth; ++i) Write("  ");
  }
  void Write(const char* data, size_t size) override {
    tinyxml2::XMLPrinter::Write(data, size);
    for (size_t i = 0; i < size; ++i) column_ = data[i] == '\n' ? 0 : column_ + 1;
  }
  void Putc(char ch) override {
    tinyxml2::XMLPrinter::Putc(ch);
    column_ = ch == '\n' ? 0 : column_ + 1;
  }

 private:
  static constexpr size_t kColumns = 100;
  void BlankLineBefore(const tinyxml2::XMLNode& n) {
    const tinyxml2::XMLElement* parent = n.Parent() ? n.Parent()->ToElement() : nullptr;
    if (!n.PreviousSibling() || !parent) return;
    if (n.ToComment() || std::strcmp(parent->Name(), "mujoco") == 0) Putc('\n');
  }
  size_t column_ = 0;
};

}  // namespace

std::string PrintMjcf(const tinyxml2::XMLDocument& doc) {
  MjcfPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

}  // namespace climbsim::sim
