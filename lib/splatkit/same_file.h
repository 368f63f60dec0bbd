// same_file: whether two paths name the same file, by identity rather than by spelling, so that a
// tool can refuse to overwrite its input or to write its report over its output whatever the
// spelling ("./m.ply", "dir/../m.ply", a symbolic link, a hard link).
//
// Existing files are compared by device and inode (symbolic links followed, as the tools open
// them). A path that does not exist yet is compared by its canonical form: its parent's real path
// plus its name, with dangling symbolic links followed to the file they would create. One existing
// and one missing path are never the same. "-" stands for a standard stream: `a_stream` and
// `b_stream` say which one (0 standard input, 1 standard output), compared by what the stream is
// open on. Only regular files (existing or to be created) count: two names of one device or FIFO
// (/dev/null, a pipe) are not "the same file" here, since writing to them twice destroys nothing.
#pragma once

#include <string>

namespace splatkit {

bool same_file(const std::string& a, const std::string& b, int a_stream = 0, int b_stream = 1);

}  // namespace splatkit
