// Building MJCF as a tinyxml2 DOM: numbers written so that MuJoCo reads back exactly the double
// the design holds, and elements added with their attributes in one call. The robot generator
// (generate.cc) and the parts it adds (tail.cc, compliance.cc) write every element through these.
#ifndef CLIMBSIM_ROBOT_MJCF_DOM_H_
#define CLIMBSIM_ROBOT_MJCF_DOM_H_

#include <tinyxml2.h>

#include <initializer_list>
#include <string>
#include <utility>

namespace climbsim::sim {

// A number as MJCF text: rounded to 12 significant digits (so a sum such as 0.03759 + 0.017 +
// 0.0005 is written 0.05509, not 0.055090000000000006), then the shortest text that reads back
// as that double, plain ("0.0002") unless that is more than two characters longer than the
// exponent form ("3e-5", "1e-6"). A design's own values (0.01368) come back exactly.
std::string MjcfNumber(double v);
// Several numbers, space-separated ("0 0.05 0").
std::string MjcfNumbers(std::initializer_list<double> values);

using MjcfAttributes = std::initializer_list<std::pair<const char*, std::string>>;

// Appends <name a="..." .../> to parent and returns it.
tinyxml2::XMLElement* AddElement(tinyxml2::XMLElement* parent, const char* name,
                                 MjcfAttributes attributes = {});
// Inserts <name .../> right after `sibling` (same parent) and returns it.
tinyxml2::XMLElement* InsertElementAfter(tinyxml2::XMLElement* sibling, const char* name,
                                         MjcfAttributes attributes = {});
// Appends <!-- line1 ... lineN --> to parent, the lines after the first indented to line up
// under the first where the file prints it.
void AddComment(tinyxml2::XMLElement* parent, std::initializer_list<std::string> lines);
// The first descendant element of root with this tag and name="..."; nullptr when none.
tinyxml2::XMLElement* FindNamed(tinyxml2::XMLElement* root, const char* tag,
                                const std::string& name);

// The document as a file people read: two spaces per level, attributes wrapped at 100 columns
// under the first one, a blank line between the top-level sections and before each comment
// that follows a sibling.
std::string PrintMjcf(const tinyxml2::XMLDocument& doc);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_MJCF_DOM_H_
