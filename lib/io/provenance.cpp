#include "io/provenance.hpp"

#include <variant>

#include "core/sha256.hpp"
#include "core/version.hpp"

namespace granflow::io {

Parameters provenance(const CommandLine& cli) {
  Parameters p;
  for (const auto& [name, text] : cli.values()) {
    switch (cli.kind(name)) {
      case OptionKind::flag: p.set(name, std::int64_t(text == "1")); break;
      case OptionKind::integer: p.set(name, std::int64_t(cli.integer(name))); break;
      case OptionKind::real: p.set(name, cli.real(name)); break;
      case OptionKind::text: p.set(name, text); break;
    }
  }
  p.set("command_line", cli.command_line());
  p.set("program", cli.program());
  p.set("version", version());
  return p;
}

void add_input(Parameters& parameters, const std::string& path, int index, const std::string& key) {
  add_hashed_input(parameters, path, sha256_file(path), index, key);
}

void add_hashed_input(Parameters& parameters, const std::string& path, const std::string& sha256, int index,
                      const std::string& key) {
  const std::string name = index == 0 ? key : key + "_" + std::to_string(index);
  parameters.set(name, path);
  parameters.set(name + "_sha256", sha256);
}

void add_input_frame(Parameters& parameters, const TrajectoryReader& input, std::size_t index, std::int64_t step,
                     double time) {
  parameters.set("input_frame", std::int64_t(index));
  parameters.set("input_step", step);
  parameters.set("input_time", time);
  const Parameters parent = input.parameters();
  // The parent's attribute names, options under their command-line names.
  for (const char* name :
       {"program", "angle", "friction", "restitution", "tangential-restitution", "rate", "input", "input_sha256"}) {
    if (!parent.has(name)) continue;
    std::visit([&](const auto& value) { parameters.set(std::string("parent_") + name, value); },
               parent.items().at(name));
  }
}

}  // namespace granflow::io
