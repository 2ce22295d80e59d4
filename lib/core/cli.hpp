#pragma once
// Command-line parsing shared by every gf-* program, so that an option keeps one
// spelling and one meaning everywhere (docs/file-format.md, Names and units).
// Every error is a UsageError naming the option; --help lists every option with
// its default.
#include <optional>
#include <string>
#include <vector>

namespace granflow {

class CommandLine {
 public:
  CommandLine(std::string program, std::string synopsis, std::string description);

  // An option taking a value; an empty default means "no default" (see has()).
  void option(const std::string& name, char short_name, const std::string& value_name, const std::string& help,
              const std::string& default_value = "");
  void flag(const std::string& name, char short_name, const std::string& help);
  // Accept positional arguments (e.g. input files); min_count of them required.
  void positionals(const std::string& value_name, const std::string& help, std::size_t min_count);

  // Returns false when --help or --version was printed (the tool should exit 0).
  bool parse(int argc, const char* const* argv);

  bool has(const std::string& name) const;    // given on the command line or defaulted
  bool given(const std::string& name) const;  // given on the command line
  bool flag_set(const std::string& name) const;
  std::string text(const std::string& name) const;
  double real(const std::string& name) const;        // finite double, else UsageError
  long long integer(const std::string& name) const;  // whole number, else UsageError
  const std::vector<std::string>& positional() const { return positional_; }

  std::string help() const;
  const std::string& program() const { return program_; }
  // The exact invocation, shell-quoted, for provenance.
  const std::string& command_line() const { return command_line_; }
  // Every option value (given or default), for the /parameters group.
  std::vector<std::pair<std::string, std::string>> values() const;

 private:
  struct Spec {
    std::string name;
    char short_name;
    std::string value_name;
    std::string help;
    std::string default_value;
    bool is_flag;
    std::optional<std::string> value;
  };
  const Spec* find(const std::string& name) const;
  Spec* find_long(const std::string& name);
  Spec* find_short(char c);

  std::string program_, synopsis_, description_;
  std::vector<Spec> specs_;
  std::string positional_name_, positional_help_;
  std::size_t positional_min_ = 0;
  bool positional_allowed_ = false;
  std::vector<std::string> positional_;
  std::string command_line_;
};

// Validation helpers: throw UsageError("--name: must be ...").
void require_in_range(const std::string& option, double value, double lo, double hi, bool lo_open, bool hi_open);
void require_positive(const std::string& option, double value);

}  // namespace granflow
