// Keys are read from and written into the resolved scenario (every key, defaults filled in,
// sim::ScenarioToYaml), dotted as optimise parameters and --set are (scenario/dotted_key.h);
// a write parses the whole tree again, so a value is refused with the file's InputError text.
#include "python/scenario_keys.h"

#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "scenario/dotted_key.h"

namespace py = pybind11;

namespace climbsim::python {
namespace {

// A scalar as the loader reads it: an integer, a number, true/false, null, else text.
py::object ScalarToPy(const std::string& text) {
  if (text == "true") return py::bool_(true);
  if (text == "false") return py::bool_(false);
  if (text == "~" || text == "null") return py::none();
  if (!text.empty()) {
    char* end = nullptr;
    errno = 0;
    const long long i = std::strtoll(text.c_str(), &end, 10);
    if (*end == '\0' && errno == 0) return py::int_(i);
    const double d = std::strtod(text.c_str(), &end);
    if (*end == '\0') return py::float_(d);
    if (text == ".nan" || text == ".inf" || text == "-.inf") {
      return py::float_(text == ".nan" ? NAN : (text[0] == '-' ? -INFINITY : INFINITY));
    }
  }
  return py::str(text);
}

py::object YamlToPy(const YAML::Node& n) {
  if (n.IsMap()) {
    py::dict d;
    for (const auto& kv : n) d[py::str(kv.first.Scalar())] = YamlToPy(kv.second);
    return d;
  }
  if (n.IsSequence()) {
    py::list l;
    for (const auto& item : n) l.append(YamlToPy(item));
    return l;
  }
  if (!n.IsDefined() || n.IsNull()) return py::none();
  return ScalarToPy(n.Scalar());
}

// A Python value as the file would give it; a double as the resolved scenario writes it (bit
// for bit), NaN and infinities as YAML's, which the loader then refuses by name.
YAML::Node PyToYaml(const py::handle& v) {
  const py::module_ np = py::module_::import("numpy");
  if (v.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (py::isinstance<py::bool_>(v) || py::isinstance(v, np.attr("bool_"))) {
    return YAML::Node(v.cast<bool>() ? "true" : "false");
  }
  if (py::isinstance<py::int_>(v) || py::isinstance(v, np.attr("integer"))) {
    return YAML::Node(std::to_string(v.cast<long long>()));
  }
  if (py::isinstance<py::float_>(v) || py::isinstance(v, np.attr("floating"))) {
    const double d = v.cast<double>();
    if (std::isnan(d)) return YAML::Node(".nan");
    if (std::isinf(d)) return YAML::Node(d > 0 ? ".inf" : "-.inf");
    return YAML::Node(sim::ExactNumber(d));
  }
  if (py::isinstance<py::str>(v)) return YAML::Node(v.cast<std::string>());
  if (py::isinstance<py::dict>(v)) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& kv : v.cast<py::dict>()) map[py::str(kv.first).cast<std::string>()] = PyToYaml(kv.second);
    return map;
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v) ||
      py::isinstance(v, np.attr("ndarray"))) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& item : v) seq.push_back(PyToYaml(item));
    return seq;
  }
  throw py::type_error("a scenario value is a number, bool, str, None, list or dict, not " +
                       py::str(v.get_type()).cast<std::string>());
}

// An InputError at `key` of the scenario, as the loader gives one for a value from outside
// the file (no line).
InputError KeyError(const sim::Scenario& s, const std::string& key, const std::string& what) {
  return InputError(s.source_file, 0, 0, key, what);
}

YAML::Node Get(const sim::Scenario& s, const std::string& key) {
  try {
    return sim::GetDottedKeyNode(sim::ScenarioToYaml(s), key);
  } catch (const std::invalid_argument& e) {
    throw py::key_error(key + ": " + e.what());
  }
}

// The tree with the change, parsed as a file is; every other key keeps the place it was
// read at.
void Replace(sim::Scenario* s, YAML::Node root, const std::string& key) {
  sim::Scenario next = sim::ParseScenario(root, s->source_file);
  sim::SourceMap places = s->places;
  places[key] = sim::SourcePlace{};
  next.places = std::move(places);
  *s = std::move(next);
}

void Set(sim::Scenario* s, const std::string& key, const py::handle& value) {
  YAML::Node root = sim::ScenarioToYaml(*s);
  try {
    sim::SetDottedKeyNode(root, key, PyToYaml(value));
  } catch (const std::invalid_argument& e) {
    throw KeyError(*s, key, e.what());
  }
  Replace(s, root, key);
}

// Removes a key: a value goes back to its default, an optional block (reflex, cpg) goes.
void Delete(sim::Scenario* s, const std::string& key) {
  Get(*s, key);  // KeyError when absent
  YAML::Node root = sim::ScenarioToYaml(*s);
  try {
    sim::RemoveDottedKey(root, key);
  } catch (const std::invalid_argument& e) {
    throw KeyError(*s, key, e.what());
  }
  Replace(s, root, key);
}

}  // namespace

void BindScenarioKeys(py::class_<sim::Scenario>& cls) {
  cls.def("__getitem__", [](const sim::Scenario& s, const std::string& key) {
       return YamlToPy(Get(s, key));
     }, py::arg("key"), "The value of a dotted key (cpg.frequency_hz, cpg.stride_rad[0]).")
      .def("__setitem__", &Set, py::arg("key"), py::arg("value"),
           "Sets a dotted key, checked as the file's (climbsim.InputError, the file's text); a "
           "missing map is made, a list item must exist.")
      .def("__delitem__", &Delete, py::arg("key"),
           "Removes a key: a value returns to its default, a block (reflex, cpg) is dropped.")
      .def("__contains__", [](const sim::Scenario& s, const std::string& key) {
        try {
          sim::GetDottedKeyNode(sim::ScenarioToYaml(s), key);
          return true;
        } catch (const std::invalid_argument&) {
          return false;
        }
      })
      .def("get", [](const sim::Scenario& s, const std::string& key, py::object default_value) {
        try {
          return YamlToPy(sim::GetDottedKeyNode(sim::ScenarioToYaml(s), key));
        } catch (const std::invalid_argument&) {
          return default_value;
        }
      }, py::arg("key"), py::arg("default") = py::none())
      .def("keys", [](const sim::Scenario& s) { return sim::DottedKeys(sim::ScenarioToYaml(s)); },
           "Every key that holds a value, dotted, list items as [i] (the resolved scenario).")
      .def("to_dict", [](const sim::Scenario& s) { return YamlToPy(sim::ScenarioToYaml(s)); },
           "The resolved scenario (every key, defaults filled in) as a dict; "
           "scenario_from_dict(s.to_dict()) is the same scenario.");
}

}  // namespace climbsim::python
