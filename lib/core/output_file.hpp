#pragma once
// An output written under a temporary name in the same directory and renamed over
// the final path only by commit(), so an interrupted or failed run never leaves a
// file that make would take as finished. The temporary is removed on destruction
// if commit() was never reached.
//
// Every program names its temporary ".NAME.part-PID" (PID: the process writing it)
// and holds an open-file-description lock (fcntl F_OFD_SETLK) on it for its whole
// life. OFD locks are independent of the flock() HDF5 takes on the files it opens
// and survive HDF5 closing its own descriptors of the file, so the lock says exactly
// whether a live process owns a temporary:
//   - another ".NAME.part-*" that is locked: another process is writing NAME, and this
//     one refuses at once (UsageError), removing only its own temporary;
//   - one that is not locked: its writer died (kill -9, power loss); it is stale and
//     removed (discard_stale), except an interrupted resumable run's partial, which
//     its checkpoint ".NAME.checkpoint" names and a --resume adopts.
#include <string>
#include <vector>

namespace granflow {

class OutputFile {
 public:
  // Checks that the directory exists and is writable, creates and locks the temporary,
  // and refuses (UsageError) when another live process writes the same output. Touches
  // no other file. A resumable output (gf-shear, gf-incline) leaves stale temporaries
  // to the caller, which knows which one its checkpoint names; any other output
  // removes them when it commits.
  explicit OutputFile(std::string final_path, bool resumable = false);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& temp_path() const { return temp_path_; }
  const std::string& final_path() const { return final_path_; }
  void commit();  // atomic rename; RuntimeFailure on error
  // Writes `bytes` as the whole content of the temporary (a text output); WriteFailure
  // naming the output, its temporary, the system's reason and the file system.
  void write_text(const std::string& bytes);
  // Leave the temporary in place at destruction (an interrupted resumable run).
  void keep_partial() { keep_ = true; }

  // Temporaries of NAME left by dead processes, as found when this one started.
  const std::vector<std::string>& stale() const { return stale_; }
  // Removes them (those still unlocked).
  void discard_stale();
  // Makes `partial`, a stale temporary of this output, this process's own: locks it and
  // renames it over temp_path() (the file keeps its inode). UsageError if it is gone or
  // another process has locked it in the meantime.
  void adopt(const std::string& partial);

 private:
  std::string final_path_, temp_path_;
  std::vector<std::string> stale_;
  int lock_fd_ = -1;  // holds the OFD lock on the temporary
  bool resumable_ = false, committed_ = false, keep_ = false;
};

// "<dir>/.<name>.checkpoint" beside an output path.
std::string checkpoint_path(const std::string& output);

// The name of a hidden file beside the output named `name`: "." + name + suffix, for the
// temporaries (suffix ".part-PID") and the checkpoint. A name too long for that within
// NAME_MAX (255 bytes; names of over 235 bytes) is cut to its first 218 bytes (whole UTF-8
// characters) followed by "~" and 16 hex digits of its SHA-256, so that every legal output
// name has its temporaries and checkpoint.
std::string hidden_name(const std::string& name, const std::string& suffix);

// UsageError "'PATH': is a FIFO (named pipe), not a regular file" (or a device, socket,
// directory) for an input that is not a regular file after symbolic links, which opening
// could block on or misread; nothing is opened. A missing path is left to the caller.
void require_regular_file(const std::string& path);

// The one message for a file that is an unfinished run (marked so, or locked by the
// process still writing it).
std::string unfinished_run_message(const std::string& path);

// "the file system holding 'DIR' (mounted at M, N MB free)", for messages about a write
// that failed there.
std::string file_system_of(const std::string& path);

// The temporaries of an output that exist now (named exactly ".NAME.part-PID" or
// ".NAME.part-PID-K", digits), in name order.
std::vector<std::string> output_temporaries(const std::string& final_path);

// This process's own temporary of an output (the locked one named with its pid), or ""
// when it writes none.
std::string own_temporary(const std::string& final_path);

// Whether a live process holds the lock of an output temporary (false once it is gone;
// true if it cannot be opened to tell). On a file system without locks: whether the
// process its name carries is alive.
bool temporary_locked(const std::string& temp_path);

// UsageError ("option --output: ...") when `output` is the same file as any of
// `inputs` (device and inode: "./NAME", other spellings, symlinks and hard links are
// all caught). Empty input paths are ignored; `more` are inputs of another role (e.g.
// references).
void refuse_output_among_inputs(const std::string& output, const std::vector<std::string>& inputs,
                                const std::vector<std::string>& more = {});

}  // namespace granflow
