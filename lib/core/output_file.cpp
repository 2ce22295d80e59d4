#include "core/output_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"
#include "core/sha256.hpp"

namespace granflow {

namespace fs = std::filesystem;

namespace {

fs::path directory_of(const fs::path& p) { return p.parent_path().empty() ? fs::path(".") : p.parent_path(); }

std::string temp_prefix(const fs::path& final_path) { return hidden_name(final_path.filename().string(), ".part-"); }

bool digits(const std::string& s) {
  return !s.empty() && s.size() < 12 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The pid a temporary's name carries (exactly ".NAME.part-PID" or ".NAME.part-PID-K");
// 0 for any other name.
long pid_of(const std::string& temp_path, const std::string& prefix) {
  const std::string name = fs::path(temp_path).filename().string();
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return 0;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  const std::string pid = rest.substr(0, dash);
  if (!digits(pid) || (dash != std::string::npos && !digits(rest.substr(dash + 1)))) return 0;
  return std::stol(pid);
}

struct flock whole_file(short type) {
  struct flock lock {};
  lock.l_type = type;
  lock.l_whence = SEEK_SET;
  lock.l_start = 0;
  lock.l_len = 0;  // to the end, however long the file grows
  return lock;
}

// Takes the write lock on fd; false if another open file description holds it.
bool lock(int fd) {
  struct flock l = whole_file(F_WRLCK);
  return ::fcntl(fd, F_OFD_SETLK, &l) == 0;
}

}  // namespace

std::string hidden_name(const std::string& name, const std::string& suffix) {
  // ".part-" + a pid of up to 10 digits + "-K" (K < 100), or ".checkpoint.new".
  constexpr std::size_t kNameMax = 255, kLongestSuffix = 19, kKept = kNameMax - 1 - kLongestSuffix - 17;
  if (1 + name.size() + kLongestSuffix <= kNameMax) return "." + name + suffix;
  std::size_t kept = kKept;
  while (kept > 0 && (static_cast<unsigned char>(name[kept]) & 0xC0) == 0x80) --kept;
  return "." + name.substr(0, kept) + "~" + sha256_hex(name).substr(0, 16) + suffix;
}

std::string checkpoint_path(const std::string& output) {
  fs::path p(output);
  return (p.parent_path() / hidden_name(p.filename().string(), ".checkpoint")).string();
}

void require_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  const char* kind = S_ISFIFO(st.st_mode)                         ? "a FIFO (named pipe)"
                     : S_ISDIR(st.st_mode)                        ? "a directory"
                     : S_ISSOCK(st.st_mode)                       ? "a socket"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                  : "not a file";
  throw UsageError("'" + path + "': is " + kind + ", not a regular file");
}

std::string unfinished_run_message(const std::string& path) {
  return "'" + path +
         "': is an unfinished run (interrupted, or still being written): continue it with --resume of the same "
         "command, or run that command without --resume to start over";
}

std::string file_system_of(const std::string& path) {
  std::error_code ec;
  fs::path dir = fs::absolute(directory_of(fs::path(path)), ec).lexically_normal();
  struct stat st {};
  if (ec || ::stat(dir.c_str(), &st) != 0) return "the file system holding '" + path + "'";
  // The mount point: the highest ancestor on the same device.
  fs::path mount = dir;
  for (fs::path up = dir.parent_path(); !up.empty(); up = up.parent_path()) {
    struct stat above {};
    if (::stat(up.c_str(), &above) != 0 || above.st_dev != st.st_dev) break;
    mount = up;
    if (up == up.root_path()) break;
  }
  std::string text =
      "the file system holding '" + directory_of(fs::path(path)).string() + "' (mounted at " + mount.string();
  struct statvfs vfs {};
  if (::statvfs(dir.c_str(), &vfs) == 0) {
    char free_text[64];
    std::snprintf(free_text, sizeof free_text, ", %.1f MB free", double(vfs.f_bavail) * double(vfs.f_frsize) / 1e6);
    text += free_text;
  }
  return text + ")";
}

std::vector<std::string> output_temporaries(const std::string& final_path) {
  const fs::path p(final_path);
  const std::string prefix = temp_prefix(p);
  std::vector<std::string> found;
  std::error_code ec;
  for (fs::directory_iterator it(directory_of(p), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (pid_of(name, prefix) > 0) found.push_back((directory_of(p) / name).string());
  }
  std::sort(found.begin(), found.end());
  return found;
}

bool temporary_locked(const std::string& temp_path) {
  const int fd = ::open(temp_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno != ENOENT;  // unreadable: not ours to judge, leave it alone
  struct flock l = whole_file(F_WRLCK);
  const int got = ::fcntl(fd, F_OFD_GETLK, &l);
  ::close(fd);  // a descriptor of its own: closing it releases no lock
  if (got == 0) return l.l_type != F_UNLCK;
  // A file system without locks (some network ones): whether the process the name
  // carries is alive on this host.
  const std::string name = fs::path(temp_path).filename().string();
  const std::size_t at = name.rfind(".part-");
  const long pid = at == std::string::npos ? 0 : std::atol(name.c_str() + at + 6);
  return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

std::string own_temporary(const std::string& final_path) {
  const std::string prefix = temp_prefix(fs::path(final_path));
  for (const std::string& t : output_temporaries(final_path))
    if (pid_of(t, prefix) == long(::getpid()) && temporary_locked(t)) return t;
  return "";
}

OutputFile::OutputFile(std::string final_path, bool resumable)
    : final_path_(std::move(final_path)), resumable_(resumable) {
  if (final_path_.empty()) throw UsageError("option --output: the file name is empty");
  const fs::path p(final_path_);
  const fs::path dir = directory_of(p);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw UsageError("cannot write '" + final_path_ + "': directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(p, ec)) throw UsageError("cannot write '" + final_path_ + "': it is a directory");

  // Creating the temporary is the only reliable writability test (root ignores
  // permission bits; read-only and virtual file systems refuse anyway). O_EXCL: a file
  // of this name is a dead process's of the same pid (pids are reused), which may be an
  // interrupted run's partial output; a further "-K" keeps it.
  const std::string prefix = temp_prefix(p);
  const std::string base = (dir / (prefix + std::to_string(::getpid()))).string();
  for (int k = 1; lock_fd_ < 0; ++k) {
    temp_path_ = k == 1 ? base : base + "-" + std::to_string(k);
    lock_fd_ = ::open(temp_path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (lock_fd_ >= 0) break;
    if (errno == EEXIST && k < 100) continue;
    const int error = errno;
    if (error == ENOSPC || error == EDQUOT || error == EIO)
      throw WriteFailure("cannot create '" + temp_path_ + "' (" + std::strerror(error) + ") on " +
                         file_system_of(final_path_));
    if (error == EACCES || error == EPERM || error == EROFS)
      throw UsageError("cannot write '" + final_path_ + "': directory '" + dir.string() + "' is not writable (" +
                       std::strerror(error) + ")");
    throw UsageError("cannot write '" + final_path_ + "': cannot create '" + temp_path_ + "' in directory '" +
                     dir.string() + "' (" + std::strerror(error) + ")");
  }
  // Without lock support (ENOLCK, EINVAL...) the temporary stays unlocked, and others
  // judge it by its pid (temporary_locked).
  if (!lock(lock_fd_) && (errno == EAGAIN || errno == EACCES)) {
    const int error = errno;
    ::unlink(temp_path_.c_str());
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw UsageError("cannot write '" + final_path_ + "': cannot lock its temporary '" + temp_path_ + "' (" +
                     std::strerror(error) + ")");
  }

  // Only now look for other writers: of two processes starting together, the later one
  // to create its temporary sees the earlier one's, locked.
  for (const std::string& other : output_temporaries(final_path_)) {
    if (other == temp_path_) continue;
    if (temporary_locked(other)) {
      ::unlink(temp_path_.c_str());
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw UsageError("another process (pid " + std::to_string(pid_of(other, prefix)) + ") is writing '" +
                       final_path_ + "' (its temporary '" + other + "' is locked)");
    }
    stale_.push_back(other);
  }
}

OutputFile::~OutputFile() {
  // Removed while still locked, so no other process ever sees it unlocked.
  if (!committed_ && !keep_ && !temp_path_.empty()) ::unlink(temp_path_.c_str());
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void OutputFile::discard_stale() {
  for (const std::string& s : stale_)
    if (!temporary_locked(s)) ::unlink(s.c_str());
  stale_.clear();
}

void OutputFile::adopt(const std::string& partial) {
  const int fd = ::open(partial.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0)
    throw UsageError("cannot continue '" + final_path_ + "': its partial output '" + partial + "' is missing (" +
                     std::strerror(errno) + ")");
  if (!lock(fd)) {
    ::close(fd);
    throw UsageError("another process is writing '" + final_path_ + "' (it holds '" + partial + "')");
  }
  if (std::rename(partial.c_str(), temp_path_.c_str()) != 0) {
    const int error = errno;
    ::close(fd);
    throw RuntimeFailure("cannot rename '" + partial + "' to '" + temp_path_ + "': " + std::strerror(error));
  }
  // The empty temporary just replaced is gone; hold the lock of the adopted file.
  ::close(lock_fd_);
  lock_fd_ = fd;
  stale_.erase(std::remove(stale_.begin(), stale_.end(), partial), stale_.end());
}

void OutputFile::write_text(const std::string& bytes) {
  const int fd = ::open(temp_path_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  int error = fd < 0 ? errno : 0;
  for (std::size_t done = 0; error == 0 && done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) error = errno;
    else done += std::size_t(n);
  }
  if (fd >= 0 && ::close(fd) != 0 && error == 0) error = errno;
  if (error != 0)
    throw WriteFailure("cannot write '" + final_path_ + "' (its temporary '" + temp_path_ +
                       "'): " + std::strerror(error) + " on " + file_system_of(final_path_));
}

void OutputFile::commit() {
  if (std::rename(temp_path_.c_str(), final_path_.c_str()) != 0)
    throw RuntimeFailure("cannot rename '" + temp_path_ + "' to '" + final_path_ + "': " + std::strerror(errno));
  committed_ = true;
  ::close(lock_fd_);  // the lock guards the temporary name only
  lock_fd_ = -1;
  // A checkpoint beside the output that is not this run's own names an interrupted
  // run's partial among the stale ones: keep them all for its --resume.
  if (resumable_ || !fs::exists(checkpoint_path(final_path_))) discard_stale();
}

void refuse_output_among_inputs(const std::string& output, const std::vector<std::string>& inputs,
                                const std::vector<std::string>& more) {
  std::error_code ec;
  if (output.empty() || !fs::exists(output, ec)) return;
  std::vector<std::string> all = inputs;
  all.insert(all.end(), more.begin(), more.end());
  for (const std::string& input : all) {
    if (input.empty()) continue;
    std::error_code same_ec;
    if (fs::equivalent(input, output, same_ec))
      throw UsageError("option --output: '" + output + "' is the same file as the input '" + input + "'");
  }
}

}  // namespace granflow
