// A scenario key as the module that owns it declares it: name, unit, meaning and allowed range
// (Field), and the Checker a struct's cross-key rules raise their errors through. Modules
// write one Serialize per parameter struct,
//   template <class A> void Serialize(A* a) { a->Visit(Field{"gain", "", "...", Range::Positive()}, &gain); }
// beside the fields it names; the default is the field's initialiser. The scenario reader
// (scenario/archive.h) and the module's own checks (keys::Validate) walk the same
// declaration, so a key has one range and one default. No dependency: cpg and reflex use it.
#ifndef CLIMBSIM_KEYS_KEYS_H_
#define CLIMBSIM_KEYS_KEYS_H_

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace climbsim {

// Closed or open interval for numeric checks; the text says it in messages ("> 0").
struct Range {
  double lo = -1e300;
  double hi = 1e300;
  bool lo_open = false;
  bool hi_open = false;

  static Range Any() { return {}; }
  static Range Positive() { return {0.0, 1e300, true, false}; }
  static Range NonNegative() { return {0.0, 1e300, false, false}; }
  static Range Closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range OpenClosed(double lo, double hi) { return {lo, hi, true, false}; }
  bool Contains(double v) const;
  std::string Describe() const;  // "must be > 0", "must be in [0, 1]"
};

// A key: its name, unit (empty when dimensionless or text), meaning, allowed range.
struct Field {
  std::string_view key;
  std::string_view unit;
  std::string_view doc;
  Range range = Range::Any();
  bool required = false;
};

// Where a struct's rules that span several keys report: the scenario reader raises an
// InputError at the key's line; a module's own check raises std::invalid_argument.
class Checker {
 public:
  virtual ~Checker() = default;
  [[noreturn]] virtual void Fail(std::string_view key, const std::string& message) const = 0;
  virtual bool Has(std::string_view key) const = 0;
};

// The shortest integer or %g text of a number, as range messages print it ("0.03", "1").
std::string ShortNumber(double v);

namespace keys {

// A value as module messages print it ("%.9g": -3, 0.1, nan, inf).
std::string FormatValue(double value);
// "<name>.<key>", or "<key>" when name is empty.
std::string KeyPath(std::string_view name, std::string_view key);

// A module's own check of a parameter struct against its declaration: each number in its
// Field's range, each choice among its allowed values, nested structs in turn, then the
// struct's Validate(const Checker&) rules. Errors are std::invalid_argument
// "<name>.<key> must be in [0, 1], got 2" (a rule's: "<name>.<key>: <message>"). A scenario
// never reaches these errors: its reader checked the same declaration at the file's lines.
class CheckArchive {
 public:
  explicit CheckArchive(std::string name) : name_(std::move(name)) {}

  template <class T>
  void Check(const T& value) {
    const_cast<T&>(value).Serialize(this);
    if constexpr (requires(const T& t, const Checker& c) { t.Validate(c); }) {
      value.Validate(RuleChecker(name_));
    }
  }

  void Visit(const Field& f, double* v) { Number(f, *v); }
  void Visit(const Field& f, std::optional<double>* v) {
    if (v->has_value()) Number(f, **v);
  }
  void Visit(const Field& f, int* v) { Number(f, *v); }
  void Visit(const Field& f, std::optional<int>* v) {
    if (v->has_value()) Number(f, **v);
  }
  void Visit(const Field&, bool*) {}
  void Visit(const Field&, std::string*) {}
  void Visit(const Field&, std::vector<std::string>*) {}
  void Choice(const Field& f, std::string* v, const std::vector<std::string>& allowed) {
    for (const auto& a : allowed) {
      if (*v == a) return;
    }
    throw std::invalid_argument(KeyPath(name_, f.key) + " must be one of " + Join(allowed) +
                                ", got '" + *v + "'");
  }
  void Choice(const Field& f, std::optional<std::string>* v,
              const std::vector<std::string>& allowed) {
    if (v->has_value()) Choice(f, &**v, allowed);
  }
  void Visit(const Field& f, std::vector<double>* v, size_t size) {
    if (size != 0 && !v->empty() && v->size() != size) {
      throw std::invalid_argument(KeyPath(name_, f.key) + " must hold " + std::to_string(size) +
                                  " numbers, got " + std::to_string(v->size()));
    }
    for (double x : *v) Number(f, x);
  }
  void Visit(const Field& f, std::vector<std::vector<double>>* v) {
    for (const auto& row : *v) {
      for (double x : row) Number(f, x);
    }
  }
  template <class T>
    requires requires(T t, CheckArchive* a) { t.Serialize(a); }
  void Visit(const Field& f, T* nested) {
    CheckArchive(KeyPath(name_, f.key)).Check(*nested);
  }
  template <class T>
  void Visit(const Field& f, std::optional<T>* nested) {
    if (nested->has_value()) CheckArchive(KeyPath(name_, f.key)).Check(**nested);
  }
  template <class T>
  void Visit(const Field& f, std::vector<T>* list) {
    for (size_t i = 0; i < list->size(); ++i) {
      CheckArchive(KeyPath(name_, f.key) + "[" + std::to_string(i) + "]").Check((*list)[i]);
    }
  }

 private:
  class RuleChecker : public Checker {
   public:
    explicit RuleChecker(std::string_view name) : name_(name) {}
    [[noreturn]] void Fail(std::string_view key, const std::string& message) const override {
      throw std::invalid_argument(KeyPath(name_, key) + ": " + message);
    }
    // Every key of a struct checked in code is present (it has its default).
    bool Has(std::string_view) const override { return true; }

   private:
    std::string_view name_;
  };

  void Number(const Field& f, double v) const;
  static std::string Join(const std::vector<std::string>& names);

  std::string name_;
};

// Checks `params` against its own declaration (CheckArchive); `name` prefixes the keys in
// messages ("reflex.gto"; empty: the bare keys).
template <class T>
void Validate(const T& params, std::string_view name = "") {
  CheckArchive(std::string(name)).Check(params);
}

}  // namespace keys
}  // namespace climbsim

#endif  // CLIMBSIM_KEYS_KEYS_H_
