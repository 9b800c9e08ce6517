// The producers' output files (see output_file.h).
#include "robot_model/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace ohrp::model {
namespace {

// write(2) of the whole text, through short writes and EINTR; 0, or the errno that stopped it
int WriteAll(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      return n < 0 ? errno : ENOSPC;  // a write of nothing for a non-empty buffer: no room
    }
  }
  return 0;
}

bool Fail(const std::string& path, int err, std::string* error) {
  *error = "cannot write '" + path + "': " + std::strerror(err);
  return false;
}

// writes the text, syncs (when the file can be synced) and closes; 0 or the first errno
int WriteSyncClose(int fd, const std::string& text) {
  int err = WriteAll(fd, text);
  // special files (pipes, /dev/null) cannot be synced: EINVAL is no failure of the data
  if (err == 0 && ::fdatasync(fd) != 0 && errno != EINVAL && errno != EROFS) err = errno;
  if (::close(fd) != 0 && err == 0 && errno != EINTR) err = errno;
  return err;
}

}  // namespace

bool PrepareOutputFile(const std::string& path, const std::string& provisional,
                       std::string* error) {
  if (path.empty()) {
    *error = "an output path is empty";
    return false;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Fail(path, errno, error);
  if (const int err = WriteSyncClose(fd, provisional); err != 0) return Fail(path, err, error);
  return true;
}

bool WriteWholeFile(const std::string& path, const std::string& text, std::string* error) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Fail(path, errno, error);
  if (const int err = WriteSyncClose(fd, text); err != 0) return Fail(path, err, error);
  return true;
}

bool ParseByteSize(const std::string& text, uint64_t* bytes, std::string* error) {
  auto bad = [&](const char* why) {
    *error = "'" + text + "' " + why +
             " (write a size in bytes, e.g. 500000, or with a suffix: 500k, 20M, 1.5G; kB MB GB "
             "are powers of 1000, KiB MiB GiB of 1024)";
    return false;
  };
  const char* s = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double number = std::strtod(s, &end);
  if (end == s || errno != 0 || !std::isfinite(number)) return bad("is not a size");
  std::string suffix(end);
  double scale = 1;
  if (suffix.empty() || suffix == "B") scale = 1;
  else if (suffix == "k" || suffix == "K" || suffix == "kB" || suffix == "KB") scale = 1e3;
  else if (suffix == "M" || suffix == "MB") scale = 1e6;
  else if (suffix == "G" || suffix == "GB") scale = 1e9;
  else if (suffix == "KiB") scale = 1024.0;
  else if (suffix == "MiB") scale = 1024.0 * 1024;
  else if (suffix == "GiB") scale = 1024.0 * 1024 * 1024;
  else return bad("has an unknown unit");
  const double b = std::floor(number * scale);
  if (b < 1) return bad("is not a positive size");
  if (b > 1e15) return bad("is past 1 PB");
  *bytes = static_cast<uint64_t>(b);
  return true;
}

}  // namespace ohrp::model
