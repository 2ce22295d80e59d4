#include "core/cli.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"
#include "core/version.hpp"

namespace granflow {
namespace {
std::string shell_quote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_./=:,+@%") ==
                        std::string::npos)
    return s;
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Terminal columns of UTF-8 text: one per code point (continuation bytes do not count).
std::size_t columns(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

// text with its lines broken at spaces to at most `width` columns, the first line indented
// by first_indent and the others by indent; each explicit '\n' starts a new line.
std::string wrap(const std::string& text, std::size_t first_indent, std::size_t indent,
                 std::size_t width = CommandLine::kHelpWidth) {
  std::string out;
  std::size_t margin = first_indent;
  for (std::size_t start = 0;;) {
    const std::size_t end = text.find('\n', start);
    // Words, a word starting with "-" kept behind the word before it, so that no
    // continuation line reads like an option line ("      --name").
    std::vector<std::string> units;
    std::istringstream words(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    for (std::string word; words >> word;) {
      if (!units.empty() && word[0] == '-') units.back() += " " + word;
      else units.push_back(word);
    }
    std::string line;
    for (const auto& unit : units) {
      if (!line.empty() && margin + columns(line) + 1 + columns(unit) > width) {
        out += std::string(margin, ' ') + line + "\n";
        margin = indent;
        line.clear();
      }
      line += (line.empty() ? "" : " ") + unit;
    }
    out += (line.empty() ? std::string() : std::string(margin, ' ') + line) + "\n";
    margin = indent;
    if (end == std::string::npos) return out;
    start = end + 1;
  }
}

std::string format_real(double v) { return format_number(v, 17); }
}  // namespace

CommandLine::CommandLine(std::string program, std::string synopsis, std::string description)
    : program_(std::move(program)), synopsis_(std::move(synopsis)), description_(std::move(description)) {
  flag("help", 'h', "print this help and exit");
  flag("version", 0, "print the program version and exit");
  flag("quiet", 'q', "no progress bar or report on stderr (errors are still printed)");
}

void CommandLine::declare(const std::string& name, char short_name, const std::string& value_name,
                          const std::string& help, const std::string& default_value, OptionKind kind) {
  for (const auto& s : specs_)
    if (s.name == name || (short_name && s.short_name == short_name))
      throw std::logic_error("option --" + name + " declared twice");
  specs_.push_back({name, short_name, value_name, help, default_value, kind, std::nullopt});
}

void CommandLine::real_option(const std::string& name, char short_name, const std::string& value_name,
                              const std::string& help, const std::string& default_value) {
  declare(name, short_name, value_name, help, default_value, OptionKind::real);
}
void CommandLine::integer_option(const std::string& name, char short_name, const std::string& value_name,
                                 const std::string& help, const std::string& default_value) {
  declare(name, short_name, value_name, help, default_value, OptionKind::integer);
}
void CommandLine::text_option(const std::string& name, char short_name, const std::string& value_name,
                              const std::string& help, const std::string& default_value) {
  declare(name, short_name, value_name, help, default_value, OptionKind::text);
}
void CommandLine::flag(const std::string& name, char short_name, const std::string& help) {
  declare(name, short_name, "", help, "", OptionKind::flag);
}

// find() throws std::logic_error for a name never declared.
void CommandLine::conflicts(const std::string& option, const std::string& other) {
  (void)find(option);
  (void)find(other);
  conflicts_.emplace_back(option, other);
}
void CommandLine::needs(const std::string& option, const std::string& other) {
  (void)find(option);
  (void)find(other);
  needs_.emplace_back(option, other);
}

void CommandLine::not_applicable(const std::string& name, const std::string& reason) {
  Spec* s = find_long(name);
  if (!s) throw std::logic_error("option --" + name + " was never declared");
  if (s->value) throw UsageError("option --" + name + " cannot be combined with " + reason);
  s->applies = false;
}

void CommandLine::check_relations() {
  for (const auto& [option, other] : conflicts_) {
    if (!given(other)) continue;
    if (given(option)) throw UsageError("option --" + option + " cannot be combined with --" + other);
    find_long(option)->applies = false;
  }
  for (const auto& [option, other] : needs_) {
    if (given(other)) continue;
    if (given(option)) throw UsageError("option --" + option + " needs --" + other);
    find_long(option)->applies = false;
  }
}

void CommandLine::positionals(const std::string& value_name, const std::string& help, std::size_t min_count) {
  positional_allowed_ = true;
  positional_name_ = value_name;
  positional_help_ = help;
  positional_min_ = min_count;
}

CommandLine::Spec* CommandLine::find_long(const std::string& name) {
  for (auto& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}
CommandLine::Spec* CommandLine::find_short(char c) {
  for (auto& s : specs_)
    if (c && s.short_name == c) return &s;
  return nullptr;
}
const CommandLine::Spec* CommandLine::find(const std::string& name) const {
  for (auto& s : specs_)
    if (s.name == name) return &s;
  throw std::logic_error("option --" + name + " was never declared");
}

bool CommandLine::parse(int argc, const char* const* argv) {
  command_line_.clear();
  for (int i = 0; i < argc; ++i) command_line_ += (i ? " " : "") + shell_quote(argv[i]);
  bool options_done = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (options_done || arg == "-" || arg.empty() || arg[0] != '-') {
      if (!positional_allowed_) throw UsageError("unexpected argument '" + arg + "' (see --help)");
      positional_.push_back(arg);
      continue;
    }
    if (arg == "--") {
      options_done = true;
      continue;
    }
    Spec* spec = nullptr;
    std::optional<std::string> inline_value;
    if (arg.rfind("--", 0) == 0) {
      std::string name = arg.substr(2);
      auto eq = name.find('=');
      if (eq != std::string::npos) {
        inline_value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      spec = find_long(name);
      if (!spec) throw UsageError("unknown option '--" + name + "' (see --help)");
    } else {
      if (arg.size() != 2) throw UsageError("unknown option '" + arg + "' (see --help)");
      spec = find_short(arg[1]);
      if (!spec) throw UsageError("unknown option '" + arg + "' (see --help)");
    }
    ++spec->times_given;
    if (spec->kind == OptionKind::flag) {
      if (inline_value) throw UsageError("option --" + spec->name + " takes no value");
      spec->value = "1";
    } else if (inline_value) {
      spec->value = *inline_value;
    } else {
      if (i + 1 >= argc) throw UsageError("option --" + spec->name + " needs a value <" + spec->value_name + ">");
      spec->value = argv[++i];
    }
  }
  if (flag_set("help")) {
    std::fputs(help().c_str(), stdout);
    return false;
  }
  if (flag_set("version")) {
    std::printf("%s %s\n%s\n", program_.c_str(), version().c_str(), kLicenceLine);
    return false;
  }
  if (positional_.size() < positional_min_) throw UsageError("missing " + positional_name_ + " argument (see --help)");
  check_relations();
  return true;
}

bool CommandLine::has(const std::string& name) const {
  const Spec* s = find(name);
  return s->value.has_value() || !s->default_value.empty();
}
bool CommandLine::given(const std::string& name) const { return find(name)->value.has_value(); }
bool CommandLine::flag_set(const std::string& name) const {
  return find_of_kind(name, OptionKind::flag)->value.has_value();
}
OptionKind CommandLine::kind(const std::string& name) const { return find(name)->kind; }

const CommandLine::Spec* CommandLine::find_of_kind(const std::string& name, OptionKind kind) const {
  static const char* const names[] = {"flag", "real", "integer", "text"};
  const Spec* s = find(name);
  if (s->kind != kind)
    throw std::logic_error("option --" + name + " is declared " + names[int(s->kind)] + ", read as " +
                           names[int(kind)]);
  return s;
}

std::vector<std::string> CommandLine::text_list(const std::string& name) const {
  std::vector<std::string> items;
  if (!has(name)) return items;
  const Spec* s = find(name);
  if (s->times_given > 1)
    throw UsageError("option --" + name + ": given " + std::to_string(s->times_given) +
                     " times; give every file in one comma-separated list (--" + name + " A.h5,B.h5)");
  const std::string list = text(name);
  if (list.empty()) return items;
  for (std::size_t start = 0;;) {
    const std::size_t comma = list.find(',', start);
    items.push_back(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (std::all_of(items.begin(), items.end(), [](const std::string& item) { return item.empty(); })) return {};
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].empty())
      throw UsageError("option --" + name + ": item " + std::to_string(k + 1) + " of '" + list +
                       "' is empty (files are separated by single commas)");
  // A comma inside a file name splits it; say so when the joined items name a file.
  std::error_code ec;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (std::filesystem::exists(items[k], ec)) continue;
    std::string joined = items[k];
    for (std::size_t j = k + 1; j < items.size(); ++j) {
      joined += "," + items[j];
      if (std::filesystem::exists(joined, ec))
        throw UsageError("option --" + name + ": '" + joined +
                         "' contains a comma, which separates the files of the list; give it through a symbolic "
                         "link or a name without one");
    }
  }
  return items;
}

std::string CommandLine::text(const std::string& name) const {
  const Spec* s = find(name);
  if (s->kind == OptionKind::flag) throw std::logic_error("option --" + name + " is a flag, read as text");
  if (s->value) return *s->value;
  if (!s->default_value.empty()) return s->default_value;
  throw UsageError("option --" + name + " is required (see --help)");
}

double CommandLine::real(const std::string& name) const {
  find_of_kind(name, OptionKind::real);
  std::string t = text(name);
  double v = 0;
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v))
    throw UsageError("option --" + name + ": '" + t + "' is not a finite number");
  return v;
}

long long CommandLine::integer(const std::string& name) const {
  find_of_kind(name, OptionKind::integer);
  std::string t = text(name);
  long long v = 0;
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size()) {
    // Accept integral values written as reals (1e4), nothing else.
    double d = 0;
    auto [p2, e2] = std::from_chars(t.data(), t.data() + t.size(), d);
    if (e2 == std::errc() && p2 == t.data() + t.size() && std::isfinite(d) && d == std::floor(d) &&
        std::fabs(d) < 9.0e15)
      return static_cast<long long>(d);
    throw UsageError("option --" + name + ": '" + t + "' is not a whole number");
  }
  return v;
}

std::vector<std::pair<std::string, std::string>> CommandLine::values() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (auto& s : specs_) {
    if (s.name == "help" || s.name == "version" || s.name == "quiet" || !s.applies) continue;
    if (s.kind == OptionKind::flag) out.emplace_back(s.name, s.value ? "1" : "0");
    else if (s.value) out.emplace_back(s.name, *s.value);
    else if (!s.default_value.empty()) out.emplace_back(s.name, s.default_value);
  }
  return out;
}

std::string CommandLine::help() const {
  std::ostringstream o;
  o << wrap("Usage: " + program_ + " " + synopsis_, 0, 7) << "\n" << wrap(description_, 0, 0) << "\n";
  if (positional_allowed_) o << "Arguments:\n  " << positional_name_ << "\n" << wrap(positional_help_, kHelpDescriptionIndent, kHelpDescriptionIndent) << "\n";
  o << "Options:\n";
  for (auto& s : specs_) {
    std::string head(kHelpOptionIndent, ' ');
    head += s.short_name ? std::string("-") + s.short_name + ", " : "    ";
    head += "--" + s.name;
    std::string text = s.help;
    if (s.kind != OptionKind::flag) {
      head += " <" + s.value_name + ">";
      if (!s.default_value.empty()) text += " [default: " + s.default_value + "]";
    }
    o << head << "\n" << wrap(text, kHelpDescriptionIndent, kHelpDescriptionIndent);
  }
  o << "\n" << wrap(kExitStatusLine, 0, 0);
  return o.str();
}

void require_in_range(const std::string& option, double value, double lo, double hi, bool lo_open, bool hi_open) {
  bool ok = (lo_open ? value > lo : value >= lo) && (hi_open ? value < hi : value <= hi);
  if (!ok)
    throw UsageError("option --" + option + ": " + format_real(value) + " is outside " + (lo_open ? "(" : "[") +
                     format_real(lo) + ", " + format_real(hi) + (hi_open ? ")" : "]"));
}

void require_positive(const std::string& option, double value) {
  if (!(value > 0)) throw UsageError("option --" + option + ": must be > 0, got " + format_real(value));
}

}  // namespace granflow
