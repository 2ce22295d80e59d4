#pragma once
// An output written under a temporary name in the same directory and renamed over
// the final path only by commit(), so an interrupted or failed run never leaves a
// file that make would take as finished. The temporary is removed on destruction
// if commit() was never reached.
#include <string>

namespace granflow {

class OutputFile {
 public:
  // Checks up front that the directory exists and is writable (UsageError otherwise).
  // A resumable output uses the fixed temporary name ".NAME.part" (instead of one
  // with the process id) so that a later run can find and continue it.
  explicit OutputFile(std::string final_path, bool resumable = false);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& temp_path() const { return temp_path_; }
  const std::string& final_path() const { return final_path_; }
  void commit();  // atomic rename; RuntimeFailure on error
  // Leave the temporary in place at destruction (an interrupted resumable run).
  void keep_partial() { keep_ = true; }

 private:
  std::string final_path_, temp_path_;
  bool committed_ = false, keep_ = false;
};

}  // namespace granflow
