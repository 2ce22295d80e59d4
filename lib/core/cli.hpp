#pragma once
// Command-line parsing shared by every gf-* program, so that an option keeps one
// spelling and one meaning everywhere (docs/file-format.md, Names and units).
// Every error is a UsageError naming the option; --help lists every option with
// its default. Each option has one declared kind, so that a value is read, and stored
// in /parameters, the same way whatever was typed ("2" for a real is the real 2.0).
#include <optional>
#include <string>
#include <vector>

namespace granflow {

enum class OptionKind { flag, real, integer, text };

class CommandLine {
 public:
  CommandLine(std::string program, std::string synopsis, std::string description);

  // Options taking a value of one kind, read with real(), integer() or text(); an empty
  // default means "no default" (see has()).
  void real_option(const std::string& name, char short_name, const std::string& value_name, const std::string& help,
                   const std::string& default_value = "");
  void integer_option(const std::string& name, char short_name, const std::string& value_name, const std::string& help,
                      const std::string& default_value = "");
  void text_option(const std::string& name, char short_name, const std::string& value_name, const std::string& help,
                   const std::string& default_value = "");
  void flag(const std::string& name, char short_name, const std::string& help);

  // Options that cannot apply to a run, checked by parse() on what the user typed (a
  // default never conflicts). conflicts: `option` has no effect when `other` is given, so
  // giving both is refused, and option is left out of values() when other is given.
  // needs: `option` has an effect only when `other` is given, so giving it alone is
  // refused, and it is left out of values() without other.
  void conflicts(const std::string& option, const std::string& other);
  void needs(const std::string& option, const std::string& other);
  // A run-time verdict of the program (e.g. from another option's value): `name` does not
  // apply to this run. Refused when given, naming `reason` (e.g. "--rate 1"); otherwise
  // left out of values().
  void not_applicable(const std::string& name, const std::string& reason);
  // Accept positional arguments (e.g. input files); min_count of them required.
  void positionals(const std::string& value_name, const std::string& help, std::size_t min_count);

  // Returns false when --help or --version was printed (the tool should exit 0).
  bool parse(int argc, const char* const* argv);

  bool has(const std::string& name) const;    // given on the command line or defaulted
  bool given(const std::string& name) const;  // given on the command line
  bool flag_set(const std::string& name) const;
  std::string text(const std::string& name) const;
  // A text option holding one comma-separated list of files (FILE,FILE,...): its items, none
  // when the option was not given or holds no file ("" or only commas) and has no default. UsageError naming the
  // option when it was given more than once (a later list would silently replace the
  // earlier one), for an empty item (",," or a comma at either end), and for a file whose
  // name contains a comma (the separator has no escape: link or rename such a file).
  std::vector<std::string> text_list(const std::string& name) const;
  // The value of a real or integer option: a finite double, or a whole number (1e4 is
  // accepted), else UsageError naming the option. Reading an option of another declared
  // kind is a programming error (std::logic_error).
  double real(const std::string& name) const;
  long long integer(const std::string& name) const;
  OptionKind kind(const std::string& name) const;
  const std::vector<std::string>& positional() const { return positional_; }

  // Every line at most kHelpWidth code points: help texts are wrapped with a hanging
  // indent, keeping their explicit line breaks.
  static constexpr std::size_t kHelpWidth = 100;
  // Columns of an option line ("  -o, --output <FILE>", "      --threads <N>") and of its
  // description beneath it, set apart from the long-only options' names.
  static constexpr std::size_t kHelpOptionIndent = 2, kHelpDescriptionIndent = 10;
  // The last line of every program's --help.
  static constexpr const char* kExitStatusLine =
      "Exit status: 0 success, 1 runtime failure or interruption, 2 bad usage or bad input.";
  std::string help() const;
  const std::string& program() const { return program_; }
  // The exact invocation, shell-quoted, for provenance.
  const std::string& command_line() const { return command_line_; }
  // Every option value (given or default) that applies to the run (see conflicts(),
  // needs(), not_applicable()), for the /parameters group and the resume signature.
  std::vector<std::pair<std::string, std::string>> values() const;

 private:
  struct Spec {
    std::string name;
    char short_name;
    std::string value_name;
    std::string help;
    std::string default_value;
    OptionKind kind;
    std::optional<std::string> value;
    int times_given = 0;
    bool applies = true;
  };
  void declare(const std::string& name, char short_name, const std::string& value_name, const std::string& help,
               const std::string& default_value, OptionKind kind);
  const Spec* find_of_kind(const std::string& name, OptionKind kind) const;
  void check_relations();
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
  std::vector<std::pair<std::string, std::string>> conflicts_, needs_;
};

// Validation helpers: throw UsageError("--name: must be ...").
void require_in_range(const std::string& option, double value, double lo, double hi, bool lo_open, bool hi_open);
void require_positive(const std::string& option, double value);

}  // namespace granflow
