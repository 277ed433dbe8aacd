#include "io/write_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "mosaic/errors.hpp"

namespace mosaic::io {

void write_file_replacing(const std::filesystem::path& path, std::string_view bytes) {
  const std::string file = path.string();
  // A hidden name with mkstemp's unique suffix. (Built with += because GCC 12 reports a false
  // -Wrestrict on `"." + std::string` at -O3.)
  std::string tmp_name(".");
  tmp_name += path.filename().string();
  tmp_name += ".XXXXXX";
  std::string tmp = (path.parent_path() / tmp_name).string();
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Error(Errc::kIo, file + ": cannot write: " + std::strerror(errno));
  std::size_t done = 0;
  int err = 0;
  while (done < bytes.size() && err == 0) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno != EINTR) err = errno;
    if (n > 0) done += static_cast<std::size_t>(n);
  }
  // mkstemp creates the file 0600; rw-r--r-- is the usual mode of a file a user writes (reading
  // the umask would mean changing it, which races with other threads).
  constexpr mode_t kFileMode = 0644;
  if (err == 0 && ::fchmod(fd, kFileMode) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && std::rename(tmp.c_str(), file.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    throw Error(Errc::kIo, file + ": cannot write: " + std::strerror(err));
  }
}

}  // namespace mosaic::io
