#include "io/provenance.hpp"

#include <charconv>
#include <cmath>
#include <variant>

#include "core/sha256.hpp"
#include "core/version.hpp"

namespace granflow::io {

Parameters provenance(const CommandLine& cli) {
  Parameters p;
  for (const auto& [name, text] : cli.values()) {
    std::int64_t i = 0;
    double d = 0;
    const char* end = text.data() + text.size();
    if (auto r = std::from_chars(text.data(), end, i); r.ec == std::errc() && r.ptr == end) p.set(name, i);
    else if (auto r2 = std::from_chars(text.data(), end, d); r2.ec == std::errc() && r2.ptr == end) p.set(name, d);
    else p.set(name, text);
  }
  p.set("command_line", cli.command_line());
  p.set("program", cli.program());
  p.set("version", version());
  return p;
}

void add_input(Parameters& parameters, const std::string& path, int index, const std::string& key) {
  const std::string name = index == 0 ? key : key + "_" + std::to_string(index);
  parameters.set(name, path);
  parameters.set(name + "_sha256", sha256_file(path));
}

void add_input_frame(Parameters& parameters, const TrajectoryReader& input, std::size_t index, std::int64_t step,
                     double time) {
  parameters.set("input_frame", std::int64_t(index));
  parameters.set("input_step", step);
  parameters.set("input_time", time);
  const Parameters parent = input.parameters();
  for (const char* name :
       {"program", "angle", "friction", "restitution", "tangential_restitution", "rate", "input", "input_sha256"}) {
    if (!parent.has(name)) continue;
    std::visit([&](const auto& value) { parameters.set(std::string("parent_") + name, value); },
               parent.items().at(name));
  }
}

}  // namespace granflow::io
