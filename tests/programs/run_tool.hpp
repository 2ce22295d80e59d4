#pragma once
// Runs a gf-* program as a user would and captures its exit code and stderr.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace granflow::testing {

struct ToolResult {
  int exit_code;
  std::string err;
};

inline std::string tool_path(const std::string& name) { return std::string(GRANFLOW_BIN_DIR) + "/" + name; }

// args are passed through the shell verbatim: quote them in the call. `prefix` goes before
// the program (environment assignments, a `timeout`).
inline ToolResult run_tool(const std::string& name, const std::string& args, const std::string& prefix = "") {
  namespace fs = std::filesystem;
  fs::path err_file = fs::temp_directory_path() / ("granflow_stderr_" + std::to_string(::getpid()));
  std::string cmd = prefix + (prefix.empty() ? "" : " ") + tool_path(name) + " " + args + " </dev/null >/dev/null 2>" +
                    err_file.string();
  int status = std::system(cmd.c_str());
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  fs::remove(err_file);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += (c == '\n');
  return n;
}

// A fresh scratch directory per test, removed at the end.
struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("granflow_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() { std::filesystem::remove_all(path); }
  std::string operator/(const std::string& f) const { return (path / f).string(); }
  // Number of entries left in the directory (no partial outputs allowed).
  int entries() const {
    int n = 0;
    for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(path)) ++n;
    return n;
  }
};

}  // namespace granflow::testing

namespace granflow::testing {

// Starts a program in the background (its own process, stdout/stderr to files in dir);
// returns its pid, for tests that signal it.
inline pid_t start_tool(const std::string& name, const std::string& args, const std::string& log) {
  pid_t pid = ::fork();
  if (pid == 0) {
    std::string cmd = "exec " + tool_path(name) + " " + args + " </dev/null >/dev/null 2>" + log;
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

inline int wait_exit_code(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The temporaries ".NAME.part-PID" of an output (".NAME.part" too) that exist now.
inline std::vector<std::filesystem::path> partials_of(const std::filesystem::path& output) {
  std::vector<std::filesystem::path> found;
  const std::string prefix = "." + output.filename().string() + ".part";
  std::error_code ec;
  for (std::filesystem::directory_iterator it(output.parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) == 0 && (name.size() == prefix.size() || name[prefix.size()] == '-'))
      found.push_back(it->path());
  }
  return found;
}

// ".NAME.checkpoint" beside an output.
inline std::filesystem::path checkpoint_of(const std::filesystem::path& output) {
  return output.parent_path() / ("." + output.filename().string() + ".checkpoint");
}

// Waits (up to 5 s) until the output's temporary appears, or the process `pid` ends;
// whether it appeared.
inline bool wait_for_partial(const std::filesystem::path& output, pid_t pid = 0) {
  for (int k = 0; k < 500; ++k) {
    if (!partials_of(output).empty()) return true;
    if (pid > 0 && ::waitpid(pid, nullptr, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// Starts a program writing `output`, sends it `signal` `settle_ms` after its temporary
// .NAME.part-PID appears, and returns its exit code (0: it finished before the signal).
inline int interrupted_run(const std::string& name, const std::string& args, const std::filesystem::path& output,
                           const std::string& log, int settle_ms, int signal = SIGINT) {
  const pid_t pid = start_tool(name, args, log);
  for (int k = 0; k < 200 && partials_of(output).empty(); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(settle_ms));
  ::kill(pid, signal);
  return wait_exit_code(pid);
}

}  // namespace granflow::testing

namespace granflow::testing {

// A bad-input case: every program must refuse it with exit code 2, one line naming the
// problem, and no output, partial file or checkpoint left behind.
struct BadInput {
  const char* name;
  const char* args;      // with {key} placeholders, {out} = the output path
  const char* expected;  // a piece of the one-line message
};
// Test names and failure messages show the case name, not its bytes.
inline void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }
inline std::string bad_input_name(const ::testing::TestParamInfo<BadInput>& info) { return info.param.name; }

// What a refusal must leave as it found it: every regular file under `paths` (files, or
// directories walked recursively) by name, size and content.
using FileSnapshot = std::map<std::string, std::pair<std::uintmax_t, std::size_t>>;
inline FileSnapshot snapshot(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  FileSnapshot files;
  auto add = [&](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    files[p.string()] = {ss.str().size(), std::hash<std::string>{}(ss.str())};
  };
  for (const std::string& path : paths) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) {
      add(path);
    } else if (fs::is_directory(path, ec)) {
      files[path + "/"] = {0, 0};  // the directory itself, so an emptied one differs from none
      for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
        if (it->is_regular_file(ec)) add(it->path());
        else files[it->path().string()] = {0, 1};  // a directory, link or other entry
    }
  }
  return files;
}

// Runs `tool` with c.args, each {key} replaced by its value and {out} by a path in a fresh
// scratch directory, plus `extra` arguments; checks the refusal, and that the scratch
// directory and every file among the values (the inputs) are unchanged byte for byte.
inline void expect_refused(const std::string& tool, const BadInput& c,
                           const std::vector<std::pair<std::string, std::string>>& values,
                           const std::string& extra = "") {
  ScratchDir dir(tool + "_bad_" + c.name);
  std::string args = c.args;
  std::vector<std::pair<std::string, std::string>> all = values;
  all.emplace_back("{out}", dir / "out.h5");
  for (const auto& [key, value] : all)
    for (auto at = args.find(key); at != std::string::npos; at = args.find(key, at + value.size()))
      args.replace(at, key.size(), value);
  std::vector<std::string> watched{dir.path.string()};
  for (const auto& [key, value] : values)
    if (std::filesystem::is_regular_file(value)) watched.push_back(value);
  const FileSnapshot before = snapshot(watched);
  auto r = run_tool(tool, args + extra);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  EXPECT_EQ(dir.entries(), 0) << "output, partial file or checkpoint left behind";
  EXPECT_TRUE(snapshot(watched) == before) << "the refusal changed the directory or an input";
}

}  // namespace granflow::testing

namespace granflow::testing {

// The output of `gf-pack ARGS`, made once per test program under `name` and shared by its
// tests (removed at exit).
inline const std::string& packed_once(const std::string& name, const std::string& args) {
  static std::map<std::string, std::pair<std::unique_ptr<ScratchDir>, std::string>> made;
  auto it = made.find(name);
  if (it == made.end()) {
    auto dir = std::make_unique<ScratchDir>(name);
    const std::string path = *dir / "pack.h5";
    EXPECT_EQ(run_tool("gf-pack", args + " --quiet -o " + path).exit_code, 0);
    it = made.emplace(name, std::make_pair(std::move(dir), path)).first;
  }
  return it->second.second;
}

}  // namespace granflow::testing
