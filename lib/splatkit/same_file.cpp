#include "splatkit/same_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <system_error>

namespace splatkit {

namespace {

namespace fs = std::filesystem;

// Where a missing path would be created: dangling symbolic links followed (at most 40, as the
// kernel does), then the parent's real path plus the name.
fs::path would_create(fs::path p) {
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) break;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  return fs::weakly_canonical(fs::absolute(p, ec), ec);
}

struct Identity {
  bool exists = false;
  bool regular = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path missing;  // canonical form of a path that does not exist yet
};

Identity identity(const std::string& path, int stream) {
  Identity id;
  struct stat st {};
  const int rc = path == "-" ? ::fstat(stream, &st) : ::stat(path.c_str(), &st);
  if (rc == 0) {
    id.exists = true;
    id.regular = S_ISREG(st.st_mode);
    id.device = st.st_dev;
    id.inode = st.st_ino;
  } else if (path != "-") {
    id.regular = true;  // a new file is a regular one
    id.missing = would_create(path);
  }
  return id;
}

}  // namespace

bool same_file(const std::string& a, const std::string& b, int a_stream, int b_stream) {
  const Identity x = identity(a, a_stream), y = identity(b, b_stream);
  if (!x.regular || !y.regular || x.exists != y.exists) return false;
  if (x.exists) return x.device == y.device && x.inode == y.inode;
  return !x.missing.empty() && x.missing == y.missing;
}

}  // namespace splatkit
