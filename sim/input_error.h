// climbsim::InputError: the one exception for bad input (scenario files, command-line
// values, run directories). Library code throws it; only tools/ catches it, prints what()
// and exits with code 2. The message always starts with the place: "file:line:col: key: ...".
#ifndef CLIMBSIM_SIM_INPUT_ERROR_H_
#define CLIMBSIM_SIM_INPUT_ERROR_H_

#include <stdexcept>
#include <string>

namespace climbsim {

class InputError : public std::runtime_error {
 public:
  // line and column are 1-based; 0 means "not known" and is left out of the message.
  InputError(const std::string& file, int line, int column, const std::string& key,
             const std::string& message)
      : std::runtime_error(Format(file, line, column, key, message)),
        file_(file),
        line_(line),
        column_(column),
        key_(key),
        message_(message) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }  // without the place

 private:
  static std::string Format(const std::string& file, int line, int column,
                            const std::string& key, const std::string& message) {
    std::string s = file;
    if (line > 0) s.append(":").append(std::to_string(line));
    if (line > 0 && column > 0) s.append(":").append(std::to_string(column));
    s.append(": ");
    if (!key.empty()) s.append(key).append(": ");
    s.append(message);
    return s;
  }

  std::string file_;
  int line_;
  int column_;
  std::string key_;
  std::string message_;
};

}  // namespace climbsim

#endif  // CLIMBSIM_SIM_INPUT_ERROR_H_
