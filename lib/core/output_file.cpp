#include "core/output_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"

namespace granflow {

OutputFile::OutputFile(std::string final_path, bool resumable) : final_path_(std::move(final_path)) {
  namespace fs = std::filesystem;
  if (final_path_.empty()) throw UsageError("output path is empty");
  fs::path p(final_path_);
  fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw UsageError("cannot write '" + final_path_ + "': directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(p, ec)) throw UsageError("cannot write '" + final_path_ + "': it is a directory");
  temp_path_ =
      (dir / ("." + p.filename().string() + (resumable ? std::string(".part") : ".part-" + std::to_string(getpid()))))
          .string();
  // Creating the temporary now is the only reliable writability test (root ignores
  // permission bits; read-only and virtual file systems refuse anyway).
  // No O_TRUNC: a resumable run must not destroy the partial output it will continue.
  int fd = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT, 0644);
  if (fd < 0)
    throw UsageError("cannot write '" + final_path_ + "': directory '" + dir.string() + "' is not writable (" +
                     std::strerror(errno) + ")");
  ::close(fd);
}

OutputFile::~OutputFile() {
  if (!committed_ && !keep_) std::remove(temp_path_.c_str());
}

void OutputFile::commit() {
  if (std::rename(temp_path_.c_str(), final_path_.c_str()) != 0)
    throw RuntimeFailure("cannot rename '" + temp_path_ + "' to '" + final_path_ + "': " + std::strerror(errno));
  committed_ = true;
}

}  // namespace granflow
