#pragma once
// A text file that grows while a run goes (trajectory.txt, keyframes.txt, timing.csv): every
// Append hands its whole text to the operating system before it returns (no user-space buffer),
// so a crash, a kill or a stop at any moment leaves the file holding every Append that
// returned. A failed write (full disk, file-size limit with SIGXFSZ ignored) cuts the file back
// to its size before that Append, so the file always ends at the end of a complete Append.

#include <string>
#include <sys/types.h>

namespace esdslam {

class AppendFile {
 public:
  AppendFile() = default;  // closed; Append throws
  // Creates or truncates `path`. Throws Error naming the file and the system's reason.
  explicit AppendFile(const std::string& path);
  ~AppendFile();
  AppendFile(AppendFile&& other) noexcept;
  AppendFile& operator=(AppendFile&& other) noexcept;
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  // Writes `text` at the end. Throws Error "cannot write PATH: REASON" (the file then holds what
  // it held before the call), also when the file is closed.
  void Append(const std::string& text);
  void Close();  // idempotent
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  off_t size() const { return size_; }  // bytes written by the Appends that succeeded

 private:
  std::string path_;
  int fd_ = -1;
  off_t size_ = 0;
};

}  // namespace esdslam
